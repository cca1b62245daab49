#include "vdtnav/io/log_odometry.hpp"

#include <algorithm>
#include <cmath>

namespace vdtnav {

namespace {

std::string odom_unusable_reason(const std::vector<CarmenOdometry>& odom, double t0, double t1) {
  if (odom.size() < 2) return "fewer than two ODOM lines";
  const bool all_zero = std::all_of(odom.begin(), odom.end(),
                                    [](const CarmenOdometry& o) { return o.pose.isZero(0.0); });
  if (all_zero) return "all ODOM poses are zero (a corrected log)";
  for (std::size_t i = 1; i < odom.size(); ++i) {
    if (!(odom[i].time >= odom[i - 1].time)) {
      return "ODOM times decrease at line " + std::to_string(odom[i].line);
    }
  }
  constexpr double kSpanTolerance = 0.5;  // seconds
  if (odom.front().time > t0 + kSpanTolerance || odom.back().time < t1 - kSpanTolerance) {
    return "ODOM lines do not span the scans' times";
  }
  return {};
}

// Linear interpolation in x, y; the shorter arc in yaw; clamped at the ends.
Pose2 odom_at(const std::vector<CarmenOdometry>& odom, double t) {
  const auto it = std::lower_bound(odom.begin(), odom.end(), t,
                                   [](const CarmenOdometry& o, double s) { return o.time < s; });
  if (it == odom.begin()) return odom.front().pose;
  if (it == odom.end()) return odom.back().pose;
  const CarmenOdometry& b = *it;
  const CarmenOdometry& a = *(it - 1);
  const double span = b.time - a.time;
  const double u = span > 0.0 ? (t - a.time) / span : 1.0;
  return {a.pose[0] + u * (b.pose[0] - a.pose[0]), a.pose[1] + u * (b.pose[1] - a.pose[1]),
          wrap_angle(a.pose[2] + u * wrap_angle(b.pose[2] - a.pose[2]))};
}

}  // namespace

LogOdometry log_odometry(const CarmenLog& log, const std::vector<std::size_t>& scans) {
  LogOdometry out;
  if (scans.empty()) return out;
  const double t0 = log.lasers[scans.front()].time;
  const double t1 = log.lasers[scans.back()].time;
  out.reason = odom_unusable_reason(log.odometry, t0, t1);
  out.poses.reserve(scans.size());
  if (out.reason.empty()) {
    out.source = LogOdometrySource::kOdomMessages;
    for (std::size_t i : scans) out.poses.push_back(odom_at(log.odometry, log.lasers[i].time));
  } else {
    out.source = LogOdometrySource::kLaserOdomFields;
    for (std::size_t i : scans) out.poses.push_back(log.lasers[i].odom);
  }
  return out;
}

std::vector<OdometryStep> odometry_steps(const std::vector<double>& times,
                                         const std::vector<Pose2>& odometry) {
  std::vector<OdometryStep> steps(odometry.size());
  for (std::size_t k = 1; k < odometry.size(); ++k) {
    OdometryStep& s = steps[k];
    s.dt = std::max(0.0, times[k] - times[k - 1]);
    s.delta = between(odometry[k - 1], odometry[k]);
    if (s.dt > 0.0) {
      s.v = std::copysign(std::hypot(s.delta[0], s.delta[1]), s.delta[0]) / s.dt;
      s.w = s.delta[2] / s.dt;
    }
  }
  return steps;
}

}  // namespace vdtnav
