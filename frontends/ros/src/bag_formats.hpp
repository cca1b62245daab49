#pragma once
// The two bag formats behind BagReader::open and the decode_* functions (bag_reader.cpp
// dispatches on the message's format), one namespace each with the same functions:
// - ros1 (ros1_bag.cpp, ros1_serialization.cpp): ROS 1 bags v2.0 through rosbag_storage;
//   FormatError for v1.2 and other formats, truncated files, corrupt indexes and unknown
//   compression; ROS 1 serialization;
// - ros2 (ros2_bag.cpp, ros2_cdr.cpp): rosbag2 folders (metadata.yaml + sqlite3 .db3), or their
//   metadata.yaml or a .db3 in them; FormatError for .mcap storage (naming the conversion to
//   sqlite3), compressed bags and unreadable databases; CDR with Fast CDR.

#include <memory>
#include <string>

#include "vdtnav/ros/bag_reader.hpp"

#define VDTNAV_ROS_BAG_FORMAT_FUNCTIONS                                           \
  [[nodiscard]] std::unique_ptr<BagReader> open(const std::string& path);         \
  [[nodiscard]] LaserScanMsg decode_laser_scan(const BagMessage& m);              \
  [[nodiscard]] PointCloud2Msg decode_point_cloud2(const BagMessage& m);          \
  [[nodiscard]] OdometryMsg decode_odometry(const BagMessage& m);                 \
  [[nodiscard]] TfMsg decode_tf(const BagMessage& m);                             \
  [[nodiscard]] PoseStampedMsg decode_pose_stamped(const BagMessage& m);          \
  [[nodiscard]] PoseWithCovarianceStampedMsg decode_pose_with_covariance_stamped( \
      const BagMessage& m);                                                       \
  [[nodiscard]] ImuMsg decode_imu(const BagMessage& m);                           \
  [[nodiscard]] OccupancyGridMsg decode_occupancy_grid(const BagMessage& m);

namespace vdtnav::ros::ros1 {
VDTNAV_ROS_BAG_FORMAT_FUNCTIONS
}  // namespace vdtnav::ros::ros1

namespace vdtnav::ros::ros2 {
VDTNAV_ROS_BAG_FORMAT_FUNCTIONS
}  // namespace vdtnav::ros::ros2

#undef VDTNAV_ROS_BAG_FORMAT_FUNCTIONS
