// The ROS 2 CDR encoders (cdr_writer.hpp) against CDR written by a ROS 2 system: every /scan,
// /tf, /tf_static and /odom message of the shared olin TurtleBot 4 bag (rmw_fastrtps) decoded
// and encoded again gives back the recorded bytes, all of them, padding included. No position is
// masked: the recorder's padding is all zero (python oracle: the 2232 messages parsed with
// struct.unpack following the .msg definitions hold 18218 padding bytes, none nonzero; every
// message ends on its last field; the options bytes are 00 00). Then encode -> decode round trips
// for the messages the bag does not hold, one OccupancyGrid laid out by hand byte by byte (an
// oracle for the alignment rules independent of both Fast CDR and the writer), and
// nav_msgs/OccupancyGrid decoded from ROS 1 serialization built by hand.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros/cdr_writer.hpp"

namespace {

namespace fs = std::filesystem;
using vdtnav::FormatError;
using vdtnav::ros::BagFormat;
using vdtnav::ros::BagMessage;
using vdtnav::ros::BagReader;
using vdtnav::ros::encode_cdr;
using vdtnav::ros::Header;
using vdtnav::ros::ImuMsg;
using vdtnav::ros::OccupancyGridMsg;
using vdtnav::ros::PointCloud2Msg;
using vdtnav::ros::PoseMsg;
using vdtnav::ros::PoseStampedMsg;
using vdtnav::ros::PoseWithCovarianceStampedMsg;
using Bytes = std::vector<std::uint8_t>;

const fs::path kBag = fs::path(VDTNAV_DATA_DIR) / "rosbags/olin-tb4-ros2/macfirst_floor_take_2";
const fs::path kDb3 = kBag / "macfirst_floor_take_2_0.db3";

#define REQUIRE_BAG()                                                     \
  do {                                                                    \
    if (!fs::exists(kDb3)) GTEST_SKIP() << "no bag at " << kBag.string(); \
  } while (false)

/// "equal" or the first offset where a and b differ, with both bytes there.
std::string difference(const Bytes& a, const Bytes& b) {
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    if (a[i] != b[i]) {
      return "first difference at byte " + std::to_string(i) + ": " + std::to_string(a[i]) +
             " vs " + std::to_string(b[i]);
    }
  }
  return a.size() == b.size()
             ? "equal"
             : "sizes " + std::to_string(a.size()) + " and " + std::to_string(b.size());
}

/// bytes as a ROS 2 bag message of the given type, for the decoders.
BagMessage as_ros2(const std::string& type, Bytes bytes) {
  BagMessage m;
  m.format = BagFormat::kRos2;
  m.topic = "/encoded";
  m.type = type;
  m.recorded_ns = 1;
  m.data = std::move(bytes);
  return m;
}

// ---- the recorded bag: decode, encode, the same bytes
// ----------------------------------------------------

TEST(CdrWriter, EveryRecordedMessageEncodesToItsRecordedBytes) {
  REQUIRE_BAG();
  namespace r = vdtnav::ros;
  const std::map<std::string, std::function<Bytes(const BagMessage&)>> reencode = {
      {"/scan", [](const BagMessage& m) { return encode_cdr(r::decode_laser_scan(m)); }},
      {"/tf", [](const BagMessage& m) { return encode_cdr(r::decode_tf(m)); }},
      {"/tf_static", [](const BagMessage& m) { return encode_cdr(r::decode_tf(m)); }},
      {"/odom", [](const BagMessage& m) { return encode_cdr(r::decode_odometry(m)); }},
  };
  std::map<std::string, std::size_t> compared, equal;
  const auto bag = BagReader::open(kBag.string());
  bag->read({"/scan", "/tf", "/tf_static", "/odom"}, [&](const BagMessage& m) {
    const Bytes again = reencode.at(m.topic)(m);
    ++compared[m.topic];
    if (again == m.data) {
      ++equal[m.topic];
    } else if (compared[m.topic] - equal[m.topic] <= 3) {  // the first few of a topic, not all
      ADD_FAILURE() << m.topic << " #" << compared[m.topic] << ": " << difference(again, m.data);
    }
    return true;
  });
  // Counts: metadata.yaml (2232 messages in all).
  const std::map<std::string, std::size_t> expected = {
      {"/odom", 920}, {"/scan", 357}, {"/tf", 953}, {"/tf_static", 2}};
  EXPECT_EQ(compared, expected);
  EXPECT_EQ(equal, expected);
}

// ---- encode -> decode
// ---------------------------------------------------------------------------------

void expect_same(const Header& a, const Header& b) {
  EXPECT_EQ(a.stamp_ns, b.stamp_ns);
  EXPECT_EQ(a.frame_id, b.frame_id);
}

void expect_same(const PoseMsg& a, const PoseMsg& b) {
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.orientation.coeffs(), b.orientation.coeffs());
}

PoseMsg a_pose(double k) {
  PoseMsg p;
  p.position = Eigen::Vector3d(1.5 * k, -2.25 * k, 0.125 * k);
  p.orientation = Eigen::Quaterniond(0.8, 0.0, -0.6, 0.0);  // w, x, y, z
  return p;
}

template <std::size_t N>
std::array<double, N> counting(double from) {
  std::array<double, N> a{};
  for (std::size_t i = 0; i < N; ++i) a[i] = from + 0.5 * static_cast<double>(i);
  return a;
}

// Frames of odd lengths put the next field off its alignment; the stamps are negative (before
// 1970, floor division: sec -2, nanosec 999999999 for -1000000001 ns) or exactly on a second.
const std::vector<Header> kHeaders = {
    {-1000000001, "base_laser"}, {-1, ""}, {0, "map"}, {1663967375548411329, "odom_"}};

TEST(CdrWriter, PointCloud2RoundTrips) {
  for (const Header& h : kHeaders) {
    for (const bool empty : {true, false}) {
      SCOPED_TRACE(h.frame_id + (empty ? " empty" : " two points"));
      PointCloud2Msg c;
      c.header = h;
      if (!empty) {
        c.height = 1;
        c.width = 2;
        // Names of 2, 10 and 5 bytes with the NUL: offset's uint32 lands unaligned each time.
        c.fields = {{"x", 0, 7, 1}, {"intensity", 4, 7, 1}, {"ring", 8, 4, 1}};
        c.point_step = 10;
        c.row_step = 20;
        for (std::uint8_t i = 0; i < 19; ++i) c.data.push_back(static_cast<std::uint8_t>(3 * i));
        c.is_dense = true;
      }
      c.is_bigendian = empty;
      const PointCloud2Msg d =
          vdtnav::ros::decode_point_cloud2(as_ros2("sensor_msgs/msg/PointCloud2", encode_cdr(c)));
      expect_same(d.header, c.header);
      EXPECT_EQ(d.height, c.height);
      EXPECT_EQ(d.width, c.width);
      ASSERT_EQ(d.fields.size(), c.fields.size());
      for (std::size_t i = 0; i < c.fields.size(); ++i) {
        EXPECT_EQ(d.fields[i].name, c.fields[i].name);
        EXPECT_EQ(d.fields[i].offset, c.fields[i].offset);
        EXPECT_EQ(d.fields[i].datatype, c.fields[i].datatype);
        EXPECT_EQ(d.fields[i].count, c.fields[i].count);
      }
      EXPECT_EQ(d.is_bigendian, c.is_bigendian);
      EXPECT_EQ(d.point_step, c.point_step);
      EXPECT_EQ(d.row_step, c.row_step);
      EXPECT_EQ(d.data, c.data);
      EXPECT_EQ(d.is_dense, c.is_dense);
    }
  }
}

TEST(CdrWriter, ImuRoundTrips) {
  for (const Header& h : kHeaders) {
    SCOPED_TRACE(h.frame_id);
    ImuMsg i;
    i.header = h;
    i.orientation = Eigen::Quaterniond(0.0, 0.6, 0.0, -0.8);
    i.orientation_covariance = counting<9>(-1.0);
    i.angular_velocity = Eigen::Vector3d(0.1, -0.2, 0.3);
    i.angular_velocity_covariance = counting<9>(10.0);
    i.linear_acceleration = Eigen::Vector3d(0.0, -0.0, 9.81);
    i.linear_acceleration_covariance = counting<9>(20.0);
    const ImuMsg d = vdtnav::ros::decode_imu(as_ros2("sensor_msgs/msg/Imu", encode_cdr(i)));
    expect_same(d.header, i.header);
    EXPECT_EQ(d.orientation.coeffs(), i.orientation.coeffs());
    EXPECT_EQ(d.orientation_covariance, i.orientation_covariance);
    EXPECT_EQ(d.angular_velocity, i.angular_velocity);
    EXPECT_EQ(d.angular_velocity_covariance, i.angular_velocity_covariance);
    EXPECT_EQ(d.linear_acceleration, i.linear_acceleration);
    EXPECT_TRUE(std::signbit(d.linear_acceleration.y()));  // -0.0 travels as written
    EXPECT_EQ(d.linear_acceleration_covariance, i.linear_acceleration_covariance);
  }
}

TEST(CdrWriter, PoseStampedAndPoseWithCovarianceStampedRoundTrip) {
  double k = 1.0;
  for (const Header& h : kHeaders) {
    SCOPED_TRACE(h.frame_id);
    k *= -3.0;
    PoseStampedMsg p;
    p.header = h;
    p.pose = a_pose(k);
    const PoseStampedMsg dp =
        vdtnav::ros::decode_pose_stamped(as_ros2("geometry_msgs/msg/PoseStamped", encode_cdr(p)));
    expect_same(dp.header, p.header);
    expect_same(dp.pose, p.pose);

    PoseWithCovarianceStampedMsg c;
    c.header = h;
    c.pose.pose = a_pose(-k);
    c.pose.covariance = counting<36>(-9.0);
    c.pose.covariance[35] = std::numeric_limits<double>::infinity();
    const PoseWithCovarianceStampedMsg dc = vdtnav::ros::decode_pose_with_covariance_stamped(
        as_ros2("geometry_msgs/msg/PoseWithCovarianceStamped", encode_cdr(c)));
    expect_same(dc.header, c.header);
    expect_same(dc.pose.pose, c.pose.pose);
    EXPECT_EQ(dc.pose.covariance, c.pose.covariance);
  }
}

TEST(CdrWriter, OccupancyGridRoundTrips) {
  for (const Header& h : kHeaders) {
    for (const bool empty : {true, false}) {
      SCOPED_TRACE(h.frame_id + (empty ? " empty" : " 5 x 3"));
      OccupancyGridMsg g;
      g.header = h;
      g.info.map_load_time_ns = -h.stamp_ns - 7;
      g.info.resolution = 0.05F;
      g.info.width = empty ? 0 : 5;
      g.info.height = empty ? 0 : 3;
      g.info.origin = a_pose(-4.0);
      for (int i = 0; i < static_cast<int>(g.info.width * g.info.height); ++i) {
        g.data.push_back(static_cast<std::int8_t>(i % 3 == 0 ? -1 : 7 * i));
      }
      const OccupancyGridMsg d =
          vdtnav::ros::decode_occupancy_grid(as_ros2("nav_msgs/msg/OccupancyGrid", encode_cdr(g)));
      expect_same(d.header, g.header);
      EXPECT_EQ(d.info.map_load_time_ns, g.info.map_load_time_ns);
      EXPECT_EQ(d.info.resolution, g.info.resolution);
      EXPECT_EQ(d.info.width, g.info.width);
      EXPECT_EQ(d.info.height, g.info.height);
      expect_same(d.info.origin, g.info.origin);
      EXPECT_EQ(d.data, g.data);
    }
  }
}

TEST(CdrWriter, LaserScanOdometryAndTfRoundTripEmptyOrOdd) {
  // The bag's messages cover the usual shapes; here empty sequences and odd frames.
  vdtnav::ros::LaserScanMsg s;
  s.header = kHeaders[0];
  s.ranges = {1.0F, std::numeric_limits<float>::infinity(), 0.5F};
  const auto ds =
      vdtnav::ros::decode_laser_scan(as_ros2("sensor_msgs/msg/LaserScan", encode_cdr(s)));
  expect_same(ds.header, s.header);
  EXPECT_EQ(ds.ranges, s.ranges);
  EXPECT_TRUE(ds.intensities.empty());

  vdtnav::ros::OdometryMsg o;
  o.header = kHeaders[1];
  o.child_frame_id = "base_footprint";
  o.pose.pose = a_pose(2.0);
  o.pose.covariance = counting<36>(1.0);
  o.twist.linear = Eigen::Vector3d(0.3, 0.0, 0.0);
  o.twist.angular = Eigen::Vector3d(0.0, 0.0, -0.7);
  o.twist.covariance = counting<36>(-1.0);
  const auto d_o = vdtnav::ros::decode_odometry(as_ros2("nav_msgs/msg/Odometry", encode_cdr(o)));
  expect_same(d_o.header, o.header);
  EXPECT_EQ(d_o.child_frame_id, o.child_frame_id);
  expect_same(d_o.pose.pose, o.pose.pose);
  EXPECT_EQ(d_o.pose.covariance, o.pose.covariance);
  EXPECT_EQ(d_o.twist.linear, o.twist.linear);
  EXPECT_EQ(d_o.twist.angular, o.twist.angular);
  EXPECT_EQ(d_o.twist.covariance, o.twist.covariance);

  vdtnav::ros::TfMsg tf;
  EXPECT_TRUE(
      vdtnav::ros::decode_tf(as_ros2("tf2_msgs/msg/TFMessage", encode_cdr(tf))).transforms.empty());
  for (const Header& h : kHeaders) {
    vdtnav::ros::TransformStampedMsg t;
    t.header = h;
    t.child_frame_id = h.frame_id + "_child";
    t.translation = a_pose(static_cast<double>(h.frame_id.size())).position;
    t.rotation = a_pose(1.0).orientation;
    tf.transforms.push_back(t);
  }
  const auto dtf = vdtnav::ros::decode_tf(as_ros2("tf2_msgs/msg/TFMessage", encode_cdr(tf)));
  ASSERT_EQ(dtf.transforms.size(), tf.transforms.size());
  for (std::size_t i = 0; i < tf.transforms.size(); ++i) {
    expect_same(dtf.transforms[i].header, tf.transforms[i].header);
    EXPECT_EQ(dtf.transforms[i].child_frame_id, tf.transforms[i].child_frame_id);
    EXPECT_EQ(dtf.transforms[i].translation, tf.transforms[i].translation);
    EXPECT_EQ(dtf.transforms[i].rotation.coeffs(), tf.transforms[i].rotation.coeffs());
  }
}

// ---- one message laid out by hand
// ---------------------------------------------------------------------

TEST(CdrWriter, OccupancyGridByteByByte) {
  OccupancyGridMsg g;
  g.header = {-1500000000, "map"};  // -1.5 s
  g.info.map_load_time_ns = 1;
  g.info.resolution = 0.05F;
  g.info.width = 3;
  g.info.height = 1;
  g.info.origin.position = Eigen::Vector3d(-10.0, 2.5, 0.0);
  g.info.origin.orientation = Eigen::Quaterniond(0.0, 0.0, 0.0, 1.0);  // w, x, y, z: yaw 180 deg
  g.data = {-1, 0, 100};
  // Offsets count from the byte after the encapsulation (body offset = index - 4).
  const Bytes expected = {
      0x00, 0x01, 0x00, 0x00,                          // encapsulation: CDR little-endian
      0xfe, 0xff, 0xff, 0xff,                          // body 0: stamp.sec = -2 (floor)
      0x00, 0x65, 0xcd, 0x1d,                          // 4: stamp.nanosec = 500000000
      0x04, 0x00, 0x00, 0x00, 0x6d, 0x61, 0x70, 0x00,  // 8: frame_id "map", length 4 with NUL
      0x00, 0x00, 0x00, 0x00,                          // 16: map_load_time.sec = 0
      0x01, 0x00, 0x00, 0x00,                          // 20: map_load_time.nanosec = 1
      0xcd, 0xcc, 0x4c, 0x3d,                          // 24: resolution 0.05F = 0x3d4ccccd
      0x03, 0x00, 0x00, 0x00,                          // 28: width 3
      0x01, 0x00, 0x00, 0x00,                          // 32: height 1
      0x00, 0x00, 0x00, 0x00,                          // 36: padding: float64 at 40, not 36
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x24, 0xc0,  // 40: origin.position.x = -10
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x04, 0x40,  // 48: y = 2.5
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // 56: z = 0
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // 64: orientation.x = 0
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // 72: y = 0
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xf0, 0x3f,  // 80: z = 1
      0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,  // 88: w = 0
      0x03, 0x00, 0x00, 0x00,                          // 96: data, 3 int8
      0xff, 0x00, 0x64,                                // 100: -1, 0, 100 (no end padding)
  };
  const Bytes got = encode_cdr(g);
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(int{got[i]}, int{expected[i]}) << "byte " << i;
  }
}

TEST(CdrWriter, StampsSplitByFloorDivision) {
  // builtin_interfaces/Time {int32 sec, uint32 nanosec}: bytes 4..11 of any stamped message.
  auto stamp_of = [](std::int64_t ns) {
    PoseStampedMsg p;
    p.header.stamp_ns = ns;
    const Bytes b = encode_cdr(p);
    std::int32_t sec = 0;
    std::uint32_t nanosec = 0;
    std::memcpy(&sec, b.data() + 4, 4);
    std::memcpy(&nanosec, b.data() + 8, 4);
    return std::make_pair(sec, nanosec);
  };
  EXPECT_EQ(stamp_of(-1), std::make_pair(-1, 999999999U));
  EXPECT_EQ(stamp_of(-1000000000), std::make_pair(-1, 0U));
  EXPECT_EQ(stamp_of(-1000000001), std::make_pair(-2, 999999999U));
  EXPECT_EQ(stamp_of(0), std::make_pair(0, 0U));
  EXPECT_EQ(stamp_of(1663967375548411329), std::make_pair(1663967375, 548411329U));
}

// ---- nav_msgs/OccupancyGrid in ROS 1 serialization
// ----------------------------------------------------

/// ROS 1 serialization by hand: packed little-endian, strings with a uint32 length and no NUL.
struct Ros1Bytes {
  Bytes bytes;
  template <typename T>
  Ros1Bytes& put(T v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
    bytes.insert(bytes.end(), p, p + sizeof(T));
    return *this;
  }
  Ros1Bytes& str(const std::string& s) {
    put(static_cast<std::uint32_t>(s.size()));
    bytes.insert(bytes.end(), s.begin(), s.end());
    return *this;
  }
};

BagMessage ros1_occupancy_grid(std::uint32_t data_length) {
  Ros1Bytes b;
  // std_msgs/Header: uint32 seq, time stamp (uint32 sec, uint32 nsec), string frame_id.
  b.put(std::uint32_t{41}).put(std::uint32_t{1700000000}).put(std::uint32_t{5}).str("map");
  // nav_msgs/MapMetaData: time map_load_time; float32 resolution; uint32 width, height; Pose.
  b.put(std::uint32_t{1699999999}).put(std::uint32_t{999999999}).put(0.1F);
  b.put(std::uint32_t{2}).put(std::uint32_t{3});
  for (const double v : {-1.0, -2.0, 0.5, 0.0, 0.0, 0.6, 0.8}) b.put(v);
  // int8[] data.
  b.put(data_length);
  for (const std::int8_t v : {0, 100, -1, 50, 0, -1}) b.put(v);
  BagMessage m;
  m.format = BagFormat::kRos1;
  m.topic = "/map";
  m.type = "nav_msgs/OccupancyGrid";
  m.recorded_ns = 1700000000000000000;
  m.data = b.bytes;
  return m;
}

TEST(Ros1Serialization, DecodesAnOccupancyGrid) {
  const OccupancyGridMsg g = vdtnav::ros::decode_occupancy_grid(ros1_occupancy_grid(6));
  EXPECT_EQ(g.header.stamp_ns, 1700000000000000005);
  EXPECT_EQ(g.header.frame_id, "map");
  EXPECT_EQ(g.info.map_load_time_ns, 1699999999999999999);
  EXPECT_EQ(g.info.resolution, 0.1F);
  EXPECT_EQ(g.info.width, 2U);
  EXPECT_EQ(g.info.height, 3U);
  EXPECT_EQ(g.info.origin.position, Eigen::Vector3d(-1.0, -2.0, 0.5));
  EXPECT_EQ(g.info.origin.orientation.coeffs(), Eigen::Vector4d(0.0, 0.0, 0.6, 0.8));
  EXPECT_EQ(g.data, (std::vector<std::int8_t>{0, 100, -1, 50, 0, -1}));

  // Re-published as ROS 2 CDR (seq dropped), it decodes alike.
  const OccupancyGridMsg again =
      vdtnav::ros::decode_occupancy_grid(as_ros2("nav_msgs/msg/OccupancyGrid", encode_cdr(g)));
  EXPECT_EQ(again.info.map_load_time_ns, g.info.map_load_time_ns);
  EXPECT_EQ(again.data, g.data);

  // A length beyond the bytes left is refused, naming the field.
  try {
    (void)vdtnav::ros::decode_occupancy_grid(ros1_occupancy_grid(7));
    ADD_FAILURE() << "no exception";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("data"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("/map"), std::string::npos) << e.what();
  }
}

}  // namespace
