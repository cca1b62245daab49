// ROS 2 messages (CDR, as rmw writes them into rosbag2) decoded into the ROS-free structs of
// messages.hpp with eProsima Fast CDR. The data starts with the 4-byte encapsulation header
// (0x00 0x00 big-endian CDR, 0x00 0x01 little-endian, then 2 option bytes); alignment counts
// from the byte after it. The field layouts are message_fields.hpp's, shared with ROS 1.

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <fastcdr/exceptions/Exception.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bag_formats.hpp"
#include "message_fields.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav::ros::ros2 {
namespace {

namespace cdr = eprosima::fastcdr;

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

/// Fast CDR over a message's bytes, with sequence lengths checked against the bytes left: the Io
/// (reading) of message_fields.hpp.
class CdrReader {
 public:
  static constexpr bool kWrites = false;

  explicit CdrReader(const BagMessage& m)
      // Fast CDR takes a mutable buffer but only reads it when deserializing.
      : buffer_(const_cast<char*>(reinterpret_cast<const char*>(m.data.data())), m.data.size()),
        cdr_(buffer_, cdr::Cdr::DEFAULT_ENDIAN, cdr::Cdr::DDS_CDR),
        m_(m) {
    cdr_.read_encapsulation();  // sets the endianness the header names
    if (cdr_.getDDSCdrPlFlag() == cdr::Cdr::DDS_CDR_WITH_PL) {
      throw FormatError(where(m_), 0,
                        "expected plain CDR encapsulation (0x0000 or 0x0001), found a parameter "
                        "list");
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
      throw FormatError(where(m_), 0,
                        std::string("expected ") + m_.type + ": the sequence " + field +
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
  const BagMessage& m_;
};

/// Reads a Msg from m with its layout over a CdrReader, turning Fast CDR's exceptions (truncated
/// data, a bad encapsulation) into FormatError.
template <class Msg>
Msg decode_with(const BagMessage& m, const std::string& ros2_type,
                void (*layout)(CdrReader&, Msg&)) {
  expect_type(m, ros2_type);
  try {
    CdrReader r(m);
    Msg msg;
    layout(r, msg);
    return msg;
  } catch (const cdr::exception::Exception& e) {
    throw FormatError(where(m), 0,
                      "expected " + ros2_type + " in CDR (" + std::to_string(m.data.size()) +
                          " bytes): " + e.what());
  }
}

}  // namespace

// The layouts: message_fields.hpp (the same for ROS 1 and ROS 2).
LaserScanMsg decode_laser_scan(const BagMessage& m) {
  return decode_with(m, "sensor_msgs/msg/LaserScan", fields::laser_scan<CdrReader>);
}
PointCloud2Msg decode_point_cloud2(const BagMessage& m) {
  return decode_with(m, "sensor_msgs/msg/PointCloud2", fields::point_cloud2<CdrReader>);
}
OdometryMsg decode_odometry(const BagMessage& m) {
  return decode_with(m, "nav_msgs/msg/Odometry", fields::odometry<CdrReader>);
}
TfMsg decode_tf(const BagMessage& m) {
  return decode_with(m, "tf2_msgs/msg/TFMessage", fields::tf<CdrReader>);
}
PoseStampedMsg decode_pose_stamped(const BagMessage& m) {
  return decode_with(m, "geometry_msgs/msg/PoseStamped", fields::pose_stamped<CdrReader>);
}
PoseWithCovarianceStampedMsg decode_pose_with_covariance_stamped(const BagMessage& m) {
  return decode_with(m, "geometry_msgs/msg/PoseWithCovarianceStamped",
                     fields::pose_with_covariance_stamped<CdrReader>);
}
ImuMsg decode_imu(const BagMessage& m) {
  return decode_with(m, "sensor_msgs/msg/Imu", fields::imu<CdrReader>);
}
OccupancyGridMsg decode_occupancy_grid(const BagMessage& m) {
  return decode_with(m, "nav_msgs/msg/OccupancyGrid", fields::occupancy_grid<CdrReader>);
}

}  // namespace vdtnav::ros::ros2
