#pragma once
/// \file
/// \brief A scan of a map-building run: its estimated pose with that estimate's covariance (e.g.
/// from a pose-graph SLAM), and its readings.

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/sensor/laser_scan.hpp"

namespace vdtnav::mapping {

/// \brief One scan the map is built from (thesis 5.2.3: X_R with cov(X_R), and S_{r theta}).
struct MapScan {
  Pose2 pose = Pose2::Zero();                                 ///< estimated robot pose (x, y, phi)
  Eigen::Matrix3d pose_covariance = Eigen::Matrix3d::Zero();  ///< of (x, y, phi); 0: exact
  ScanPoints points;  ///< readings as robot-frame points (sigma_range is the range noise)
};

}  // namespace vdtnav::mapping
