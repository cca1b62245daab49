#pragma once
/// \file
/// \brief The 3D observation set of a pan-tilt point laser sweep (thesis 3.4.4: "observation point
/// clouds ... transforming the range measurements to the robot frame using pan and tilt angles and
/// calibration parameters"): robot-frame points with dp/dr and the range noise that produced them.

#include <cmath>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/sensor/pan_tilt_unit.hpp"

namespace vdtnav {

/// \brief The valid readings of a sweep as points in the robot frame.
struct PointLaserObservations {
  std::vector<Eigen::Vector3d> points;           ///< robot frame
  std::vector<Eigen::Vector3d> d_point_d_range;  ///< unit beam directions (dp/dr), robot frame
  std::vector<double> ranges;                    ///< the ranges kept, metres
  std::vector<std::size_t> reading;              ///< index of each kept reading in its source
  double sigma_range = 0.0;                      ///< range noise standard deviation, metres
  std::size_t dropped_not_finite = 0;            ///< NaN or inf range, pan or tilt
  std::size_t dropped_out_of_range = 0;          ///< range outside [range_min, range_max)

  [[nodiscard]] std::size_t size() const noexcept { return points.size(); }
};

/// \brief Converts a sweep to robot-frame points with pan_tilt_point, dropping and counting
/// non-finite readings and ranges outside [spec.range_min, spec.range_max).
[[nodiscard]] inline PointLaserObservations point_laser_observations(
    const std::vector<PanTiltReading>& readings, const PanTiltCalibration& calibration,
    const PointLaserSpec& spec = {}) {
  PointLaserObservations out;
  out.sigma_range = spec.sigma_range;
  out.points.reserve(readings.size());
  out.d_point_d_range.reserve(readings.size());
  out.ranges.reserve(readings.size());
  out.reading.reserve(readings.size());
  for (std::size_t i = 0; i < readings.size(); ++i) {
    const PanTiltReading& z = readings[i];
    if (!std::isfinite(z.range) || !std::isfinite(z.pan) || !std::isfinite(z.tilt)) {
      ++out.dropped_not_finite;
      continue;
    }
    if (z.range < spec.range_min || z.range >= spec.range_max) {
      ++out.dropped_out_of_range;
      continue;
    }
    const PanTiltPoint p = pan_tilt_point(calibration, z);
    out.points.push_back(p.point);
    out.d_point_d_range.push_back(p.d_range);
    out.ranges.push_back(z.range);
    out.reading.push_back(i);
  }
  return out;
}

}  // namespace vdtnav
