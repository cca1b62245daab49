#pragma once
/// \file
/// \brief The messages of messages.hpp decoded from ROS 2 CDR bytes as a DDS sample carries them
/// (the 4-byte encapsulation header, then the message): the inverse of cdr_writer.hpp's
/// encode_cdr, for every type it encodes. The decode_* functions of bag_reader.hpp decode a ROS 2
/// bag's messages the same way, after checking the type the bag names.
///
/// Either endianness of plain CDR (00 00 big-endian, 00 01 little-endian) is read; alignment
/// counts from the byte after the header; the options bytes are not interpreted. Bytes after the
/// last field are ignored, such as the up to 3 bytes of padding an XTypes 1.3 writer (Cyclone
/// DDS) adds to reach a multiple of 4. A bool is true for any nonzero byte; an empty message's
/// placeholder byte (cdr_writer.hpp) is read and dropped, whatever its value. The bytes do not name
/// their type: the caller knows it from the topic or service (a sample of another type fails, or
/// decodes to nonsense).
///
/// Errors: bytes that do not hold the message (cut short, a parameter-list or XCDR2 encapsulation,
/// a sequence longer than the bytes left) throw FormatError(what, 0, "expected <ROS 2 type> in CDR
/// (<n> bytes): <detail>"), where what says where the bytes come from (a topic, a service) and n
/// is cdr.size(). A sequence's length is checked against the bytes left before anything is
/// allocated. *out is assigned only when the whole message decoded.

#include <cstdint>
#include <string>
#include <vector>

#include "vdtnav/ros/messages.hpp"

namespace vdtnav::ros {

/// \brief Decodes sensor_msgs/msg/LaserScan from ROS 2 CDR.
/// \param cdr the sample's bytes, encapsulation header first
/// \param out the message decoded (unchanged when this throws)
/// \param what where the bytes come from, for the FormatError (e.g. "topic /scan")
void decode_cdr(const std::vector<std::uint8_t>& cdr, LaserScanMsg* out, const std::string& what);
/// \brief Decodes sensor_msgs/msg/PointCloud2 from ROS 2 CDR (parameters as for LaserScanMsg).
void decode_cdr(const std::vector<std::uint8_t>& cdr, PointCloud2Msg* out, const std::string& what);
/// \brief Decodes nav_msgs/msg/Odometry from ROS 2 CDR.
void decode_cdr(const std::vector<std::uint8_t>& cdr, OdometryMsg* out, const std::string& what);
/// \brief Decodes tf2_msgs/msg/TFMessage from ROS 2 CDR.
void decode_cdr(const std::vector<std::uint8_t>& cdr, TfMsg* out, const std::string& what);
/// \brief Decodes geometry_msgs/msg/PoseStamped from ROS 2 CDR.
void decode_cdr(const std::vector<std::uint8_t>& cdr, PoseStampedMsg* out, const std::string& what);
/// \brief Decodes geometry_msgs/msg/PoseWithCovarianceStamped from ROS 2 CDR.
void decode_cdr(const std::vector<std::uint8_t>& cdr, PoseWithCovarianceStampedMsg* out,
                const std::string& what);
/// \brief Decodes sensor_msgs/msg/Imu from ROS 2 CDR.
void decode_cdr(const std::vector<std::uint8_t>& cdr, ImuMsg* out, const std::string& what);
/// \brief Decodes nav_msgs/msg/OccupancyGrid from ROS 2 CDR.
void decode_cdr(const std::vector<std::uint8_t>& cdr, OccupancyGridMsg* out,
                const std::string& what);
/// \brief Decodes lifecycle_msgs/msg/Transition from ROS 2 CDR.
void decode_cdr(const std::vector<std::uint8_t>& cdr, LifecycleTransitionMsg* out,
                const std::string& what);
/// \brief Decodes lifecycle_msgs/msg/State from ROS 2 CDR.
void decode_cdr(const std::vector<std::uint8_t>& cdr, LifecycleStateMsg* out,
                const std::string& what);
/// \brief Decodes lifecycle_msgs/srv/ChangeState_Request from ROS 2 CDR.
void decode_cdr(const std::vector<std::uint8_t>& cdr, ChangeStateRequestMsg* out,
                const std::string& what);
/// \brief Decodes lifecycle_msgs/srv/ChangeState_Response from ROS 2 CDR.
void decode_cdr(const std::vector<std::uint8_t>& cdr, ChangeStateResponseMsg* out,
                const std::string& what);
/// \brief Decodes lifecycle_msgs/srv/GetState_Response from ROS 2 CDR.
void decode_cdr(const std::vector<std::uint8_t>& cdr, GetStateResponseMsg* out,
                const std::string& what);
/// \brief Decodes lifecycle_msgs/msg/TransitionEvent from ROS 2 CDR.
void decode_cdr(const std::vector<std::uint8_t>& cdr, TransitionEventMsg* out,
                const std::string& what);
/// \brief Decodes bond/msg/Status from ROS 2 CDR.
void decode_cdr(const std::vector<std::uint8_t>& cdr, BondStatusMsg* out, const std::string& what);
/// \brief Decodes any empty message, request or response (GetState_Request, std_srvs/Empty's
/// request and response, SetInitialPose_Response) from ROS 2 CDR: checks the encapsulation and
/// the placeholder byte are there.
void decode_cdr(const std::vector<std::uint8_t>& cdr, EmptyMsg* out, const std::string& what);
/// \brief Decodes nav2_msgs/srv/SetInitialPose_Request from ROS 2 CDR.
void decode_cdr(const std::vector<std::uint8_t>& cdr, SetInitialPoseRequestMsg* out,
                const std::string& what);

}  // namespace vdtnav::ros
