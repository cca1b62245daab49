#pragma once
/// \file
/// \brief The odometry a localizer gets from a CARMEN log: the log's ODOM messages interpolated at
/// the scan times when they are usable, otherwise the odometry fields of the laser messages.

#include <cstddef>
#include <string>
#include <vector>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/io/carmen_log.hpp"
#include "vdtnav/sensor/odometry.hpp"

namespace vdtnav {

/// \brief Where the odometry came from.
enum class LogOdometrySource {
  kOdomMessages,     ///< ODOM lines, interpolated at each scan's time
  kLaserOdomFields,  ///< the odom_x odom_y odom_theta fields of FLASER / ROBOTLASER1
};

/// \brief The odometry pose at each selected scan.
struct LogOdometry {
  LogOdometrySource source = LogOdometrySource::kLaserOdomFields;
  std::vector<Pose2> poses;  ///< one per selected scan, in the odometry frame
  std::string reason;        ///< why ODOM lines were not used (empty when they were)
};

/// \brief Odometry poses at the scans `log.lasers[i]`, i in `scans` (increasing times).
///
/// ODOM lines are usable when there are at least two, they are not all at the origin (corrected
/// logs zero them), their times increase, and they span the selected scans' times (to 0.5 s).
/// They are interpolated linearly in x, y and along the shorter arc in yaw.
[[nodiscard]] LogOdometry log_odometry(const CarmenLog& log, const std::vector<std::size_t>& scans);

/// \brief The steps between consecutive scans: step k is from scan k-1 to scan k (step 0 has
/// dt = 0 and a zero increment). v and w are the increment's arc length and turn over dt.
[[nodiscard]] std::vector<OdometryStep> odometry_steps(const std::vector<double>& times,
                                                       const std::vector<Pose2>& odometry);

}  // namespace vdtnav
