#include "vdtnav/estimation/active_beam.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "vdtnav/core/error.hpp"
#include "vdtnav/map/sphere_tracing.hpp"

namespace vdtnav {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}  // namespace

RotatingBeamOptions RotatingBeamOptions::table_4_1() {
  RotatingBeamOptions o;
  o.rotation_range = 2.0 * kPi;
  o.angular_velocity = 0.525;
  o.segments = 8;
  o.lambda = 1e-5;
  o.range_min = 0.5;
  o.range_max = 3.0;
  return o;
}

RotatingBeamOptions RotatingBeamOptions::table_4_3() {
  RotatingBeamOptions o;
  o.rotation_range = 1.5 * kPi;
  o.angular_velocity = 0.1745;
  o.segments = 23;
  o.lambda = 1e-5;
  o.range_min = 0.5;
  o.range_max = 30.0;
  return o;
}

bool RotatingBeamOptions::full_turn() const noexcept { return rotation_range >= 2.0 * kPi - 1e-9; }

void RotatingBeamOptions::validate() const {
  VDTNAV_CHECK(
      std::isfinite(rotation_range) && rotation_range > 0.0 && rotation_range <= 2.0 * kPi + 1e-9,
      "rotating beam: rotation_range must be in (0, 2 pi] radians");
  VDTNAV_CHECK(std::isfinite(angular_velocity) && angular_velocity > 0.0,
               "rotating beam: angular_velocity must be > 0");
  VDTNAV_CHECK(segments >= 1, "rotating beam: segments must be >= 1");
  VDTNAV_CHECK(std::isfinite(lambda) && lambda >= 0.0, "rotating beam: lambda must be >= 0");
  VDTNAV_CHECK(range_min >= 0.0 && range_max > range_min && std::isfinite(range_max),
               "rotating beam: ranges must satisfy 0 <= range_min < range_max < inf");
  VDTNAV_CHECK(std::isfinite(sigma_range) && sigma_range > 0.0,
               "rotating beam: sigma_range must be > 0");
  VDTNAV_CHECK(std::isfinite(hypothesis_resolution) && hypothesis_resolution > 0.0,
               "rotating beam: hypothesis_resolution must be > 0");
  VDTNAV_CHECK(std::isfinite(gate), "rotating beam: gate must be finite (<= 0: no gate)");
}

const char* to_string(BeamStrategy s) noexcept {
  switch (s) {
    case BeamStrategy::kActiveTrace:
      return "active-trace";
    case BeamStrategy::kActiveDet:
      return "active-det";
    case BeamStrategy::kActiveFisher:
      return "active-fisher";
    case BeamStrategy::kPassiveFixed:
      return "passive-fixed";
    case BeamStrategy::kPassiveRotate:
      return "passive-rotate";
  }
  return "?";
}

BeamStrategy beam_strategy_from_string(const std::string& name) {
  for (const BeamStrategy s :
       {BeamStrategy::kActiveTrace, BeamStrategy::kActiveDet, BeamStrategy::kActiveFisher,
        BeamStrategy::kPassiveFixed, BeamStrategy::kPassiveRotate}) {
    if (name == to_string(s)) return s;
  }
  throw ConfigError("unknown beam strategy '" + name +
                    "' (expected one of: active-trace, active-det, active-fisher, passive-fixed, "
                    "passive-rotate)");
}

// ------------------------------------------------------------------------------- selector

ActiveBeamSelector::ActiveBeamSelector(const VdtMap2& map, const RotatingBeamOptions& beam,
                                       const VdtSensorModelOptions& sensor)
    : map_(&map), beam_(beam), model_(map, sensor) {
  beam_.validate();
}

double ActiveBeamSelector::segment_lower(int i) const {
  return -0.5 * beam_.rotation_range + i * beam_.rotation_range / beam_.segments;
}
double ActiveBeamSelector::segment_upper(int i) const { return segment_lower(i + 1); }
double ActiveBeamSelector::segment_centre(int i) const {
  return 0.5 * (segment_lower(i) + segment_upper(i));
}

bool ActiveBeamSelector::consistent(const Pose2& pose, const Eigen::Matrix3d& p, double theta,
                                    double range) const {
  if (beam_.gate <= 0.0) return true;
  Eigen::Vector3d g;
  if (!range_gradient(pose, theta, &g)) return false;
  const double predicted = hypothetical_range(pose, theta);
  const double var = g.dot(p * g) + beam_.sigma_range * beam_.sigma_range +
                     model_.map_sigma() * model_.map_sigma();
  return std::abs(range - predicted) <= beam_.gate * std::sqrt(var);
}

int ActiveBeamSelector::segment_of(double theta) const {
  const double half = 0.5 * beam_.rotation_range;
  double t = beam_.full_turn() ? wrap_angle(theta) : theta;
  t = std::clamp(t, -half, half);
  const int i = static_cast<int>(std::floor((t + half) / beam_.rotation_range * beam_.segments));
  return std::clamp(i, 0, beam_.segments - 1);
}

double ActiveBeamSelector::hypothetical_range(const Pose2& pose, double theta) const {
  const double a = pose[2] + theta;
  const double r = sphere_trace<2>(*map_, pose.head<2>(), Eigen::Vector2d(std::cos(a), std::sin(a)),
                                   beam_.range_max);
  return r >= beam_.range_min && r < beam_.range_max ? r : kInf;
}

bool ActiveBeamSelector::range_gradient(const Pose2& pose, double theta, Eigen::Vector3d* g) const {
  const double r = hypothetical_range(pose, theta);
  if (!std::isfinite(r)) return false;
  const Eigen::Vector2d u(std::cos(pose[2] + theta), std::sin(pose[2] + theta));
  // The surface normal: dDT_v/dp at the hit is the projector n n^T onto it (a wall's VDT), its
  // dominant eigenvector, turned toward the sensor.
  const Eigen::Matrix2d j = map_->evaluate(pose.head<2>() + r * u).jacobian;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(0.5 * (j + j.transpose()));
  Eigen::Vector2d n = es.eigenvectors().col(1);
  if (n.dot(u) > 0.0) n = -n;
  const double nu = n.dot(u);
  if (std::abs(nu) < 1e-3) return false;        // grazing: the range is not defined by the surface
  const Eigen::Vector2d u_perp(-u.y(), u.x());  // du/dphi
  *g = -Eigen::Vector3d(n.x(), n.y(), r * n.dot(u_perp)) / nu;
  return true;
}

Eigen::Matrix3d ActiveBeamSelector::predicted_covariance(const Pose2& pose,
                                                         const Eigen::Matrix3d& p, int segment,
                                                         BeamStrategy strategy,
                                                         int* readings) const {
  const double lo = segment_lower(segment), hi = segment_upper(segment);
  const int n = std::max(1, static_cast<int>(std::lround((hi - lo) / beam_.hypothesis_resolution)));
  Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
  int count = 0;
  if (strategy == BeamStrategy::kActiveFisher) {
    const double s2 = beam_.sigma_range * beam_.sigma_range;
    for (int k = 0; k < n; ++k) {
      Eigen::Vector3d g;
      if (!range_gradient(pose, lo + (k + 0.5) * (hi - lo) / n, &g)) continue;
      info.noalias() += g * g.transpose() / s2;
      ++count;
    }
  } else {
    // The EKF's information-form update (vdt_ekf.cpp) with the hypothetical readings.
    ScanPoints pts;
    pts.sigma_range = beam_.sigma_range;
    pts.range_max = beam_.range_max;
    for (int k = 0; k < n; ++k) {
      const double theta = lo + (k + 0.5) * (hi - lo) / n;
      const double r = hypothetical_range(pose, theta);
      if (!std::isfinite(r)) continue;
      pts.add(Eigen::Vector2d::Zero(), Eigen::Vector2d(std::cos(theta), std::sin(theta)), r,
              static_cast<std::size_t>(k));
    }
    std::vector<BeamDisparity> d;
    model_.disparities(PoseTraits<2>::rotation(pose), pose.head<2>(), pts, nullptr, &d);
    for (std::size_t k = 0; k < pts.size(); ++k) {
      if (!d[k].inlier) continue;
      const Eigen::Matrix2d r_inv = model_.disparity_covariance(d[k], pts.sigma_range).inverse();
      info.noalias() += d[k].d_pose.transpose() * r_inv * d[k].d_pose;  // (3.13)-(3.21)
      ++count;
    }
  }
  if (readings != nullptr) *readings = count;
  if (count == 0) return p;
  const Eigen::Matrix3d post = (p.inverse() + info).inverse();
  return 0.5 * (post + post.transpose());
}

BeamSelection ActiveBeamSelector::select(const Pose2& pose, const Eigen::Matrix3d& p, int current,
                                         BeamStrategy strategy) const {
  VDTNAV_CHECK(
      strategy == BeamStrategy::kActiveTrace || strategy == BeamStrategy::kActiveDet ||
          strategy == BeamStrategy::kActiveFisher,
      std::string("active beam: select() needs an active strategy, not ") + to_string(strategy));
  const int n = beam_.segments;
  BeamSelection out;
  out.cost.assign(static_cast<std::size_t>(n), kInf);
  out.readings.assign(static_cast<std::size_t>(n), 0);
  double best = kInf;
  for (int i = 0; i < n; ++i) {
    int readings = 0;
    const Eigen::Matrix3d pi = predicted_covariance(pose, p, i, strategy, &readings);
    int moved = std::abs(i - current);
    if (beam_.full_turn()) moved = std::min(moved, n - moved);
    // (4.1); D-optimality through det^(1/3), a variance like trace / 3, so that lambda weighs
    // the motion against it in the same units.
    const double c =
        (strategy == BeamStrategy::kActiveDet ? std::cbrt(pi.determinant()) : pi.trace()) +
        beam_.lambda * moved;
    out.cost[static_cast<std::size_t>(i)] = c;
    out.readings[static_cast<std::size_t>(i)] = readings;
    if (c < best) {
      best = c;
      out.segment = i;
    }
  }
  return out;
}

// ------------------------------------------------------------------------------- controller

RotatingBeamController::RotatingBeamController(const RotatingBeamOptions& beam,
                                               BeamStrategy strategy)
    : beam_(beam), strategy_(strategy) {
  beam_.validate();
}

bool RotatingBeamController::needs_goal() const noexcept {
  return reached_ &&
         (strategy_ == BeamStrategy::kActiveTrace || strategy_ == BeamStrategy::kActiveDet ||
          strategy_ == BeamStrategy::kActiveFisher);
}

void RotatingBeamController::set_goal(int segment, const ActiveBeamSelector& selector) {
  goal_ = segment;
  // Sweep toward the end of the goal segment further from the current bearing.
  const double lo = selector.segment_lower(segment), hi = selector.segment_upper(segment);
  const auto distance = [&](double a) {
    return beam_.full_turn() ? std::abs(wrap_angle(a - theta_)) : std::abs(a - theta_);
  };
  target_ = distance(lo) > distance(hi) ? lo : hi;
  reached_ = false;
}

void RotatingBeamController::advance(double dt) {
  const double step = beam_.angular_velocity * dt;
  const double half = 0.5 * beam_.rotation_range;
  switch (strategy_) {
    case BeamStrategy::kPassiveFixed:
      theta_ = 0.0;
      return;
    case BeamStrategy::kPassiveRotate:
      theta_ += direction_ * step;
      if (beam_.full_turn()) {
        theta_ = wrap_angle(theta_);
      } else if (theta_ > half || theta_ < -half) {  // bounce at the ends of the range
        direction_ = -direction_;
        theta_ = std::clamp(theta_, -half, half);
      }
      return;
    default:
      break;
  }
  if (reached_) return;
  const double to_go = beam_.full_turn() ? wrap_angle(target_ - theta_) : target_ - theta_;
  if (std::abs(to_go) <= step) {
    theta_ = beam_.full_turn() ? wrap_angle(target_) : target_;
    reached_ = true;
  } else {
    theta_ += std::copysign(step, to_go);
    if (beam_.full_turn()) theta_ = wrap_angle(theta_);
  }
}

}  // namespace vdtnav
