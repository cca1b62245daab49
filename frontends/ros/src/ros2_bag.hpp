#pragma once
// ROS 2 bags (rosbag2 folders: metadata.yaml + sqlite3 .db3 files), and the CDR decoding of the
// messages of messages.hpp with eProsima Fast CDR.

#include <memory>
#include <string>

#include "vdtnav/ros/bag_reader.hpp"

namespace vdtnav::ros::ros2 {

/// \brief Opens a ROS 2 bag folder (or its metadata.yaml or a .db3 in it); FormatError for .mcap
/// storage (naming the conversion to sqlite3), compressed bags and unreadable databases.
[[nodiscard]] std::unique_ptr<BagReader> open(const std::string& path);

[[nodiscard]] LaserScanMsg decode_laser_scan(const BagMessage& m);
[[nodiscard]] PointCloud2Msg decode_point_cloud2(const BagMessage& m);
[[nodiscard]] OdometryMsg decode_odometry(const BagMessage& m);
[[nodiscard]] TfMsg decode_tf(const BagMessage& m);
[[nodiscard]] PoseStampedMsg decode_pose_stamped(const BagMessage& m);
[[nodiscard]] PoseWithCovarianceStampedMsg decode_pose_with_covariance_stamped(const BagMessage& m);
[[nodiscard]] ImuMsg decode_imu(const BagMessage& m);

}  // namespace vdtnav::ros::ros2
