// The messages of messages.hpp decoded from ROS 1 serialization by message_fields.hpp's layouts
// with a bounds-checked reader (ros::serialization resizes a sequence to whatever length the
// bytes claim before it checks them, gigabytes for a corrupt message).

#include <array>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "bag_formats.hpp"
#include "message_fields.hpp"
#include "ros1_time.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav::ros::ros1 {
namespace {

/// \brief "topic /scan, bag time 1684338971.720189000 s": where a message is, for errors.
std::string describe(const BagMessage& m) {
  std::ostringstream s;
  const std::int64_t sec = m.recorded_ns / 1000000000LL;
  std::int64_t nsec = m.recorded_ns % 1000000000LL;
  if (nsec < 0) nsec = -nsec;
  s << "topic " << m.topic << ", bag time " << sec << '.';
  s.width(9);
  s.fill('0');
  s << nsec << " s";
  return s.str();
}

/// \brief ROS 1 serialization (packed, little-endian; strings and sequences with a uint32
/// length) over a message's bytes, every read bounds-checked: a message cut short or a length
/// larger than the bytes left is a FormatError, before anything is allocated. The Io (reading)
/// of message_fields.hpp.
class Ros1Reader {
 public:
  static constexpr bool kWrites = false;

  explicit Ros1Reader(const BagMessage& m) : m_(m) {}

  template <typename T>
  void value(T& v) {
    std::memcpy(&v, take(sizeof(T), "a field"), sizeof(T));  // x86-64 and ARM: little-endian
  }
  /// bool: one byte, any nonzero true.
  void value(bool& v) {
    std::uint8_t b = 0;
    value(b);
    v = b != 0;
  }
  void str(std::string& s) {
    const std::size_t n = length(1, "a string");
    const std::uint8_t* p = take(n, "a string");
    s.assign(reinterpret_cast<const char*>(p), n);
  }
  /// time: uint32 sec, uint32 nsec.
  void time(std::int64_t& ns) {
    std::uint32_t sec = 0, nsec = 0;
    value(sec);
    value(nsec);
    ns = detail::to_ns(sec, nsec);
  }
  /// std_msgs/Header: uint32 seq (dropped), time stamp, string frame_id.
  void header(Header& h) {
    std::uint32_t seq = 0;
    value(seq);
    time(h.stamp_ns);
    str(h.frame_id);
  }
  std::size_t length(std::size_t min_element_bytes, const char* field) {
    std::uint32_t n = 0;
    value(n);
    if (static_cast<std::uint64_t>(n) * min_element_bytes > m_.data.size() - at_) {
      throw FormatError(describe(m_), 0,
                        std::string("expected ") + m_.type + ": " + field + " claims " +
                            std::to_string(n) + " elements, only " +
                            std::to_string(m_.data.size() - at_) + " bytes are left");
    }
    return n;
  }
  template <typename T>
  void size(std::vector<T>& out, std::size_t min_element_bytes, const char* field) {
    out.resize(length(min_element_bytes, field));
  }
  template <typename T>
  void sequence(std::vector<T>& out, const char* field) {
    out.resize(length(sizeof(T), field));
    if (!out.empty())
      std::memcpy(out.data(), take(out.size() * sizeof(T), field), out.size() * sizeof(T));
  }
  template <std::size_t N>
  void array(std::array<double, N>& out) {
    std::memcpy(out.data(), take(N * sizeof(double), "a fixed array"), N * sizeof(double));
  }

 private:
  const std::uint8_t* take(std::size_t n, const char* what) {
    if (n > m_.data.size() - at_) {
      throw FormatError(describe(m_), 0,
                        "expected " + m_.type + ": the " + std::to_string(m_.data.size()) +
                            " bytes end inside " + what);
    }
    const std::uint8_t* p = m_.data.data() + at_;
    at_ += n;
    return p;
  }
  const BagMessage& m_;
  std::size_t at_ = 0;
};

/// \brief Checks m's type and format, then decodes its fields (message_fields.hpp).
template <class Msg>
Msg decode_with(const BagMessage& m, const std::string& expected,
                void (*layout)(Ros1Reader&, Msg&)) {
  if (ros1_type_name(m.type) != expected) {
    throw FormatError(describe(m), 0, "expected " + expected + ", the topic holds " + m.type);
  }
  if (m.format != BagFormat::kRos1) {
    throw FormatError(describe(m), 0, "not a ROS 1 message (ROS 2 CDR bytes)");
  }
  Ros1Reader r(m);
  Msg msg;
  layout(r, msg);
  return msg;
}

}  // namespace

LaserScanMsg decode_laser_scan(const BagMessage& m) {
  return decode_with(m, "sensor_msgs/LaserScan", fields::laser_scan<Ros1Reader>);
}
PointCloud2Msg decode_point_cloud2(const BagMessage& m) {
  return decode_with(m, "sensor_msgs/PointCloud2", fields::point_cloud2<Ros1Reader>);
}
OdometryMsg decode_odometry(const BagMessage& m) {
  return decode_with(m, "nav_msgs/Odometry", fields::odometry<Ros1Reader>);
}
TfMsg decode_tf(const BagMessage& m) {
  return decode_with(m, "tf2_msgs/TFMessage", fields::tf<Ros1Reader>);
}
PoseStampedMsg decode_pose_stamped(const BagMessage& m) {
  return decode_with(m, "geometry_msgs/PoseStamped", fields::pose_stamped<Ros1Reader>);
}
PoseWithCovarianceStampedMsg decode_pose_with_covariance_stamped(const BagMessage& m) {
  return decode_with(m, "geometry_msgs/PoseWithCovarianceStamped",
                     fields::pose_with_covariance_stamped<Ros1Reader>);
}
ImuMsg decode_imu(const BagMessage& m) {
  return decode_with(m, "sensor_msgs/Imu", fields::imu<Ros1Reader>);
}
OccupancyGridMsg decode_occupancy_grid(const BagMessage& m) {
  return decode_with(m, "nav_msgs/OccupancyGrid", fields::occupancy_grid<Ros1Reader>);
}

}  // namespace vdtnav::ros::ros1
