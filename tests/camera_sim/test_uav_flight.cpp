// Tests of the simulated UAV flight: bounds of the motion, the frames of the odometry
// increments, the noise of every simulated sensor, and the stretches over the grass.

#include "vdtnav/camera_sim/uav_flight.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "vdtnav/core/error.hpp"

namespace vdtnav::uav_camera {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

const RunwayScene& scene() {
  static const RunwayScene s = [] {
    RunwaySceneOptions o;
    o.resolution = 0.1;  // the flight needs only the geometry
    o.grass_margin = 1.0;
    return make_runway_scene(o);
  }();
  return s;
}

// ZYX Euler angles (roll, pitch, yaw) of R = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Vector3d euler(const Eigen::Matrix3d& r) {
  return {std::atan2(r(2, 1), r(2, 2)), -std::asin(r(2, 0)), std::atan2(r(1, 0), r(0, 0))};
}

double sample_std(const std::vector<double>& x) {
  double m = 0.0;
  for (const double v : x) m += v;
  m /= x.size();
  double s = 0.0;
  for (const double v : x) s += (v - m) * (v - m);
  return std::sqrt(s / (x.size() - 1));
}

TEST(UavFlight, StaysWithinTheAltitudeAndTiltBoundsAtTheConfiguredSpeed) {
  const UavFlightOptions o;
  const auto flight = simulate_uav_flight(scene(), UavRig{}, o);
  ASSERT_EQ(flight.size(), o.frames);
  double max_roll = 0.0, max_pitch = 0.0, z_lo = 1e9, z_hi = -1e9;
  for (std::size_t i = 0; i < flight.size(); ++i) {
    const auto& s = flight[i];
    EXPECT_NEAR(s.time, i / o.frame_rate, 1e-9);
    const double z = s.world_from_body.translation().z();
    z_lo = std::min(z_lo, z);
    z_hi = std::max(z_hi, z);
    const Eigen::Vector3d rpy = euler(s.world_from_body.linear());
    EXPECT_LE(std::abs(rpy[0]), o.max_tilt + 1e-12);
    EXPECT_LE(std::abs(rpy[1]), o.max_tilt + 1e-12);
    max_roll = std::max(max_roll, std::abs(rpy[0]));
    max_pitch = std::max(max_pitch, std::abs(rpy[1]));
    // The 3-DOF truth is the body's position and yaw.
    EXPECT_NEAR(s.pose.x(), s.world_from_body.translation().x(), 1e-12);
    EXPECT_NEAR(s.pose.y(), s.world_from_body.translation().y(), 1e-12);
    EXPECT_NEAR(wrap_angle(s.pose[2] - rpy[2]), 0.0, 1e-9);
    if (i > 0) {
      const Eigen::Vector2d step = s.pose.head<2>() - flight[i - 1].pose.head<2>();
      EXPECT_NEAR(step.norm(), o.speed / o.frame_rate, 0.02 * o.speed / o.frame_rate);
      // Yaw along the direction of travel (smoothed, so a few degrees off in turns).
      const double travel = std::atan2(step.y(), step.x());
      EXPECT_LT(std::abs(wrap_angle(travel - s.pose[2])), 6.0 * kDeg);
      // Smooth attitude: no jumps between frames.
      const Eigen::Vector3d prev = euler(flight[i - 1].world_from_body.linear());
      EXPECT_LT(std::abs(rpy[0] - prev[0]), 1.0 * kDeg);
      EXPECT_LT(std::abs(rpy[1] - prev[1]), 1.0 * kDeg);
    }
  }
  EXPECT_GE(z_lo, o.altitude_min);
  EXPECT_LE(z_hi, o.altitude_max);
  EXPECT_LT(z_lo, o.altitude_min + 0.5);  // the altitude really spans its range
  EXPECT_GT(z_hi, o.altitude_max - 0.5);
  EXPECT_GT(max_roll, 0.5 * o.max_tilt);  // the turns tilt the multirotor
  EXPECT_GT(max_pitch, 0.2 * o.max_tilt);
}

TEST(UavFlight, NoiseFreeIncrementsComposeIntoTheTrajectory) {
  UavFlightOptions o;
  o.odometry_sigma_xy_per_m = 0.0;
  o.odometry_sigma_yaw_per_rad = 0.0;
  o.odometry_sigma_yaw_per_s = 0.0;
  const auto flight = simulate_uav_flight(scene(), UavRig{}, o);
  EXPECT_EQ(flight[0].odometry.dt, 0.0);
  EXPECT_EQ(flight[0].odometry.delta, Pose2::Zero());
  Pose2 dead_reckoning = flight[0].pose;
  for (std::size_t i = 1; i < flight.size(); ++i) {
    const OdometryStep& odo = flight[i].odometry;
    EXPECT_NEAR(odo.dt, 1.0 / o.frame_rate, 1e-12);
    // Increments are in the previous level frame: mostly forward, never backward.
    EXPECT_GT(odo.delta.x(), 0.0);
    EXPECT_NEAR(odo.v, odo.delta.head<2>().norm() / odo.dt, 1e-9);
    EXPECT_NEAR(odo.w, odo.delta[2] / odo.dt, 1e-9);
    dead_reckoning = compose(dead_reckoning, odo.delta);
    ASSERT_LT(pose_error(dead_reckoning, flight[i].pose).norm(), 1e-9) << "at frame " << i;
  }
}

TEST(UavFlight, SensorNoiseHasTheConfiguredSigmas) {
  UavFlightOptions o;
  o.frames = 3000;
  const UavRig rig;
  const auto flight = simulate_uav_flight(scene(), rig, o);
  std::vector<double> roll, pitch, range, ox, oy, oyaw;
  for (std::size_t i = 0; i < flight.size(); ++i) {
    const auto& s = flight[i];
    const Eigen::Vector3d rpy = euler(s.world_from_body.linear());
    roll.push_back(s.reading.roll - rpy[0]);
    pitch.push_back(s.reading.pitch - rpy[1]);
    // Default laser: from the body origin straight down the body z axis.
    const double z = s.world_from_body.translation().z();
    range.push_back(s.reading.laser_range - z / (std::cos(rpy[0]) * std::cos(rpy[1])));
    if (i == 0) continue;
    const Pose2 truth = between(flight[i - 1].pose, s.pose);
    const double sxy = o.odometry_sigma_xy_per_m * truth.head<2>().norm();
    const double syaw =
        o.odometry_sigma_yaw_per_rad * std::abs(truth[2]) + o.odometry_sigma_yaw_per_s * 0.1;
    const Eigen::Vector3d e = pose_error(s.odometry.delta, truth);
    ox.push_back(e.x() / sxy);
    oy.push_back(e.y() / sxy);
    oyaw.push_back(e.z() / syaw);
  }
  EXPECT_NEAR(sample_std(roll), o.sigma_roll, 0.15 * o.sigma_roll);
  EXPECT_NEAR(sample_std(pitch), o.sigma_pitch, 0.15 * o.sigma_pitch);
  EXPECT_NEAR(sample_std(range), o.sigma_laser_range, 0.15 * o.sigma_laser_range);
  EXPECT_NEAR(sample_std(ox), 1.0, 0.15);
  EXPECT_NEAR(sample_std(oy), 1.0, 0.15);
  EXPECT_NEAR(sample_std(oyaw), 1.0, 0.15);
}

TEST(UavFlight, LeavesTheRunwayForShortStretchesTwicePerLoop) {
  const UavFlightOptions o;
  const auto flight = simulate_uav_flight(scene(), UavRig{}, o);
  std::size_t off = 0;
  std::vector<double> stretches;  // durations over grass, s
  double start = -1.0;
  for (const auto& s : flight) {
    if (!s.over_runway) {
      ++off;
      if (start < 0.0) start = s.time;
    } else if (start >= 0.0) {
      stretches.push_back(s.time - start);
      start = -1.0;
    }
  }
  const double fraction = static_cast<double>(off) / flight.size();
  EXPECT_GT(fraction, 0.05);
  EXPECT_LT(fraction, 0.40);
  // Road length ~170 m at 4 m/s: 120 s of flight covers > 2.5 loops, so >= 4 full stretches.
  ASSERT_GE(stretches.size(), 4u);
  for (const double d : stretches) {
    EXPECT_GE(d, 3.0);
    EXPECT_LE(d, 9.0);
  }
  // The footprint centre really is off the asphalt then: far beyond the border.
  double max_y = 0.0;
  for (const auto& s : flight) max_y = std::max(max_y, std::abs(s.pose.y()));
  EXPECT_GT(max_y, scene().runway.max().y() + 3.0);

  UavFlightOptions on = o;
  on.off_runway_stretches = false;
  for (const auto& s : simulate_uav_flight(scene(), UavRig{}, on)) EXPECT_TRUE(s.over_runway);
}

TEST(UavFlight, IsDeterministicAndRejectsBadOptions) {
  UavFlightOptions o;
  o.frames = 50;
  const auto a = simulate_uav_flight(scene(), UavRig{}, o);
  const auto b = simulate_uav_flight(scene(), UavRig{}, o);
  o.seed = 9;
  const auto c = simulate_uav_flight(scene(), UavRig{}, o);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].reading.laser_range, b[i].reading.laser_range);
    EXPECT_TRUE(a[i].world_from_body.isApprox(b[i].world_from_body, 0.0));
  }
  EXPECT_NE(a[10].reading.laser_range, c[10].reading.laser_range);
  UavFlightOptions bad;
  bad.altitude_min = 30.0;  // above altitude_max
  EXPECT_THROW((void)simulate_uav_flight(scene(), UavRig{}, bad), ConfigError);
  bad = UavFlightOptions{};
  bad.speed = 0.0;
  EXPECT_THROW((void)simulate_uav_flight(scene(), UavRig{}, bad), ConfigError);
}

}  // namespace
}  // namespace vdtnav::uav_camera
