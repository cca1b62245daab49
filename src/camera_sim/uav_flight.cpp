#include "vdtnav/camera_sim/uav_flight.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "vdtnav/camera_sim/ground_renderer.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav::uav_camera {
namespace {

constexpr double kGravity = 9.80665;  // m/s^2

// A closed polyline parameterised by arc length.
class ClosedPath {
 public:
  explicit ClosedPath(std::vector<Eigen::Vector2d> points) : points_(std::move(points)) {
    cumulative_.reserve(points_.size() + 1);
    cumulative_.push_back(0.0);
    for (std::size_t k = 0; k < points_.size(); ++k) {
      const Eigen::Vector2d& next = points_[(k + 1) % points_.size()];
      cumulative_.push_back(cumulative_.back() + (next - points_[k]).norm());
    }
  }
  [[nodiscard]] double length() const { return cumulative_.back(); }
  [[nodiscard]] double arc_length(std::size_t k) const { return cumulative_[k]; }

  [[nodiscard]] Eigen::Vector2d point(double s) const {
    s -= length() * std::floor(s / length());
    const auto it = std::upper_bound(cumulative_.begin(), cumulative_.end(), s);
    const std::size_t k = std::min<std::size_t>(
        static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - cumulative_.begin() - 1, 0)),
        points_.size() - 1);
    const double span = cumulative_[k + 1] - cumulative_[k];
    const double f = span > 0.0 ? (s - cumulative_[k]) / span : 0.0;
    return points_[k] + f * (points_[(k + 1) % points_.size()] - points_[k]);
  }

 private:
  std::vector<Eigen::Vector2d> points_;
  std::vector<double> cumulative_;
};

void validate(const UavFlightOptions& o) {
  const auto finite_nonneg = [](double v) { return std::isfinite(v) && v >= 0.0; };
  VDTNAV_CHECK(o.frames >= 1, "uav flight: frames must be >= 1");
  VDTNAV_CHECK(std::isfinite(o.frame_rate) && o.frame_rate > 0.0,
               "uav flight: frame_rate must be > 0 (Hz)");
  VDTNAV_CHECK(std::isfinite(o.speed) && o.speed > 0.0, "uav flight: speed must be > 0 (m/s)");
  VDTNAV_CHECK(std::isfinite(o.altitude_min) && o.altitude_min > 0.0 &&
                   std::isfinite(o.altitude_max) && o.altitude_max >= o.altitude_min,
               "uav flight: need 0 < altitude_min <= altitude_max (m)");
  VDTNAV_CHECK(std::isfinite(o.altitude_period) && o.altitude_period > 0.0,
               "uav flight: altitude_period must be > 0 (s)");
  VDTNAV_CHECK(finite_nonneg(o.max_tilt) && o.max_tilt < 0.25 * kPi,
               "uav flight: max_tilt must be in [0, pi/4) (rad)");
  VDTNAV_CHECK(finite_nonneg(o.sigma_roll) && finite_nonneg(o.sigma_pitch) &&
                   finite_nonneg(o.sigma_laser_range),
               "uav flight: sigma_roll, sigma_pitch, sigma_laser_range must be >= 0");
  VDTNAV_CHECK(finite_nonneg(o.odometry_sigma_xy_per_m) &&
                   finite_nonneg(o.odometry_sigma_yaw_per_rad) &&
                   finite_nonneg(o.odometry_sigma_yaw_per_s),
               "uav flight: odometry sigmas must be >= 0");
  VDTNAV_CHECK(finite_nonneg(o.off_runway_offset) && std::isfinite(o.off_runway_length) &&
                   o.off_runway_length > 0.0,
               "uav flight: off_runway_offset must be >= 0 and off_runway_length > 0 (m)");
}

}  // namespace

std::vector<UavFlightSample> simulate_uav_flight(const RunwayScene& scene, const UavRig& rig,
                                                 const UavFlightOptions& options) {
  validate(options);
  const std::vector<Eigen::Vector2d>& centre = scene.centreline;
  VDTNAV_CHECK(centre.size() >= 8, "uav flight: the scene's centreline has fewer than 8 points");
  const std::size_t n = centre.size();
  const ClosedPath road(centre);

  // Flight path: the road, pushed sideways by raised-cosine detours over the grass beside the
  // outer sides of the two loops (the road's highest point right of the crossing and its lowest
  // point left of it), each `off_runway_length` of road long.
  std::vector<Eigen::Vector2d> path = centre;
  if (options.off_runway_stretches && options.off_runway_offset > 0.0) {
    std::size_t top = 0, bottom = 0;
    double best_top = -std::numeric_limits<double>::infinity();
    double best_bottom = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < n; ++k) {
      if (centre[k].x() > 0.0 && centre[k].y() > best_top) best_top = centre[k].y(), top = k;
      if (centre[k].x() < 0.0 && centre[k].y() < best_bottom) {
        best_bottom = centre[k].y(), bottom = k;
      }
    }
    const double half = 0.5 * std::min(options.off_runway_length, 0.45 * road.length());
    const auto left_normal = [&](std::size_t k) {
      const Eigen::Vector2d tangent = (centre[(k + 1) % n] - centre[(k + n - 1) % n]).normalized();
      return Eigen::Vector2d(-tangent.y(), tangent.x());
    };
    for (const std::size_t b : {top, bottom}) {
      // The side (left or right of travel) that points off the runway at the apex, kept along
      // the whole detour: the offset stays on the convex side of the loop, so no cusps.
      const Eigen::Vector2d away(0.0, centre[b].y() >= 0.0 ? 1.0 : -1.0);
      const double side = left_normal(b).dot(away) >= 0.0 ? 1.0 : -1.0;
      for (std::size_t k = 0; k < n; ++k) {
        double ds = road.arc_length(k) - road.arc_length(b);
        ds -= road.length() * std::round(ds / road.length());  // circular distance
        if (std::abs(ds) >= half) continue;
        const double bump = 0.5 * (1.0 + std::cos(kPi * ds / half));  // 1 at the apex, C1 ends
        path[k] += options.off_runway_offset * bump * side * left_normal(k);
      }
    }
  }
  const ClosedPath flight(path);

  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> phase(-kPi, kPi);
  const double altitude_phase = phase(rng);
  // Gusts: slow sums of sines on roll and pitch (periods in s, incommensurate).
  const double gust_roll[2] = {phase(rng), phase(rng)};
  const double gust_pitch[2] = {phase(rng), phase(rng)};
  const double gust = 0.35 * options.max_tilt;
  std::normal_distribution<double> normal(0.0, 1.0);

  const double dt = 1.0 / options.frame_rate;
  const double v = options.speed;
  const double mid = 0.5 * (options.altitude_min + options.altitude_max);
  const double amplitude = 0.5 * (options.altitude_max - options.altitude_min);
  const Eigen::Vector3d camera_axis_body = rig.body_from_camera.linear().col(2);
  const Eigen::Vector3d camera_centre_body = rig.body_from_camera.translation();

  std::vector<UavFlightSample> samples;
  samples.reserve(options.frames);
  for (std::size_t i = 0; i < options.frames; ++i) {
    UavFlightSample sample;
    const double t = static_cast<double>(i) * dt;
    sample.time = t;
    const double s = v * t;
    const Eigen::Vector2d p = flight.point(s);
    // Yaw along the direction of travel, smoothed over +-0.3 s of path.
    const Eigen::Vector2d ahead = flight.point(s + 0.3 * v) - flight.point(s - 0.3 * v);
    const double yaw = std::atan2(ahead.y(), ahead.x());
    // Acceleration by a second difference over +-1 s: a triangular low-pass over 2 s, like the
    // lag of a position controller that anticipates its path, in the level frame.
    constexpr double h = 1.0;
    const Eigen::Vector2d accel =
        (flight.point(s + v * h) - 2.0 * p + flight.point(s - v * h)) / (h * h);
    const double a_forward = accel.x() * std::cos(yaw) + accel.y() * std::sin(yaw);
    const double a_left = -accel.x() * std::sin(yaw) + accel.y() * std::cos(yaw);
    // A multirotor tilts its thrust toward its acceleration: nose down (positive pitch about
    // body y) to speed up, left side down (negative roll) to accelerate left.
    double roll =
        -std::atan(a_left / kGravity) + gust * (0.6 * std::sin(2 * kPi * t / 7.3 + gust_roll[0]) +
                                                0.4 * std::sin(2 * kPi * t / 2.9 + gust_roll[1]));
    double pitch = std::atan(a_forward / kGravity) +
                   gust * (0.6 * std::sin(2 * kPi * t / 6.1 + gust_pitch[0]) +
                           0.4 * std::sin(2 * kPi * t / 3.7 + gust_pitch[1]));
    // Soft limit: smooth, monotonic, and strictly within +-max_tilt.
    if (options.max_tilt > 0.0) {
      roll = options.max_tilt * std::tanh(roll / options.max_tilt);
      pitch = options.max_tilt * std::tanh(pitch / options.max_tilt);
    } else {
      roll = pitch = 0.0;
    }
    const double altitude =
        mid + amplitude * std::sin(2 * kPi * t / options.altitude_period + altitude_phase);

    sample.world_from_body = body_pose(p.x(), p.y(), altitude, roll, pitch, yaw);
    sample.pose = Pose2(p.x(), p.y(), wrap_angle(yaw));

    // IMU and laser: the laser ray from T_wb o_l along R_wb d_l meets z = 0 at range -o_z / d_z.
    const Eigen::Matrix3d& r_wb = sample.world_from_body.linear();
    const Eigen::Vector3d laser_origin = sample.world_from_body * rig.laser_origin;
    const Eigen::Vector3d laser_dir = r_wb * rig.laser_direction.normalized();
    const double true_range = laser_dir.z() < -1e-9 ? -laser_origin.z() / laser_dir.z()
                                                    : std::numeric_limits<double>::infinity();
    sample.reading.roll = roll + options.sigma_roll * normal(rng);
    sample.reading.pitch = pitch + options.sigma_pitch * normal(rng);
    sample.reading.laser_range = true_range + options.sigma_laser_range * normal(rng);

    // Footprint centre: the optical axis from the camera centre meets the ground.
    const Eigen::Vector3d cam = sample.world_from_body * camera_centre_body;
    const Eigen::Vector3d axis = r_wb * camera_axis_body;
    if (axis.z() < -1e-9 && cam.z() > 0.0) {
      const Eigen::Vector3d ground = cam - cam.z() / axis.z() * axis;
      sample.over_runway = scene.runway.contains(ground.head<2>());
    }

    // Odometry: the true increment in the previous level frame, with VIO-like noise.
    if (i > 0) {
      const Pose2 truth = between(samples.back().pose, sample.pose);
      const double sigma_xy = options.odometry_sigma_xy_per_m * truth.head<2>().norm();
      const double sigma_yaw = options.odometry_sigma_yaw_per_rad * std::abs(truth[2]) +
                               options.odometry_sigma_yaw_per_s * dt;
      Pose2 delta = truth;
      delta[0] += sigma_xy * normal(rng);
      delta[1] += sigma_xy * normal(rng);
      delta[2] = wrap_angle(delta[2] + sigma_yaw * normal(rng));
      sample.odometry.dt = dt;
      sample.odometry.delta = delta;
      sample.odometry.v = std::copysign(delta.head<2>().norm(), delta[0]) / dt;
      sample.odometry.w = delta[2] / dt;
    }
    samples.push_back(sample);
  }
  return samples;
}

}  // namespace vdtnav::uav_camera
