#pragma once
// ROS 1 bags (v2.0) through rosbag_storage, and the ROS 1 deserialization of the messages of
// messages.hpp through Debian's message headers (ros::serialization).

#include <memory>
#include <string>

#include "vdtnav/ros/bag_reader.hpp"

namespace vdtnav::ros::ros1 {

/// \brief Opens a ROS 1 bag file; FormatError for v1.2 and other formats, truncated files and
/// unknown compression.
[[nodiscard]] std::unique_ptr<BagReader> open(const std::string& path);

[[nodiscard]] LaserScanMsg decode_laser_scan(const BagMessage& m);
[[nodiscard]] PointCloud2Msg decode_point_cloud2(const BagMessage& m);
[[nodiscard]] OdometryMsg decode_odometry(const BagMessage& m);
[[nodiscard]] TfMsg decode_tf(const BagMessage& m);
[[nodiscard]] PoseStampedMsg decode_pose_stamped(const BagMessage& m);
[[nodiscard]] PoseWithCovarianceStampedMsg decode_pose_with_covariance_stamped(const BagMessage& m);
[[nodiscard]] ImuMsg decode_imu(const BagMessage& m);

}  // namespace vdtnav::ros::ros1
