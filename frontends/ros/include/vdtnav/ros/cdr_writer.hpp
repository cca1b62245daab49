#pragma once
/// \file
/// \brief The messages of messages.hpp serialized as ROS 2's default middleware does
/// (rmw_fastrtps, rosidl_typesupport_fastrtps): plain CDR (XCDR1), little-endian, behind the
/// 4-byte encapsulation header 0x00 0x01 0x00 0x00. Each primitive is aligned to its size
/// counted from the byte after that header (float64 to 8), with zero padding; a string is its
/// uint32 length counting the NUL, its bytes and the NUL; a sequence is its uint32 length and its
/// elements. These are the bytes a ROS 2 subscriber takes and rosbag2 records: as a BagMessage
/// of format kRos2 they decode with the decode_* functions of bag_reader.hpp.
///
/// std_msgs/Header's stamp becomes builtin_interfaces/Time {int32 sec, uint32 nanosec} by floor
/// division, as rclcpp converts a Time (-1 ns is sec -1, nanosec 999999999); sec wraps outside
/// int32 (after January 2038), as there.

#include <cstdint>
#include <vector>

#include "vdtnav/ros/messages.hpp"

namespace vdtnav::ros {

/// \brief sensor_msgs/msg/LaserScan as ROS 2 CDR.
[[nodiscard]] std::vector<std::uint8_t> encode_cdr(const LaserScanMsg& m);
/// \brief sensor_msgs/msg/PointCloud2 as ROS 2 CDR.
[[nodiscard]] std::vector<std::uint8_t> encode_cdr(const PointCloud2Msg& m);
/// \brief nav_msgs/msg/Odometry as ROS 2 CDR.
[[nodiscard]] std::vector<std::uint8_t> encode_cdr(const OdometryMsg& m);
/// \brief tf2_msgs/msg/TFMessage as ROS 2 CDR.
[[nodiscard]] std::vector<std::uint8_t> encode_cdr(const TfMsg& m);
/// \brief geometry_msgs/msg/PoseStamped as ROS 2 CDR.
[[nodiscard]] std::vector<std::uint8_t> encode_cdr(const PoseStampedMsg& m);
/// \brief geometry_msgs/msg/PoseWithCovarianceStamped as ROS 2 CDR.
[[nodiscard]] std::vector<std::uint8_t> encode_cdr(const PoseWithCovarianceStampedMsg& m);
/// \brief sensor_msgs/msg/Imu as ROS 2 CDR.
[[nodiscard]] std::vector<std::uint8_t> encode_cdr(const ImuMsg& m);
/// \brief nav_msgs/msg/OccupancyGrid as ROS 2 CDR.
[[nodiscard]] std::vector<std::uint8_t> encode_cdr(const OccupancyGridMsg& m);

}  // namespace vdtnav::ros
