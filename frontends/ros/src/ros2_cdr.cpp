// ROS 2 messages (CDR, as rmw writes them into rosbag2 and DDS samples carry them) decoded into
// the ROS-free structs of messages.hpp with eProsima Fast CDR: from bytes (decode_cdr,
// cdr_reader.hpp) and, through the same path, from a bag's messages (decode_*, bag_reader.hpp).
// The data starts with the 4-byte encapsulation header (0x00 0x00 big-endian CDR, 0x00 0x01
// little-endian, then 2 option bytes); alignment counts from the byte after it. The field
// layouts are message_fields.hpp's, shared with ROS 1.

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <fastcdr/exceptions/Exception.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "bag_formats.hpp"
#include "message_fields.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/ros/cdr_reader.hpp"

namespace vdtnav::ros {
namespace {

namespace cdr = eprosima::fastcdr;

// The ROS 2 types, named once for decode_cdr and the bag's decoders.
constexpr char kLaserScan[] = "sensor_msgs/msg/LaserScan";
constexpr char kPointCloud2[] = "sensor_msgs/msg/PointCloud2";
constexpr char kOdometry[] = "nav_msgs/msg/Odometry";
constexpr char kTf[] = "tf2_msgs/msg/TFMessage";
constexpr char kPoseStamped[] = "geometry_msgs/msg/PoseStamped";
constexpr char kPoseWithCovarianceStamped[] = "geometry_msgs/msg/PoseWithCovarianceStamped";
constexpr char kImu[] = "sensor_msgs/msg/Imu";
constexpr char kOccupancyGrid[] = "nav_msgs/msg/OccupancyGrid";

/// "expected <ros2_type> in CDR (<n> bytes): ", the start of every error about bytes.
std::string expected(const char* ros2_type, std::size_t n) {
  return std::string("expected ") + ros2_type + " in CDR (" + std::to_string(n) + " bytes): ";
}

/// Fast CDR over a message's bytes, with sequence lengths checked against the bytes left: the Io
/// (reading) of message_fields.hpp. what and ros2_type name the bytes in errors.
class CdrReader {
 public:
  static constexpr bool kWrites = false;

  CdrReader(const std::vector<std::uint8_t>& bytes, const std::string& what, const char* ros2_type)
      // Fast CDR takes a mutable buffer but only reads it when deserializing.
      : buffer_(const_cast<char*>(reinterpret_cast<const char*>(bytes.data())), bytes.size()),
        cdr_(buffer_, cdr::Cdr::DEFAULT_ENDIAN, cdr::Cdr::DDS_CDR),
        what_(what),
        ros2_type_(ros2_type) {
    cdr_.read_encapsulation();  // sets the endianness the header names
    if (cdr_.getDDSCdrPlFlag() == cdr::Cdr::DDS_CDR_WITH_PL) {
      throw FormatError(what_, 0,
                        expected(ros2_type_, buffer_.getBufferSize()) +
                            "a parameter-list encapsulation, not plain CDR (00 00 or 00 01)");
    }
  }

  template <typename T>
  void value(T& v) {
    cdr_.deserialize(v);
  }
  /// bool: one byte, any nonzero true (Fast CDR would refuse all but 0 and 1).
  void value(bool& v) {
    std::uint8_t b = 0;
    cdr_.deserialize(b);
    v = b != 0;
  }

  /// A CDR string: uint32 length counting the NUL, the bytes, the NUL (Fast CDR drops it and
  /// checks the length against the buffer).
  void str(std::string& s) { cdr_.deserialize(s); }

  /// A sequence's uint32 length, refused when min_element_bytes * length exceeds what is left
  /// (so a corrupt length cannot make us allocate gigabytes).
  std::size_t length(std::size_t min_element_bytes, const char* field) {
    std::uint32_t n = 0;
    value(n);
    const std::size_t left =
        buffer_.getBufferSize() -
        static_cast<std::size_t>(cdr_.getCurrentPosition() - cdr_.getBufferPointer());
    if (static_cast<std::uint64_t>(n) * min_element_bytes > left) {
      throw FormatError(what_, 0,
                        expected(ros2_type_, buffer_.getBufferSize()) + "the sequence " + field +
                            " claims " + std::to_string(n) + " elements, only " +
                            std::to_string(left) + " bytes are left");
    }
    return n;
  }

  /// A sequence of messages: its length (the caller reads the elements).
  template <typename T>
  void size(std::vector<T>& out, std::size_t min_element_bytes, const char* field) {
    out.resize(length(min_element_bytes, field));
  }

  /// float32[] / uint8[] / int8[]: length then the elements.
  template <typename T>
  void sequence(std::vector<T>& out, const char* field) {
    out.resize(length(sizeof(T), field));
    if (!out.empty()) cdr_.deserializeArray(out.data(), out.size());
  }

  /// float64[N]: a fixed array, no length.
  template <std::size_t N>
  void array(std::array<double, N>& out) {
    cdr_.deserializeArray(out.data(), N);
  }

  /// builtin_interfaces/msg/Time: int32 sec, uint32 nanosec.
  void time(std::int64_t& ns) {
    std::int32_t sec = 0;
    std::uint32_t nanosec = 0;
    value(sec);
    value(nanosec);
    ns = std::int64_t{sec} * 1000000000 + std::int64_t{nanosec};
  }

  /// std_msgs/msg/Header: builtin_interfaces/msg/Time stamp; string frame_id.
  void header(Header& h) {
    time(h.stamp_ns);
    str(h.frame_id);
  }

 private:
  cdr::FastBuffer buffer_;
  cdr::Cdr cdr_;
  const std::string& what_;
  const char* ros2_type_;
};

/// Reads a Msg from bytes with its layout over a CdrReader into *out (only when all of it
/// decoded), turning Fast CDR's exceptions (truncated data, a bad encapsulation) into
/// FormatError.
template <class Msg>
void decode_with(const std::vector<std::uint8_t>& bytes, const std::string& what,
                 const char* ros2_type, void (*layout)(CdrReader&, Msg&), Msg* out) {
  VDTNAV_ASSERT(out != nullptr);
  try {
    CdrReader r(bytes, what, ros2_type);
    Msg msg;
    layout(r, msg);
    *out = std::move(msg);
  } catch (const cdr::exception::Exception& e) {
    throw FormatError(what, 0, expected(ros2_type, bytes.size()) + e.what());
  }
}

}  // namespace

// The layouts: message_fields.hpp (the same for ROS 1 and ROS 2).
void decode_cdr(const std::vector<std::uint8_t>& cdr, LaserScanMsg* out, const std::string& what) {
  decode_with(cdr, what, kLaserScan, fields::laser_scan<CdrReader>, out);
}
void decode_cdr(const std::vector<std::uint8_t>& cdr, PointCloud2Msg* out,
                const std::string& what) {
  decode_with(cdr, what, kPointCloud2, fields::point_cloud2<CdrReader>, out);
}
void decode_cdr(const std::vector<std::uint8_t>& cdr, OdometryMsg* out, const std::string& what) {
  decode_with(cdr, what, kOdometry, fields::odometry<CdrReader>, out);
}
void decode_cdr(const std::vector<std::uint8_t>& cdr, TfMsg* out, const std::string& what) {
  decode_with(cdr, what, kTf, fields::tf<CdrReader>, out);
}
void decode_cdr(const std::vector<std::uint8_t>& cdr, PoseStampedMsg* out,
                const std::string& what) {
  decode_with(cdr, what, kPoseStamped, fields::pose_stamped<CdrReader>, out);
}
void decode_cdr(const std::vector<std::uint8_t>& cdr, PoseWithCovarianceStampedMsg* out,
                const std::string& what) {
  decode_with(cdr, what, kPoseWithCovarianceStamped,
              fields::pose_with_covariance_stamped<CdrReader>, out);
}
void decode_cdr(const std::vector<std::uint8_t>& cdr, ImuMsg* out, const std::string& what) {
  decode_with(cdr, what, kImu, fields::imu<CdrReader>, out);
}
void decode_cdr(const std::vector<std::uint8_t>& cdr, OccupancyGridMsg* out,
                const std::string& what) {
  decode_with(cdr, what, kOccupancyGrid, fields::occupancy_grid<CdrReader>, out);
}
void decode_cdr(const std::vector<std::uint8_t>& cdr, LifecycleTransitionMsg* out,
                const std::string& what) {
  decode_with(cdr, what, "lifecycle_msgs/msg/Transition", fields::lifecycle_transition<CdrReader>,
              out);
}
void decode_cdr(const std::vector<std::uint8_t>& cdr, LifecycleStateMsg* out,
                const std::string& what) {
  decode_with(cdr, what, "lifecycle_msgs/msg/State", fields::lifecycle_state<CdrReader>, out);
}
void decode_cdr(const std::vector<std::uint8_t>& cdr, ChangeStateRequestMsg* out,
                const std::string& what) {
  decode_with(cdr, what, "lifecycle_msgs/srv/ChangeState_Request",
              fields::change_state_request<CdrReader>, out);
}
void decode_cdr(const std::vector<std::uint8_t>& cdr, ChangeStateResponseMsg* out,
                const std::string& what) {
  decode_with(cdr, what, "lifecycle_msgs/srv/ChangeState_Response",
              fields::change_state_response<CdrReader>, out);
}
void decode_cdr(const std::vector<std::uint8_t>& cdr, GetStateResponseMsg* out,
                const std::string& what) {
  decode_with(cdr, what, "lifecycle_msgs/srv/GetState_Response",
              fields::get_state_response<CdrReader>, out);
}
void decode_cdr(const std::vector<std::uint8_t>& cdr, TransitionEventMsg* out,
                const std::string& what) {
  decode_with(cdr, what, "lifecycle_msgs/msg/TransitionEvent", fields::transition_event<CdrReader>,
              out);
}
void decode_cdr(const std::vector<std::uint8_t>& cdr, BondStatusMsg* out, const std::string& what) {
  decode_with(cdr, what, "bond/msg/Status", fields::bond_status<CdrReader>, out);
}
void decode_cdr(const std::vector<std::uint8_t>& cdr, EmptyMsg* out, const std::string& what) {
  // One name for the several empty types (GetState_Request, std_srvs/Empty_*, ...).
  decode_with(cdr, what, "an empty message (one uint8 placeholder)", fields::empty<CdrReader>, out);
}
void decode_cdr(const std::vector<std::uint8_t>& cdr, SetInitialPoseRequestMsg* out,
                const std::string& what) {
  decode_with(cdr, what, "nav2_msgs/srv/SetInitialPose_Request",
              fields::set_initial_pose_request<CdrReader>, out);
}

namespace ros2 {
namespace {

/// "topic at sec.nsec" for error messages: where in the bag the message lies.
std::string where(const BagMessage& m) {
  const std::int64_t sec = m.recorded_ns / 1000000000;
  std::string nsec = std::to_string(m.recorded_ns % 1000000000);
  if (nsec.size() < 9) nsec.insert(0, 9 - nsec.size(), '0');
  return "topic " + m.topic + " at bag time " + std::to_string(sec) + "." + nsec + " s";
}

/// Throws unless m is of type ros2_type (compared in ROS 1 spelling, so either spelling passes).
void expect_type(const BagMessage& m, const std::string& ros2_type) {
  if (ros1_type_name(m.type) != ros1_type_name(ros2_type)) {
    throw FormatError(where(m), 0, "expected " + ros2_type + ", the topic holds " + m.type);
  }
}

/// A bag's message: its type checked, then its bytes decoded as decode_cdr does.
template <class Msg>
Msg from_bag(const BagMessage& m, const char* ros2_type) {
  expect_type(m, ros2_type);
  Msg msg;
  decode_cdr(m.data, &msg, where(m));
  return msg;
}

}  // namespace

LaserScanMsg decode_laser_scan(const BagMessage& m) {
  return from_bag<LaserScanMsg>(m, kLaserScan);
}
PointCloud2Msg decode_point_cloud2(const BagMessage& m) {
  return from_bag<PointCloud2Msg>(m, kPointCloud2);
}
OdometryMsg decode_odometry(const BagMessage& m) { return from_bag<OdometryMsg>(m, kOdometry); }
TfMsg decode_tf(const BagMessage& m) { return from_bag<TfMsg>(m, kTf); }
PoseStampedMsg decode_pose_stamped(const BagMessage& m) {
  return from_bag<PoseStampedMsg>(m, kPoseStamped);
}
PoseWithCovarianceStampedMsg decode_pose_with_covariance_stamped(const BagMessage& m) {
  return from_bag<PoseWithCovarianceStampedMsg>(m, kPoseWithCovarianceStamped);
}
ImuMsg decode_imu(const BagMessage& m) { return from_bag<ImuMsg>(m, kImu); }
OccupancyGridMsg decode_occupancy_grid(const BagMessage& m) {
  return from_bag<OccupancyGridMsg>(m, kOccupancyGrid);
}

}  // namespace ros2
}  // namespace vdtnav::ros
