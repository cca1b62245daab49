#pragma once
/// \file
/// \brief The messages of messages.hpp serialized as ROS 2's default middleware does
/// (rmw_fastrtps, rosidl_typesupport_fastrtps): plain CDR (XCDR1), little-endian, behind the
/// 4-byte encapsulation header 0x00 0x01 0x00 0x00. Each primitive is aligned to its size
/// counted from the byte after that header (float64 to 8), with zero padding; a string is its
/// uint32 length counting the NUL, its bytes and the NUL; a sequence is its uint32 length and its
/// elements. These are the bytes a ROS 2 subscriber takes and rosbag2 records: as a BagMessage
/// of format kRos2 they decode with the decode_* functions of bag_reader.hpp, as bytes with
/// decode_cdr (cdr_reader.hpp).
///
/// The message ends on its last field: no padding after it and the options bytes 00 00, as
/// rmw_fastrtps sends it (its payload length is Fast CDR's serialized length). A message,
/// request or response without fields (EmptyMsg) is the one byte of rosidl's placeholder member
/// `uint8 structure_needs_at_least_one_member`: 00 01 00 00 00. A service's request or response
/// is its struct alone; rmw_fastrtps carries the request's id beside the payload (the sample's
/// identity), not in it.
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
/// \brief lifecycle_msgs/msg/Transition as ROS 2 CDR.
[[nodiscard]] std::vector<std::uint8_t> encode_cdr(const LifecycleTransitionMsg& m);
/// \brief lifecycle_msgs/msg/State as ROS 2 CDR.
[[nodiscard]] std::vector<std::uint8_t> encode_cdr(const LifecycleStateMsg& m);
/// \brief lifecycle_msgs/srv/ChangeState_Request as ROS 2 CDR.
[[nodiscard]] std::vector<std::uint8_t> encode_cdr(const ChangeStateRequestMsg& m);
/// \brief lifecycle_msgs/srv/ChangeState_Response as ROS 2 CDR.
[[nodiscard]] std::vector<std::uint8_t> encode_cdr(const ChangeStateResponseMsg& m);
/// \brief lifecycle_msgs/srv/GetState_Response as ROS 2 CDR.
[[nodiscard]] std::vector<std::uint8_t> encode_cdr(const GetStateResponseMsg& m);
/// \brief lifecycle_msgs/msg/TransitionEvent as ROS 2 CDR.
[[nodiscard]] std::vector<std::uint8_t> encode_cdr(const TransitionEventMsg& m);
/// \brief bond/msg/Status as ROS 2 CDR.
[[nodiscard]] std::vector<std::uint8_t> encode_cdr(const BondStatusMsg& m);
/// \brief Any empty message, request or response (lifecycle_msgs/srv/GetState_Request,
/// std_srvs/srv/Empty_Request and _Response, nav2_msgs/srv/SetInitialPose_Response) as ROS 2
/// CDR: always 00 01 00 00 00.
[[nodiscard]] std::vector<std::uint8_t> encode_cdr(const EmptyMsg& m);
/// \brief nav2_msgs/srv/SetInitialPose_Request as ROS 2 CDR (the bytes of its
/// PoseWithCovarianceStamped).
[[nodiscard]] std::vector<std::uint8_t> encode_cdr(const SetInitialPoseRequestMsg& m);

}  // namespace vdtnav::ros
