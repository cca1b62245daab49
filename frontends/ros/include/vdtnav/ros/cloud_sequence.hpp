#pragma once
/// \file
/// \brief A 3D LiDAR run read from a bag, one cloud at a time: each sensor_msgs/PointCloud2 with
/// the sensor's mounting, the robot's odometry pose and the IMU's roll and pitch at its header
/// stamp — what `vdtnav localize3d --bag` localizes.
///
/// Where things come from (REP 105 names by default):
/// - clouds: `cloud_topic`, or the bag's only PointCloud2 topic;
/// - odometry: `odom_topic` when given ("none": no odometry, the localizer predicts with constant
///   velocity); otherwise TF odom_frame -> base_frame when the bag's /tf connects them; otherwise
///   the bag's only nav_msgs/Odometry topic; otherwise none. Interpolated at each stamp;
/// - mounting: `lidar_pose` when given, else TF base_frame -> the cloud's frame, else identity
///   when the cloud is in base_frame; otherwise a ConfigError naming the frames;
/// - roll and pitch: `imu_topic` when given (sensor_msgs/Imu orientation, slerped at the stamp and
///   turned into the robot's through TF base_frame -> the IMU's frame when the bag has it); its
///   angular velocities and linear accelerations too, turned the same way (CloudFrame::imu), for
///   the localizer to preintegrate between clouds.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vdtnav/core/pose3.hpp"
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros/cloud_points.hpp"
#include "vdtnav/sensor/imu.hpp"

namespace vdtnav::ros {

/// \brief Which topics and frames make up the run.
struct CloudSequenceOptions {
  std::string cloud_topic;  ///< "" = the only PointCloud2 topic
  std::string odom_topic;   ///< "" = TF, else the only Odometry topic; "none" = no odometry
  std::string imu_topic;    ///< "" = no IMU
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  std::optional<Pose3> lidar_pose;  ///< the cloud frame's pose in base_frame; unset: from TF
};

/// \brief One cloud of the run.
struct CloudFrame {
  std::int64_t stamp_ns = 0;
  std::string frame;
  CloudPoints cloud;                ///< in the cloud's frame
  Pose3 mount = Pose3::Identity();  ///< the cloud frame in base_frame
  std::optional<Pose3> odometry;    ///< base_frame in odom_frame at the stamp
  double roll = std::numeric_limits<double>::quiet_NaN();   ///< the robot's, from the IMU
  double pitch = std::numeric_limits<double>::quiet_NaN();  ///< NaN: no IMU reading there
  /// With an IMU topic: every sample of the bag's (angular velocity and linear acceleration turned
  /// into base_frame, stamps in seconds, increasing), shared by the frames; else null.
  std::shared_ptr<const std::vector<vdtnav::ImuSample>> imu;
};

/// \brief What the run is made of, said once before the clouds come.
struct CloudSequenceInfo {
  std::string cloud_topic, odometry_source, mount_source, imu_source;
  std::size_t clouds = 0;
};

/// \brief Reads TF, odometry and IMU first, then calls `visit` on every cloud in stamp order
/// (stops when it returns false). \return what the run is made of. \throws ConfigError for a
/// missing topic or transform (naming what the bag has), FormatError for a bad message.
CloudSequenceInfo read_cloud_sequence(const BagReader& bag, const CloudSequenceOptions& options,
                                      const std::function<bool(const CloudFrame&)>& visit);

}  // namespace vdtnav::ros
