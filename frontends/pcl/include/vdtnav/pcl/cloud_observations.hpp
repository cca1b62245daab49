#pragma once
/// \file
/// \brief A 3D LiDAR scan (a pcl::PointCloud in the sensor's frame) as the ObservationSet3 every 3D
/// estimator takes: robot-frame endpoints with their beam directions and range noise.
///
/// Every beam starts at the cloud's viewpoint o = `cloud.sensor_origin_` (a PCD file's VIEWPOINT;
/// (0, 0, 0) for a cloud in the sensor's frame). Point q then has
///   range r = |q - o|,  direction u = (q - o) / r,
/// and in the robot frame p = T q, dp/dr = R u, T = (R, t) the pose of the cloud's frame in the
/// robot frame, so that the point's covariance is sigma_r^2 (R u)(R u)^T (observation_set.hpp).

#include <limits>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "vdtnav/core/pose3.hpp"
#include "vdtnav/sensor/observation_set.hpp"

namespace vdtnav {

/// \brief The sensor a cloud comes from and how it is thinned.
struct CloudObservationOptions {
  Pose3 sensor_in_robot = Pose3::Identity();  ///< pose of the cloud's frame in the robot frame
  /// Range noise standard deviation, metres (>= 0). Default: the +-3 cm of Velodyne's VLP-16/HDL-32
  /// data sheets; set the sensor's own (an Ouster OS1: ~0.03 m, a Livox Mid-70: 0.02 m).
  double sigma_range = 0.03;
  double range_min = 0.0;  ///< metres: shorter readings are dropped (the robot's own body)
  /// Metres: readings at or beyond it are dropped (no-return values, or far points to ignore).
  /// Default: none, every finite point is kept.
  double range_max = std::numeric_limits<double>::infinity();
  /// Voxel downsampling, metres: > 0 keeps one reading per cube of this edge (in the cloud's
  /// frame), the measured point nearest the centroid of the cube's points, so that every kept
  /// point is a real reading with a real beam (a centroid of points at several ranges is not);
  /// 0: every reading.
  double voxel = 0.0;
};

/// \brief Converts a cloud to robot-frame observations (see the file comment). Points with a
/// non-finite coordinate are dropped and counted in `dropped_not_finite`; ranges outside
/// [range_min, range_max) or zero in `dropped_out_of_range`; `beam` holds each kept point's index
/// in the cloud. With `voxel` > 0 the kept readings come in the order their cubes first appear.
/// \throws ConfigError when an option is out of its domain (the message names it).
[[nodiscard]] ObservationSet3 observations_from_cloud(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                                      const CloudObservationOptions& options = {});

/// \brief As above, each kept reading with its time: `times[i]`, seconds after the scan's stamp,
/// for point i of the cloud (PointTimes, point_cloud_file.hpp; a PointCloud2's, ros/cloud_points),
/// into ObservationSet3::times for deskewing (a reading whose time is not finite is dropped and
/// counted in `dropped_not_finite`). Empty `times`: as above (an instantaneous sweep).
/// \throws ConfigError as above, and when `times` is neither empty nor one per point.
[[nodiscard]] ObservationSet3 observations_from_cloud(const pcl::PointCloud<pcl::PointXYZ>& cloud,
                                                      const CloudObservationOptions& options,
                                                      const std::vector<double>& times);

/// \return the observation points as a cloud in the robot frame (to view or save with PCL).
[[nodiscard]] pcl::PointCloud<pcl::PointXYZ> to_cloud(const ObservationSet3& observations);

}  // namespace vdtnav
