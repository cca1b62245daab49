#pragma once
/// \file
/// \brief The 3D observation set of a pan-tilt point laser sweep (thesis 3.4.4: "observation point
/// clouds ... transforming the range measurements to the robot frame using pan and tilt angles and
/// calibration parameters"): an ObservationSet3, robot-frame points with dp/dr and the range noise
/// that produced them, the type every 3D estimator takes.

#include <cmath>
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/sensor/observation_set.hpp"
#include "vdtnav/sensor/pan_tilt_unit.hpp"

namespace vdtnav {

/// \brief Converts a sweep to robot-frame points with pan_tilt_point, dropping and counting
/// non-finite readings and ranges outside [spec.range_min, spec.range_max); `beam` holds each kept
/// reading's index in `readings`.
[[nodiscard]] inline ObservationSet3 point_laser_observations(
    const std::vector<PanTiltReading>& readings, const PanTiltCalibration& calibration,
    const PointLaserSpec& spec = {}) {
  ObservationSet3 out;
  out.sigma_range = spec.sigma_range;
  out.range_max = spec.range_max;
  out.points.reserve(readings.size());
  out.directions.reserve(readings.size());
  out.ranges.reserve(readings.size());
  out.beam.reserve(readings.size());
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
    out.directions.push_back(p.d_range);
    out.ranges.push_back(z.range);
    out.beam.push_back(i);
  }
  return out;
}

}  // namespace vdtnav
