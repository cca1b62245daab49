// ROS 2 messages (CDR, as rmw writes them into rosbag2) decoded into the ROS-free structs of
// messages.hpp with eProsima Fast CDR. The data starts with the 4-byte encapsulation header
// (0x00 0x00 big-endian CDR, 0x00 0x01 little-endian, then 2 option bytes); alignment counts
// from the byte after it. Field layouts follow the .msg definitions cited at each decoder.

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <fastcdr/exceptions/Exception.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "ros2_bag.hpp"
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

/// Fast CDR over a message's bytes, with sequence lengths checked against the bytes left.
class CdrReader {
 public:
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
  T get() {
    T v{};
    cdr_.deserialize(v);
    return v;
  }

  /// A CDR string: uint32 length counting the NUL, the bytes, the NUL (Fast CDR drops it and
  /// checks the length against the buffer).
  std::string str() {
    std::string s;
    cdr_.deserialize(s);
    return s;
  }

  /// A sequence's uint32 length, refused when min_element_bytes * length exceeds what is left
  /// (so a corrupt length cannot make us allocate gigabytes).
  std::size_t length(std::size_t min_element_bytes, const char* field) {
    const auto n = get<std::uint32_t>();
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

  /// float32[] / uint8[]: length then the elements.
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

  /// builtin_interfaces/msg/Time (int32 sec, uint32 nanosec) + string frame_id:
  /// std_msgs/msg/Header.
  Header header() {
    Header h;
    const auto sec = get<std::int32_t>();
    const auto nanosec = get<std::uint32_t>();
    h.stamp_ns = std::int64_t{sec} * 1000000000 + std::int64_t{nanosec};
    h.frame_id = str();
    return h;
  }

  /// geometry_msgs/msg/Vector3 or Point: float64 x, y, z.
  Eigen::Vector3d vector3() {
    Eigen::Vector3d v;
    v.x() = get<double>();
    v.y() = get<double>();
    v.z() = get<double>();
    return v;
  }

  /// geometry_msgs/msg/Quaternion: float64 x, y, z, w.
  Eigen::Quaterniond quaternion() {
    const double x = get<double>(), y = get<double>(), z = get<double>(), w = get<double>();
    return Eigen::Quaterniond(w, x, y, z);
  }

  /// geometry_msgs/msg/Pose: Point position, Quaternion orientation.
  PoseMsg pose() {
    PoseMsg p;
    p.position = vector3();
    p.orientation = quaternion();
    return p;
  }

  /// geometry_msgs/msg/PoseWithCovariance: Pose pose, float64[36] covariance.
  PoseWithCovarianceMsg pose_with_covariance() {
    PoseWithCovarianceMsg p;
    p.pose = pose();
    array(p.covariance);
    return p;
  }

 private:
  cdr::FastBuffer buffer_;
  cdr::Cdr cdr_;
  const BagMessage& m_;
};

/// Runs decode on a CdrReader of m, turning Fast CDR's exceptions (truncated data, a bad
/// encapsulation) into FormatError.
template <typename Decode>
auto decode_with(const BagMessage& m, const std::string& ros2_type, Decode decode) {
  expect_type(m, ros2_type);
  try {
    CdrReader r(m);
    return decode(r);
  } catch (const cdr::exception::Exception& e) {
    throw FormatError(where(m), 0,
                      "expected " + ros2_type + " in CDR (" + std::to_string(m.data.size()) +
                          " bytes): " + e.what());
  }
}

}  // namespace

// sensor_msgs/msg/LaserScan: Header header; float32 angle_min, angle_max, angle_increment,
// time_increment, scan_time, range_min, range_max; float32[] ranges; float32[] intensities.
LaserScanMsg decode_laser_scan(const BagMessage& m) {
  return decode_with(m, "sensor_msgs/msg/LaserScan", [](CdrReader& r) {
    LaserScanMsg s;
    s.header = r.header();
    s.angle_min = r.get<float>();
    s.angle_max = r.get<float>();
    s.angle_increment = r.get<float>();
    s.time_increment = r.get<float>();
    s.scan_time = r.get<float>();
    s.range_min = r.get<float>();
    s.range_max = r.get<float>();
    r.sequence(s.ranges, "ranges");
    r.sequence(s.intensities, "intensities");
    return s;
  });
}

// sensor_msgs/msg/PointCloud2: Header header; uint32 height, width; PointField[] fields;
// bool is_bigendian; uint32 point_step, row_step; uint8[] data; bool is_dense.
// sensor_msgs/msg/PointField: string name; uint32 offset; uint8 datatype; uint32 count.
PointCloud2Msg decode_point_cloud2(const BagMessage& m) {
  return decode_with(m, "sensor_msgs/msg/PointCloud2", [](CdrReader& r) {
    PointCloud2Msg c;
    c.header = r.header();
    c.height = r.get<std::uint32_t>();
    c.width = r.get<std::uint32_t>();
    // A PointField takes at least 13 bytes: name length, offset, datatype, count.
    c.fields.resize(r.length(13, "fields"));
    for (PointFieldMsg& f : c.fields) {
      f.name = r.str();
      f.offset = r.get<std::uint32_t>();
      f.datatype = r.get<std::uint8_t>();
      f.count = r.get<std::uint32_t>();
    }
    c.is_bigendian = r.get<bool>();
    c.point_step = r.get<std::uint32_t>();
    c.row_step = r.get<std::uint32_t>();
    r.sequence(c.data, "data");
    c.is_dense = r.get<bool>();
    return c;
  });
}

// nav_msgs/msg/Odometry: Header header; string child_frame_id;
// geometry_msgs/PoseWithCovariance pose; geometry_msgs/TwistWithCovariance twist
// (Twist twist {Vector3 linear, Vector3 angular}; float64[36] covariance).
OdometryMsg decode_odometry(const BagMessage& m) {
  return decode_with(m, "nav_msgs/msg/Odometry", [](CdrReader& r) {
    OdometryMsg o;
    o.header = r.header();
    o.child_frame_id = r.str();
    o.pose = r.pose_with_covariance();
    o.twist.linear = r.vector3();
    o.twist.angular = r.vector3();
    r.array(o.twist.covariance);
    return o;
  });
}

// tf2_msgs/msg/TFMessage: geometry_msgs/TransformStamped[] transforms.
// geometry_msgs/msg/TransformStamped: Header header; string child_frame_id;
// Transform transform {Vector3 translation; Quaternion rotation}.
TfMsg decode_tf(const BagMessage& m) {
  return decode_with(m, "tf2_msgs/msg/TFMessage", [](CdrReader& r) {
    TfMsg tf;
    // A TransformStamped takes at least 72 bytes: stamp 8, two string lengths 8, 7 float64.
    tf.transforms.resize(r.length(72, "transforms"));
    for (TransformStampedMsg& t : tf.transforms) {
      t.header = r.header();
      t.child_frame_id = r.str();
      t.translation = r.vector3();
      t.rotation = r.quaternion();
    }
    return tf;
  });
}

// geometry_msgs/msg/PoseStamped: Header header; Pose pose.
PoseStampedMsg decode_pose_stamped(const BagMessage& m) {
  return decode_with(m, "geometry_msgs/msg/PoseStamped", [](CdrReader& r) {
    PoseStampedMsg p;
    p.header = r.header();
    p.pose = r.pose();
    return p;
  });
}

// geometry_msgs/msg/PoseWithCovarianceStamped: Header header; PoseWithCovariance pose.
PoseWithCovarianceStampedMsg decode_pose_with_covariance_stamped(const BagMessage& m) {
  return decode_with(m, "geometry_msgs/msg/PoseWithCovarianceStamped", [](CdrReader& r) {
    PoseWithCovarianceStampedMsg p;
    p.header = r.header();
    p.pose = r.pose_with_covariance();
    return p;
  });
}

// sensor_msgs/msg/Imu: Header header; Quaternion orientation; float64[9] orientation_covariance;
// Vector3 angular_velocity; float64[9] angular_velocity_covariance; Vector3 linear_acceleration;
// float64[9] linear_acceleration_covariance.
ImuMsg decode_imu(const BagMessage& m) {
  return decode_with(m, "sensor_msgs/msg/Imu", [](CdrReader& r) {
    ImuMsg i;
    i.header = r.header();
    i.orientation = r.quaternion();
    r.array(i.orientation_covariance);
    i.angular_velocity = r.vector3();
    r.array(i.angular_velocity_covariance);
    i.linear_acceleration = r.vector3();
    r.array(i.linear_acceleration_covariance);
    return i;
  });
}

}  // namespace vdtnav::ros::ros2
