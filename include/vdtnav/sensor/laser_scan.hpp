#pragma once
/// \file
/// \brief A planar range scan as a LiDAR driver delivers it, and the observation points the
/// estimators use (SPEC: points in the sensor frame with the range noise that produced them, plus
/// the mounting pose).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/sensor/observation_set.hpp"

namespace vdtnav {

/// \brief One 2D scan (ROS sensor_msgs/LaserScan semantics).
struct LaserScan {
  double time = 0.0;             ///< seconds
  std::vector<double> ranges;    ///< metres; NaN/inf/out-of-range readings are dropped
  double angle_min = 0.0;        ///< radians, angle of beam 0 in the sensor frame
  double angle_increment = 0.0;  ///< radians between beams
  std::vector<double> angles;    ///< explicit beam angles; when non-empty, used instead
  double range_min = 0.1;        ///< metres; readings < range_min are dropped
  double range_max = 30.0;       ///< metres; readings >= range_max are dropped (no return)
  Pose2 mount = Pose2::Zero();   ///< sensor pose in the robot frame
  double sigma_range = 0.02;     ///< range noise standard deviation, metres

  /// \return the angle of beam i in the sensor frame.
  [[nodiscard]] double angle(std::size_t i) const {
    return angles.empty() ? angle_min + static_cast<double>(i) * angle_increment : angles[i];
  }
};

/// \brief The valid beams of a scan as points in the robot frame.
///
/// Beam i with range r and angle theta ends at  p = t_m + R(phi_m) r (cos theta, sin theta)  in the
/// robot frame (SPEC's corrected (2.11) after the mounting transform); dp/dr = R(phi_m) (cos, sin).
using ScanPoints = ObservationSet<2>;

/// \brief Converts a scan to robot-frame points, dropping and counting invalid readings.
[[nodiscard]] inline ScanPoints scan_points(const LaserScan& scan) {
  ScanPoints out;
  out.sigma_range = scan.sigma_range;
  out.range_max = scan.range_max;
  const double cm = std::cos(scan.mount[2]), sm = std::sin(scan.mount[2]);
  // Evenly spaced beams: the direction of beam i = 32 h + l is R(angle_min + 32 h inc) (cos, sin)
  // (l inc), from two tables of ~sqrt(n) sines and cosines, each entry computed directly (no
  // recurrence, so no drift: a few ulp from std::cos/sin of the beam angle itself).
  constexpr std::size_t kLow = 32;
  const bool even = scan.angles.empty();
  std::vector<Eigen::Vector2d> low, high;
  if (even) {
    const std::size_t n = scan.ranges.size();
    low.resize(std::min(n, kLow));
    high.resize((n + kLow - 1) / kLow);
    for (std::size_t l = 0; l < low.size(); ++l) {
      const double a = static_cast<double>(l) * scan.angle_increment;
      low[l] = Eigen::Vector2d(std::cos(a), std::sin(a));
    }
    for (std::size_t h = 0; h < high.size(); ++h) {
      const double a = scan.angle_min + static_cast<double>(h * kLow) * scan.angle_increment;
      high[h] = Eigen::Vector2d(std::cos(a), std::sin(a));
    }
  }
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    if (!std::isfinite(r)) {
      ++out.dropped_not_finite;
      continue;
    }
    if (r < scan.range_min || r >= scan.range_max) {
      ++out.dropped_out_of_range;
      continue;
    }
    double ca, sa;
    if (even) {
      const Eigen::Vector2d& h = high[i / kLow];
      const Eigen::Vector2d& l = low[i % kLow];
      ca = h.x() * l.x() - h.y() * l.y();
      sa = h.y() * l.x() + h.x() * l.y();
    } else {
      const double a = scan.angle(i);
      ca = std::cos(a);
      sa = std::sin(a);
    }
    const Eigen::Vector2d dir(cm * ca - sm * sa, sm * ca + cm * sa);
    out.points.emplace_back(scan.mount[0] + r * dir.x(), scan.mount[1] + r * dir.y());
    out.directions.push_back(dir);
    out.ranges.push_back(r);
    out.beam.push_back(i);
  }
  return out;
}

}  // namespace vdtnav
