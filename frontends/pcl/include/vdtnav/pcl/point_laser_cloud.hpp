#pragma once
/// \file
/// \brief Point-laser observation clouds from PCL: a pcl::PointCloud<pcl::PointXYZ> (or a PCD
/// file) of points measured in the sensor's own frame, whose pose in the robot frame is given.
///
/// The conversion is vdtnav::pcl's observations_from_cloud (cloud_observations.hpp) with the
/// pan-tilt unit's range limits and noise: every beam starts at the cloud's viewpoint,
/// `cloud.sensor_origin_`. For the pan-tilt unit this is exact when the beam origin does not move
/// with pan and tilt (tilt_to_laser = 0 and pan_to_tilt on the pan axis, the viewpoint then being
/// pan_to_tilt in the mount frame); otherwise prefer (pan, tilt, range) readings and
/// point_laser_observations.

#include <string>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "vdtnav/core/pose3.hpp"
#include "vdtnav/pcl/cloud_observations.hpp"
#include "vdtnav/sensor/pan_tilt_unit.hpp"
#include "vdtnav/sensor/point_laser_observations.hpp"

namespace vdtnav::point_laser {

/// \brief observations_from_cloud (cloud_observations.hpp) with the pan-tilt unit's
/// spec.sigma_range and range interval [spec.range_min, spec.range_max).
/// \param sensor_in_robot the pose of the cloud's frame in the robot frame (for a pan-tilt unit
///   whose driver reports points in its base frame: PanTiltCalibration::mount).
[[nodiscard]] ObservationSet3 observations_from_cloud(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                                      const Pose3& sensor_in_robot,
                                                      const PointLaserSpec& spec = {});

/// \brief Loads a point cloud file (read_point_cloud: PCD, PLY, VTK, text) and converts it with
/// observations_from_cloud, the beams starting at a PCD file's VIEWPOINT.
/// \throws IoError when the file cannot be opened; FormatError (`file: what was expected`) when it
/// is not a point cloud with x, y and z fields.
[[nodiscard]] ObservationSet3 read_point_laser_pcd(const std::string& path,
                                                   const Pose3& sensor_in_robot,
                                                   const PointLaserSpec& spec = {});

}  // namespace vdtnav::point_laser
