// The ROS 2 CDR of the lifecycle_msgs, bond, std_srvs and nav2_msgs messages a node without
// rclcpp serves nav2 with (cdr_writer.hpp, cdr_reader.hpp), and decode_cdr on every type.
// Oracles independent of the writer: layouts computed by hand byte by byte from the alignment
// rules (each primitive at a multiple of its size counted after the 4-byte encapsulation; a
// string is its uint32 length with the NUL, its bytes, the NUL; no padding after the last field)
// and rosidl's placeholder byte for an empty structure; and decode_* of bag_reader.hpp on every
// message of the shared olin TurtleBot 4 bag (recorded through rmw_fastrtps).

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros/cdr_reader.hpp"
#include "vdtnav/ros/cdr_writer.hpp"
#include "vdtnav/ros/lifecycle_ids.hpp"

namespace {

namespace fs = std::filesystem;
namespace lifecycle = vdtnav::ros::lifecycle;
using vdtnav::FormatError;
using vdtnav::ros::BagMessage;
using vdtnav::ros::BagReader;
using vdtnav::ros::BondStatusMsg;
using vdtnav::ros::ChangeStateRequestMsg;
using vdtnav::ros::ChangeStateResponseMsg;
using vdtnav::ros::decode_cdr;
using vdtnav::ros::EmptyMsg;
using vdtnav::ros::encode_cdr;
using vdtnav::ros::GetStateResponseMsg;
using vdtnav::ros::LifecycleStateMsg;
using vdtnav::ros::LifecycleTransitionMsg;
using vdtnav::ros::PoseWithCovarianceStampedMsg;
using vdtnav::ros::SetInitialPoseRequestMsg;
using vdtnav::ros::TransitionEventMsg;
using Bytes = std::vector<std::uint8_t>;

const fs::path kBag = fs::path(VDTNAV_DATA_DIR) / "rosbags/olin-tb4-ros2/macfirst_floor_take_2";
const fs::path kDb3 = kBag / "macfirst_floor_take_2_0.db3";

#define REQUIRE_BAG()                                                     \
  do {                                                                    \
    if (!fs::exists(kDb3)) GTEST_SKIP() << "no bag at " << kBag.string(); \
  } while (false)

/// Labels of 0 to 4 characters (string lengths 1 to 5 with the NUL) put the next field at every
/// remainder modulo 4, and a real one.
const std::vector<std::string> kLabels = {"", "a", "ab", "abc", "abcd", "deactivate"};

/// m encoded, then decoded.
template <class Msg>
Msg round_trip(const Msg& m) {
  Msg out;
  decode_cdr(encode_cdr(m), &out, "a round trip");
  return out;
}

/// Compares got with expected byte by byte, naming the first bytes that differ.
void expect_bytes(const Bytes& got, const Bytes& expected) {
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(int{got[i]}, int{expected[i]}) << "byte " << i;
  }
}

// ---- encode -> decode
// ---------------------------------------------------------------------------------

TEST(CdrMessages, LifecycleMessagesRoundTrip) {
  std::uint8_t id = 0;
  for (const std::string& label : kLabels) {
    SCOPED_TRACE("label '" + label + "'");
    id = static_cast<std::uint8_t>(id + 37);  // 37, 74, ..., 222: every bit of the uint8 in use

    const LifecycleTransitionMsg t = round_trip(LifecycleTransitionMsg{id, label});
    EXPECT_EQ(t.id, id);
    EXPECT_EQ(t.label, label);
    const LifecycleStateMsg s = round_trip(LifecycleStateMsg{id, label + "_s"});
    EXPECT_EQ(s.id, id);
    EXPECT_EQ(s.label, label + "_s");

    const ChangeStateRequestMsg req = round_trip(ChangeStateRequestMsg{{id, label}});
    EXPECT_EQ(req.transition.id, id);
    EXPECT_EQ(req.transition.label, label);
    const GetStateResponseMsg get = round_trip(GetStateResponseMsg{{id, label}});
    EXPECT_EQ(get.current_state.id, id);
    EXPECT_EQ(get.current_state.label, label);

    // uint64 first (body offset 0); then each label shifts the uint8 and uint32 after it.
    TransitionEventMsg e;
    e.timestamp = std::numeric_limits<std::uint64_t>::max() - id;
    e.transition = {lifecycle::kTransitionOnActivateSuccess, label};
    e.start_state = {lifecycle::kTransitionStateActivating, label + "x"};
    e.goal_state = {lifecycle::kPrimaryStateActive, "active" + label};
    const TransitionEventMsg d = round_trip(e);
    EXPECT_EQ(d.timestamp, e.timestamp);
    EXPECT_EQ(d.transition.id, e.transition.id);
    EXPECT_EQ(d.transition.label, e.transition.label);
    EXPECT_EQ(d.start_state.id, e.start_state.id);
    EXPECT_EQ(d.start_state.label, e.start_state.label);
    EXPECT_EQ(d.goal_state.id, e.goal_state.id);
    EXPECT_EQ(d.goal_state.label, e.goal_state.label);
  }
  for (const bool success : {false, true}) {
    EXPECT_EQ(round_trip(ChangeStateResponseMsg{success}).success, success);
  }
}

TEST(CdrMessages, BondStatusRoundTrips) {
  for (const std::string& label : kLabels) {
    SCOPED_TRACE("'" + label + "'");
    for (const bool active : {false, true}) {
      BondStatusMsg b;
      b.header = {-1000000001, label};  // sec -2, nanosec 999999999
      b.id = "amcl" + label;
      b.instance_id = label + "9e1c";
      b.active = active;
      b.heartbeat_timeout = 4.0F;
      b.heartbeat_period = -std::numeric_limits<float>::infinity();
      const BondStatusMsg d = round_trip(b);
      EXPECT_EQ(d.header.stamp_ns, b.header.stamp_ns);
      EXPECT_EQ(d.header.frame_id, b.header.frame_id);
      EXPECT_EQ(d.id, b.id);
      EXPECT_EQ(d.instance_id, b.instance_id);
      EXPECT_EQ(d.active, b.active);
      EXPECT_EQ(d.heartbeat_timeout, b.heartbeat_timeout);
      EXPECT_EQ(d.heartbeat_period, b.heartbeat_period);
    }
  }
}

TEST(CdrMessages, SetInitialPoseRequestIsItsPoseWithCovarianceStamped) {
  SetInitialPoseRequestMsg r;
  r.pose.header = {1700000000123456789, "map"};
  r.pose.pose.pose.position = Eigen::Vector3d(-3.5, 12.25, 0.0);
  r.pose.pose.pose.orientation = Eigen::Quaterniond(0.6, 0.0, 0.0, 0.8);
  for (std::size_t i = 0; i < 36; ++i) r.pose.pose.covariance[i] = 0.25 * static_cast<double>(i);
  // The request's one member is the message: the same bytes, field for field.
  EXPECT_EQ(encode_cdr(r), encode_cdr(r.pose));
  const SetInitialPoseRequestMsg d = round_trip(r);
  EXPECT_EQ(d.pose.header.stamp_ns, r.pose.header.stamp_ns);
  EXPECT_EQ(d.pose.header.frame_id, r.pose.header.frame_id);
  EXPECT_EQ(d.pose.pose.pose.position, r.pose.pose.pose.position);
  EXPECT_EQ(d.pose.pose.pose.orientation.coeffs(), r.pose.pose.pose.orientation.coeffs());
  EXPECT_EQ(d.pose.pose.covariance, r.pose.pose.covariance);
}

// ---- layouts by hand
// ----------------------------------------------------------------------------------

TEST(CdrMessages, ChangeStateRequestByteByByte) {
  const ChangeStateRequestMsg r{{lifecycle::kTransitionActivate, "activate"}};
  const Bytes expected = {
      0x00, 0x01, 0x00, 0x00,                          // encapsulation: CDR little-endian
      0x03,                                            // body 0: transition.id = 3 (ACTIVATE)
      0x00, 0x00, 0x00,                                // 1: padding, the uint32 goes at 4
      0x09, 0x00, 0x00, 0x00,                          // 4: label length 9 (8 + NUL)
      0x61, 0x63, 0x74, 0x69, 0x76, 0x61, 0x74, 0x65,  // 8: "activate"
      0x00,                                            // 16: NUL; the end (21 bytes, no padding)
  };
  expect_bytes(encode_cdr(r), expected);
  // The hand-made bytes decode without the writer.
  ChangeStateRequestMsg d;
  decode_cdr(expected, &d, "service /amcl/change_state request");
  EXPECT_EQ(d.transition.id, 3);
  EXPECT_EQ(d.transition.label, "activate");
}

TEST(CdrMessages, LifecycleResponsesByteByByte) {
  // lifecycle_msgs/srv/ChangeState_Response {bool success}: one byte, no end padding.
  expect_bytes(encode_cdr(ChangeStateResponseMsg{true}), {0x00, 0x01, 0x00, 0x00, 0x01});
  // lifecycle_msgs/srv/GetState_Response {State current_state {3, "active"}}.
  expect_bytes(encode_cdr(GetStateResponseMsg{{lifecycle::kPrimaryStateActive, "active"}}),
               {
                   0x00, 0x01, 0x00, 0x00,                    // encapsulation
                   0x03, 0x00, 0x00, 0x00,                    // body 0: id 3 (ACTIVE), padding
                   0x07, 0x00, 0x00, 0x00,                    // 4: label length 7
                   0x61, 0x63, 0x74, 0x69, 0x76, 0x65, 0x00,  // 8: "active", NUL (19 bytes)
               });
}

TEST(CdrMessages, EmptyIsOnePlaceholderByte) {
  // rosidl's structure_needs_at_least_one_member (uint8, 0) behind the encapsulation; the
  // message ends on it, as rmw_fastrtps sends it (payload length = serialized length).
  const Bytes expected = {0x00, 0x01, 0x00, 0x00, 0x00};
  expect_bytes(encode_cdr(EmptyMsg{}), expected);
  EmptyMsg e;
  decode_cdr(expected, &e, "service /x/get_state request");
  // An XTypes 1.3 writer (Cyclone DDS) pads to 4 and says so in the options (0x0003); a nonzero
  // placeholder is taken too, as rmw_fastrtps's deserializer does.
  decode_cdr({0x00, 0x01, 0x00, 0x03, 0x00, 0x00, 0x00, 0x00}, &e, "padded");
  decode_cdr({0x00, 0x01, 0x00, 0x00, 0x07}, &e, "nonzero placeholder");
  decode_cdr({0x00, 0x00, 0x00, 0x00, 0x00}, &e, "big-endian");
  // Without the placeholder it is not a ROS 2 empty message.
  try {
    decode_cdr({0x00, 0x01, 0x00, 0x00}, &e, "service /x/get_state request");
    ADD_FAILURE() << "no exception";
  } catch (const FormatError& err) {
    EXPECT_EQ(err.file(), "service /x/get_state request");
    EXPECT_NE(std::string(err.what()).find("empty message"), std::string::npos) << err.what();
    EXPECT_NE(std::string(err.what()).find("(4 bytes)"), std::string::npos) << err.what();
  }
}

TEST(CdrMessages, BondStatusAlignsItsFloatsAfterTheBool) {
  BondStatusMsg b;
  b.header = {1000000002, ""};
  b.id = "amcl";
  b.instance_id = "x";
  b.active = true;
  b.heartbeat_timeout = 4.0F;  // nav2's bond timeout and heartbeat period
  b.heartbeat_period = 0.1F;
  const Bytes expected = {
      0x00, 0x01, 0x00, 0x00,        // encapsulation
      0x01, 0x00, 0x00, 0x00,        // body 0: stamp.sec = 1
      0x02, 0x00, 0x00, 0x00,        // 4: stamp.nanosec = 2
      0x01, 0x00, 0x00, 0x00,        // 8: frame_id length 1 (just the NUL)
      0x00,                          // 12: NUL
      0x00, 0x00, 0x00,              // 13: padding
      0x05, 0x00, 0x00, 0x00,        // 16: id length 5
      0x61, 0x6d, 0x63, 0x6c, 0x00,  // 20: "amcl", NUL
      0x00, 0x00, 0x00,              // 25: padding
      0x02, 0x00, 0x00, 0x00,        // 28: instance_id length 2
      0x78, 0x00,                    // 32: "x", NUL
      0x01,                          // 34: active (bool, no alignment)
      0x00,                          // 35: padding: float32 at 36, not 35
      0x00, 0x00, 0x80, 0x40,        // 36: heartbeat_timeout 4.0F = 0x40800000
      0xcd, 0xcc, 0xcc, 0x3d,        // 40: heartbeat_period 0.1F = 0x3dcccccd (48 bytes)
  };
  expect_bytes(encode_cdr(b), expected);
  BondStatusMsg d;
  decode_cdr(expected, &d, "topic /bond");
  EXPECT_EQ(d.header.stamp_ns, 1000000002);
  EXPECT_EQ(d.id, "amcl");
  EXPECT_EQ(d.instance_id, "x");
  EXPECT_TRUE(d.active);
  EXPECT_EQ(d.heartbeat_timeout, 4.0F);
  EXPECT_EQ(d.heartbeat_period, 0.1F);
}

// ---- refused bytes
// ------------------------------------------------------------------------------------

/// Every proper prefix of m's bytes is refused, naming what, the type and the size, and leaves
/// the output as it was.
template <class Msg>
void expect_every_cut_refused(const Msg& m, const std::string& ros2_type) {
  const Bytes full = encode_cdr(m);
  for (std::size_t keep = 0; keep < full.size(); ++keep) {
    SCOPED_TRACE(ros2_type + " cut to " + std::to_string(keep) + " bytes");
    Msg out = m;
    try {
      decode_cdr(Bytes(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(keep)), &out,
                 "service /lifecycle_test");
      ADD_FAILURE() << "no exception";
    } catch (const FormatError& e) {
      const std::string what = e.what();
      EXPECT_EQ(e.file(), "service /lifecycle_test");
      EXPECT_NE(
          what.find("expected " + ros2_type + " in CDR (" + std::to_string(keep) + " bytes): "),
          std::string::npos)
          << what;
    }
    EXPECT_EQ(encode_cdr(out), full) << "the output changed";
  }
}

TEST(CdrMessages, DecodeCdrRefusesCutBytes) {
  expect_every_cut_refused(LifecycleTransitionMsg{1, "configure"}, "lifecycle_msgs/msg/Transition");
  expect_every_cut_refused(LifecycleStateMsg{2, "inactive"}, "lifecycle_msgs/msg/State");
  expect_every_cut_refused(ChangeStateRequestMsg{{3, "activate"}},
                           "lifecycle_msgs/srv/ChangeState_Request");
  expect_every_cut_refused(ChangeStateResponseMsg{true}, "lifecycle_msgs/srv/ChangeState_Response");
  expect_every_cut_refused(GetStateResponseMsg{{3, "active"}},
                           "lifecycle_msgs/srv/GetState_Response");
  expect_every_cut_refused(TransitionEventMsg{7, {4, "deactivate"}, {3, "active"}, {2, "inactive"}},
                           "lifecycle_msgs/msg/TransitionEvent");
  BondStatusMsg b;
  b.header = {5, "f"};
  b.id = "amcl";
  b.instance_id = "uuid";
  b.active = true;
  b.heartbeat_timeout = 4.0F;
  b.heartbeat_period = 0.1F;
  expect_every_cut_refused(b, "bond/msg/Status");
  SetInitialPoseRequestMsg r;
  r.pose.header.frame_id = "map";
  expect_every_cut_refused(r, "nav2_msgs/srv/SetInitialPose_Request");
  // And two of the existing types.
  PoseWithCovarianceStampedMsg p;
  p.header.frame_id = "odom";
  expect_every_cut_refused(p, "geometry_msgs/msg/PoseWithCovarianceStamped");
  vdtnav::ros::OccupancyGridMsg g;
  g.header.frame_id = "map";
  g.data = {0, 100, -1};
  expect_every_cut_refused(g, "nav_msgs/msg/OccupancyGrid");
}

TEST(CdrMessages, DecodeCdrRefusesAParameterListOrAnAbsurdLength) {
  // 00 03: PL_CDR little-endian, which Fast CDR reads but is not plain CDR.
  Bytes pl = encode_cdr(ChangeStateRequestMsg{{1, "configure"}});
  pl[1] = 0x03;
  ChangeStateRequestMsg out;
  try {
    decode_cdr(pl, &out, "service /amcl/change_state request");
    ADD_FAILURE() << "no exception";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("parameter-list"), std::string::npos) << e.what();
  }
  // A grid whose data claims more int8 than the bytes hold, refused before the allocation.
  vdtnav::ros::OccupancyGridMsg g;
  g.data = {1, 2, 3};
  Bytes absurd = encode_cdr(g);
  for (std::size_t i = absurd.size() - 7; i < absurd.size() - 3; ++i) absurd[i] = 0xff;
  try {
    decode_cdr(absurd, &g, "topic /map");
    ADD_FAILURE() << "no exception";
  } catch (const FormatError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("topic /map"), std::string::npos) << what;
    EXPECT_NE(what.find("nav_msgs/msg/OccupancyGrid"), std::string::npos) << what;
    EXPECT_NE(what.find("the sequence data claims 4294967295"), std::string::npos) << what;
  }
}

// ---- the recorded bag: decode_cdr == decode_*
// -------------------------------------------------------------

/// decode_cdr of m's bytes and decode_* of m, both encoded again (the writer gives back every
/// field: test_cdr_writer.cpp), equal.
template <class Msg>
bool same_decoding(const BagMessage& m, Msg (*decode)(const BagMessage&)) {
  Msg from_bytes;
  decode_cdr(m.data, &from_bytes, "topic " + m.topic);
  return encode_cdr(from_bytes) == encode_cdr(decode(m));
}

TEST(CdrMessages, DecodeCdrOfTheRecordedBagEqualsItsDecoders) {
  REQUIRE_BAG();
  namespace r = vdtnav::ros;
  std::map<std::string, std::size_t> compared, equal;
  const auto bag = BagReader::open(kBag.string());
  bag->read({"/scan", "/tf", "/tf_static", "/odom"}, [&](const BagMessage& m) {
    bool same = false;
    if (m.topic == "/scan") {
      same = same_decoding(m, r::decode_laser_scan);
      if (compared[m.topic] == 0) {  // one field seen directly, not through the writer
        r::LaserScanMsg s;
        decode_cdr(m.data, &s, "topic /scan");
        EXPECT_EQ(s.ranges, r::decode_laser_scan(m).ranges);
        EXPECT_EQ(s.ranges.size(), 720U);
      }
    } else if (m.topic == "/odom") {
      same = same_decoding(m, r::decode_odometry);
    } else {
      same = same_decoding(m, r::decode_tf);
    }
    ++compared[m.topic];
    equal[m.topic] += same ? 1 : 0;
    return true;
  });
  // Counts: metadata.yaml (2232 messages in all).
  const std::map<std::string, std::size_t> expected = {
      {"/odom", 920}, {"/scan", 357}, {"/tf", 953}, {"/tf_static", 2}};
  EXPECT_EQ(compared, expected);
  EXPECT_EQ(equal, expected);
}

}  // namespace
