#pragma once
/// \file
/// \brief Point-laser observation clouds from PCL: a pcl::PointCloud<pcl::PointXYZ> (or a PCD
/// file) of points measured in the sensor's own frame, whose pose in the robot frame is given.
///
/// Every beam is taken to start at the cloud's viewpoint, `cloud.sensor_origin_` (the PCD
/// VIEWPOINT; (0, 0, 0) by default), expressed in the cloud's frame. Point q then has
///   range r = |q - o|,  direction d = (q - o) / r,
/// and in the robot frame p = T q, dp/dr = R d (T = (R, t) the sensor's pose in the robot frame).
/// For the pan-tilt unit this is exact when the beam origin does not move with pan and tilt
/// (tilt_to_laser = 0 and pan_to_tilt on the pan axis, the viewpoint then being pan_to_tilt in
/// the mount frame); otherwise prefer (pan, tilt, range) readings and point_laser_observations.

#include <string>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "vdtnav/core/pose3.hpp"
#include "vdtnav/sensor/pan_tilt_unit.hpp"
#include "vdtnav/sensor/point_laser_observations.hpp"

namespace vdtnav::point_laser {

/// \brief Converts a cloud in the sensor frame to robot-frame observations (see the file comment).
/// Points with a non-finite coordinate are dropped as not finite, ranges outside
/// [spec.range_min, spec.range_max) as out of range; `reading` holds the point's cloud index.
/// \param sensor_in_robot the pose of the cloud's frame in the robot frame (for a pan-tilt unit
///   whose driver reports points in its base frame: PanTiltCalibration::mount).
[[nodiscard]] PointLaserObservations observations_from_cloud(
    const pcl::PointCloud<pcl::PointXYZ>& cloud, const Pose3& sensor_in_robot,
    const PointLaserSpec& spec = {});

/// \brief Loads a PCD file (pcl::io::loadPCDFile, x y z fields) and converts it with
/// observations_from_cloud, the beams starting at the file's VIEWPOINT.
/// \throws IoError when the file cannot be opened; FormatError (`file: what was expected`) when it
/// is not a PCD point cloud with x, y and z fields.
[[nodiscard]] PointLaserObservations read_point_laser_pcd(const std::string& path,
                                                          const Pose3& sensor_in_robot,
                                                          const PointLaserSpec& spec = {});

/// \return the observation points as a cloud in the robot frame (to view or save with PCL).
[[nodiscard]] pcl::PointCloud<pcl::PointXYZ> to_cloud(const PointLaserObservations& observations);

}  // namespace vdtnav::point_laser
