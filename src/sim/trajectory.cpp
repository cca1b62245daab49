#include "vdtnav/sim/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>

#include "vdtnav/core/error.hpp"
#include "vdtnav/map/vector_distance_transform.hpp"

namespace vdtnav::sim {

Pose2 unicycle_increment(double v, double w, double dt) {
  const double theta = w * dt;
  const double s = v * dt;
  // sin(theta)/theta and (1 - cos(theta))/theta = sin(theta/2) * sinc(theta/2), by series near 0.
  double sinc, cosc;
  if (std::abs(theta) < 1e-4) {
    const double t2 = theta * theta;
    sinc = 1.0 - t2 / 6.0;
    cosc = theta / 2.0 * (1.0 - t2 / 12.0);
  } else {
    sinc = std::sin(theta) / theta;
    const double h = 0.5 * theta;
    cosc = std::sin(h) * std::sin(h) / h;
  }
  return {s * sinc, s * cosc, theta};
}

namespace {

constexpr double kRouteSpacing = 0.025;     // metres between route points
constexpr double kArcSampleStep = 0.05;     // metres between clearance checks along an arc
constexpr double kStopTolerance = 0.1;      // metres: a stop point counts as reached
constexpr double kBrakeOffset = 0.05;       // metres: braking profile aims this far before a stop
constexpr double kRotateEnter = kPi / 3;    // rotate in place when the target is this far off
constexpr double kRotateLeave = kPi / 12;   // ... until it is within this
constexpr double kRotateGain = 2.0;         // w = gain * heading error while rotating in place
constexpr double kStuckSeconds = 60.0;      // no progress for this long is an error
constexpr double kClosedGap = 0.5;          // a path whose ends are this close is a loop
constexpr double kCuspAngle = 2 * kPi / 3;  // a turn sharper than this within ...
constexpr double kCuspSpan = 0.2;           // ... this distance either side is a cusp

/// Clearance (UDT at the nearest cell centre; 0 outside the map).
class Clearance {
 public:
  explicit Clearance(const OccupancyGrid<2>& map)
      : map_(map), udt_(unsigned_distance_transform(nearest_occupied_cells(map))) {}
  [[nodiscard]] double at(const Eigen::Vector2d& p) const {
    const Eigen::Vector2i c = map_.cell_of(p);
    return map_.contains(c) ? static_cast<double>(udt_(c)) : 0.0;
  }
  /// Minimum clearance along the segment a-b.
  [[nodiscard]] double along(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / kArcSampleStep)));
    double m = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= n; ++k) m = std::min(m, at(a + (b - a) * (static_cast<double>(k) / n)));
    return m;
  }

 private:
  const OccupancyGrid<2>& map_;
  Grid<float, 2> udt_;
};

/// The polyline resampled at uniform arc-length spacing (last point kept exactly).
std::vector<Eigen::Vector2d> resample(const std::vector<Eigen::Vector2d>& path, double spacing) {
  std::vector<Eigen::Vector2d> out{path.front()};
  double carry = 0.0;  // arc length already covered since the last emitted point
  for (std::size_t k = 0; k + 1 < path.size(); ++k) {
    const Eigen::Vector2d a = path[k], b = path[k + 1];
    const double len = (b - a).norm();
    if (len <= 0.0) continue;
    double s = spacing - carry;
    while (s <= len) {
      out.push_back(a + (b - a) * (s / len));
      s += spacing;
    }
    carry = len - (s - spacing);
  }
  if ((out.back() - path.back()).norm() > 1e-9) out.push_back(path.back());
  return out;
}

/// Indices of the cusps of a uniformly spaced polyline: where it turns back by more than
/// kCuspAngle within kCuspSpan either side (e.g. at a waypoint in a dead end). The robot stops and
/// turns in place there instead of cutting the turn.
std::vector<std::size_t> find_cusps(const std::vector<Eigen::Vector2d>& p) {
  const auto m = static_cast<std::size_t>(std::lround(kCuspSpan / kRouteSpacing));
  const double cos_limit = std::cos(kCuspAngle);
  std::vector<std::size_t> cusps;
  std::size_t run_best = 0;
  double run_cos = 2.0;  // the sharpest turn of the current run of flagged points
  for (std::size_t k = m; k + m < p.size(); ++k) {
    const Eigen::Vector2d a = p[k] - p[k - m], b = p[k + m] - p[k];
    const double c = a.dot(b) / std::max(a.norm() * b.norm(), 1e-12);
    if (c < cos_limit) {
      if (c < run_cos) {
        run_cos = c;
        run_best = k;
      }
    } else if (run_cos <= 1.0) {
      cusps.push_back(run_best);
      run_cos = 2.0;
    }
  }
  if (run_cos <= 1.0) cusps.push_back(run_best);
  return cusps;
}

/// The route the robot drives: passes of the path appended as needed, with the indices where it
/// must come to a stop (cusps, and the turning points of a back-and-forth route).
class Route {
 public:
  /// \param pass uniformly spaced; for a closed route pass.front() == pass.back().
  Route(std::vector<Eigen::Vector2d> pass, bool closed) : pass_(std::move(pass)), closed_(closed) {
    const std::size_t n = pass_.size();
    const auto m = static_cast<std::size_t>(std::lround(kCuspSpan / kRouteSpacing));
    if (!closed_ || n < m + 2) {
      cusps_ = find_cusps(pass_);
    } else {
      // Wrap the loop m points either way so that a cusp at (or near) the junction is found.
      std::vector<Eigen::Vector2d> wrapped(pass_.end() - static_cast<std::ptrdiff_t>(m + 1),
                                           pass_.end() - 1);
      wrapped.insert(wrapped.end(), pass_.begin(), pass_.end());
      wrapped.insert(wrapped.end(), pass_.begin() + 1,
                     pass_.begin() + static_cast<std::ptrdiff_t>(m + 1));
      for (std::size_t e : find_cusps(wrapped)) {
        const std::size_t j = e - m;
        if (j == 0 || j == n - 1) {
          junction_cusp_ = true;
        } else {
          cusps_.push_back(j);
        }
      }
    }
    points_ = pass_;
    stops_ = cusps_;
    stops_.push_back(points_.size() - 1);
  }
  [[nodiscard]] const std::vector<Eigen::Vector2d>& points() const { return points_; }
  [[nodiscard]] std::size_t last() const { return points_.size() - 1; }
  /// The first stop at or after index i (the route's end if there is none).
  [[nodiscard]] std::size_t next_stop(std::size_t i) const {
    const auto it = std::lower_bound(stops_.begin(), stops_.end(), i);
    return it == stops_.end() ? last() : *it;
  }
  /// Appends one more pass: the path again (a loop) or reversed (back and forth).
  void extend() {
    ++passes_;
    const bool forward = closed_ || passes_ % 2 == 0;
    const std::size_t offset = last(), n = pass_.size();
    if (closed_ && !junction_cusp_) stops_.pop_back();  // a smooth loop flows through its end
    if (forward) {
      points_.insert(points_.end(), pass_.begin() + 1, pass_.end());
      for (std::size_t c : cusps_) stops_.push_back(offset + c);
    } else {
      points_.insert(points_.end(), pass_.rbegin() + 1, pass_.rend());
      for (auto it = cusps_.rbegin(); it != cusps_.rend(); ++it)
        stops_.push_back(offset + (n - 1 - *it));
    }
    stops_.push_back(last());
  }

 private:
  std::vector<Eigen::Vector2d> pass_;
  std::vector<std::size_t> cusps_;  // in pass_, excluding its ends
  bool closed_;
  bool junction_cusp_ = false;  // a closed route turns back where it closes
  int passes_ = 0;
  std::vector<Eigen::Vector2d> points_;
  std::vector<std::size_t> stops_;  // ascending indices into points_
};

/// A pure-pursuit target: the look-ahead point in the robot frame and the arc's curvature.
struct Target {
  double alpha = 0.0;      // bearing of the target from the heading
  double curvature = 0.0;  // of the circular arc through the target tangent to the heading
  double distance = 0.0;   // chord length to the target
  double clearance = 0.0;  // minimum clearance along the arc
};

Target make_target(const Pose2& pose, const Eigen::Vector2d& point, const Clearance& clearance) {
  Target t;
  const Pose2 rel = between(pose, Pose2(point.x(), point.y(), 0.0));
  t.distance = std::hypot(rel[0], rel[1]);
  t.alpha = std::atan2(rel[1], rel[0]);
  if (t.distance < 1e-9) {
    t.alpha = 0.0;
    t.clearance = clearance.at(pose.head<2>());
    return t;
  }
  t.curvature = 2.0 * rel[1] / (t.distance * t.distance);  // pure pursuit: kappa = 2 sin(a) / L
  if (std::abs(t.alpha) > kRotateEnter) {  // the robot turns in place first: nothing to sweep
    t.clearance = clearance.at(pose.head<2>());
    return t;
  }
  // Arc length from the robot to the target on that circle (the swept angle is 2 alpha).
  const double arc =
      std::abs(t.alpha) < 1e-9 ? t.distance : t.distance * t.alpha / std::sin(t.alpha);
  const int n = std::max(1, static_cast<int>(std::ceil(arc / kArcSampleStep)));
  t.clearance = std::numeric_limits<double>::infinity();
  for (int k = 1; k <= n; ++k) {
    const Pose2 p = compose(pose, unicycle_increment(1.0, t.curvature, arc * k / n));
    t.clearance = std::min(t.clearance, clearance.at(p.head<2>()));
  }
  return t;
}

}  // namespace

std::vector<TimedPose> follow_path(const std::vector<Eigen::Vector2d>& path,
                                   const OccupancyGrid<2>& map, const TrajectoryOptions& o) {
  VDTNAV_CHECK(std::isfinite(o.speed) && o.speed > 0.0, "follow_path: speed must be > 0");
  VDTNAV_CHECK(std::isfinite(o.max_turn_rate) && o.max_turn_rate > 0.0,
               "follow_path: max_turn_rate must be > 0");
  VDTNAV_CHECK(std::isfinite(o.rate_hz) && o.rate_hz > 0.0, "follow_path: rate_hz must be > 0");
  VDTNAV_CHECK(o.min_steps >= 1, "follow_path: min_steps must be >= 1");
  VDTNAV_CHECK(std::isfinite(o.look_ahead) && o.look_ahead > 0.0,
               "follow_path: look_ahead must be > 0");
  VDTNAV_CHECK(std::isfinite(o.min_clearance) && o.min_clearance >= 0.0,
               "follow_path: min_clearance must be >= 0");
  VDTNAV_CHECK(o.max_acceleration > 0.0 && o.max_angular_acceleration > 0.0,
               "follow_path: acceleration limits must be > 0");
  VDTNAV_CHECK(path.size() >= 2, "follow_path: the path needs at least two points");
  double length = 0.0;
  for (std::size_t k = 0; k < path.size(); ++k) {
    VDTNAV_CHECK(path[k].allFinite(),
                 "follow_path: path point " + std::to_string(k) + " is not finite");
    VDTNAV_CHECK(map.contains(map.cell_of(path[k])),
                 "follow_path: path point " + std::to_string(k) + " lies outside the map");
    if (k > 0) length += (path[k] - path[k - 1]).norm();
  }
  VDTNAV_CHECK(length > kRouteSpacing, "follow_path: the path has (almost) zero length");

  const Clearance clearance(map);
  std::vector<Eigen::Vector2d> pass = resample(path, kRouteSpacing);
  const double gap = (pass.back() - pass.front()).norm();
  const bool closed = gap <= kClosedGap && clearance.along(pass.back(), pass.front()) >=
                                               std::min(o.min_clearance, clearance.at(pass.back()));
  if (closed && gap > 0.0) {
    std::vector<Eigen::Vector2d> loop = pass;
    loop.push_back(pass.front());
    pass = resample(loop, kRouteSpacing);
  }
  Route route(pass, closed);
  const std::size_t first_pass_end = route.last();

  const double dt_nominal = 1.0 / o.rate_hz;
  const auto lookahead_steps = [](double metres) {
    return static_cast<std::size_t>(std::lround(metres / kRouteSpacing));
  };
  // Look-ahead candidates, longest first; the first whose arc keeps clear is taken.
  std::vector<double> candidates;
  for (double f : {1.0, 0.7, 0.5, 0.35, 0.25})
    candidates.push_back(std::max(f * o.look_ahead, 2 * kRouteSpacing));
  const std::size_t search_window = lookahead_steps(o.look_ahead + 0.5);

  // Start at the first point, facing along the path.
  Pose2 pose(pass[0].x(), pass[0].y(), 0.0);
  {
    std::size_t k = 1;
    while (k + 1 < pass.size() && (pass[k] - pass[0]).norm() < 0.3) ++k;
    const Eigen::Vector2d d = pass[k] - pass[0];
    pose[2] = std::atan2(d.y(), d.x());
  }
  std::vector<TimedPose> out;
  out.reserve(static_cast<std::size_t>(o.min_steps));
  out.push_back({0.0, pose, 0.0, 0.0});

  std::size_t i = 0;           // progress: index of the route point the robot is at
  std::size_t not_before = 0;  // stops before this index have been passed
  double v = 0.0, w = 0.0;
  bool rotating = false, stopping = false;
  std::size_t last_progress_step = 0, best_progress = 0;
  bool first_pass_done = false;
  for (std::size_t step = 1;; ++step) {
    if (first_pass_done && out.size() >= static_cast<std::size_t>(o.min_steps)) break;
    // Keep enough route ahead that a loop never brakes at its end.
    const double braking = o.speed * o.speed / (2.0 * o.max_acceleration);
    while (route.last() - i < lookahead_steps(o.look_ahead + braking + 1.0)) route.extend();
    const auto& pts = route.points();
    std::size_t stop = route.next_stop(std::max(i, not_before));

    // Monotone projection onto the route, never past the next stop.
    {
      const std::size_t hi = std::min(i + search_window, stop);
      double best = (pts[i] - pose.head<2>()).squaredNorm();
      for (std::size_t j = i + 1; j <= hi; ++j) {
        const double d2 = (pts[j] - pose.head<2>()).squaredNorm();
        if (d2 < best) {
          best = d2;
          i = j;
        }
      }
    }
    if (i >= first_pass_end) first_pass_done = true;

    // Reaching a stop: brake to rest, then carry on past it.
    if (!stopping && stop - i <= lookahead_steps(2 * kStopTolerance) &&
        (pts[stop] - pose.head<2>()).norm() < kStopTolerance)
      stopping = true;
    if (stopping && v == 0.0 && w == 0.0) {
      stopping = false;
      i = stop;
      if (i >= first_pass_end) first_pass_done = true;
      if (first_pass_done && out.size() >= static_cast<std::size_t>(o.min_steps)) break;
      not_before = i + 1;
      stop = route.next_stop(not_before);
    }
    if (i > best_progress) {
      best_progress = i;
      last_progress_step = step;
    }
    if (static_cast<double>(step - last_progress_step) * dt_nominal > kStuckSeconds)
      throw ConfigError("follow_path: the robot made no progress along the path for " +
                        std::to_string(kStuckSeconds) + " s (is the path in free space?)");

    double v_cmd = 0.0, w_cmd = 0.0;
    if (!stopping) {
      // Pure pursuit: the longest look-ahead whose arc keeps its clearance (never asking for more
      // than the robot has now, so it can always move away from a wall it starts next to).
      const double needed = std::min(o.min_clearance, clearance.at(pose.head<2>()));
      Target target, best_target;
      best_target.clearance = -1.0;
      for (double l : candidates) {
        target = make_target(pose, pts[std::min(i + lookahead_steps(l), stop)], clearance);
        if (target.clearance >= needed) break;
        if (target.clearance > best_target.clearance) best_target = target;
      }
      if (target.clearance < needed) target = best_target;

      if (std::abs(target.alpha) > kRotateEnter) rotating = true;
      if (std::abs(target.alpha) < kRotateLeave) rotating = false;
      if (rotating) {
        w_cmd = std::clamp(kRotateGain * target.alpha, -o.max_turn_rate, o.max_turn_rate);
      } else {
        // Along the route, or straight to the stop if the robot is off to the side of it.
        const double remaining = std::max(static_cast<double>(stop - i) * kRouteSpacing,
                                          (pts[stop] - pose.head<2>()).norm());
        v_cmd = std::min(
            o.speed, std::sqrt(2.0 * o.max_acceleration * std::max(0.0, remaining - kBrakeOffset)));
        if (std::abs(target.curvature) > 1e-9)
          v_cmd = std::min(v_cmd, o.max_turn_rate / std::abs(target.curvature));
      }
      // Acceleration limits; in driving, w follows the arc at the speed actually reached.
      const double dv = o.max_acceleration * dt_nominal;
      v = std::clamp(v_cmd, v - dv, v + dv);
      if (!rotating) w_cmd = v * target.curvature;
    } else {
      const double dv = o.max_acceleration * dt_nominal;
      v = std::clamp(0.0, v - dv, v + dv);
    }
    const double dw = o.max_angular_acceleration * dt_nominal;
    w = std::clamp(std::clamp(w_cmd, w - dw, w + dw), -o.max_turn_rate, o.max_turn_rate);
    v = std::clamp(v, 0.0, o.speed);

    const double t = static_cast<double>(step) / o.rate_hz;
    pose = compose(pose, unicycle_increment(v, w, t - out.back().t));
    out.push_back({t, pose, v, w});
  }
  return out;
}

}  // namespace vdtnav::sim
