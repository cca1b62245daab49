// The ROS 2 bag reader (rosbag2 sqlite3 folders, CDR decoded with Fast CDR) on the shared olin
// TurtleBot 4 bag, on broken copies of it made here, and on CDR messages serialized here with
// Fast CDR in both endiannesses.
//
// The expected values come from outside this reader: the facts of
// shared/data/rosbags/README.md, and values read from the .db3 by a short python3 script (the
// sqlite3 module opened with `?mode=ro&immutable=1`, `SELECT ... FROM messages JOIN topics ...
// ORDER BY timestamp`, the CDR decoded by hand with struct.unpack following the .msg
// definitions); those are marked "python oracle".

#include <gtest/gtest.h>

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/ros/bag_reader.hpp"

namespace {

namespace fs = std::filesystem;
using vdtnav::FormatError;
using vdtnav::IoError;
using vdtnav::ros::BagFormat;
using vdtnav::ros::BagMessage;
using vdtnav::ros::BagReader;
using vdtnav::ros::BagTopic;

const fs::path kBag = fs::path(VDTNAV_DATA_DIR) / "rosbags/olin-tb4-ros2/macfirst_floor_take_2";
const fs::path kDb3 = kBag / "macfirst_floor_take_2_0.db3";

#define REQUIRE_BAG()                                                     \
  do {                                                                    \
    if (!fs::exists(kDb3)) GTEST_SKIP() << "no bag at " << kBag.string(); \
  } while (false)

/// A folder of its own under VDTNAV_TEST_TMP, removed at the end of the test.
class TempDir {
 public:
  explicit TempDir(const std::string& name) {
    std::random_device rd;
    path_ = fs::path(VDTNAV_TEST_TMP) / ("ros2_" + name + "_" + std::to_string(rd()));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

/// text with every `from` replaced by `to` (at least one must be there).
std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  for (; at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return text;
}

/// Copies a read-only shared file and makes the copy writable.
void copy_writable(const fs::path& from, const fs::path& to) {
  fs::copy_file(from, to, fs::copy_options::overwrite_existing);
  fs::permissions(to, fs::perms::owner_read | fs::perms::owner_write, fs::perm_options::add);
}

/// The 1-based line of the first line of text containing key.
std::size_t line_of(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(key);
  std::size_t line = 1;
  for (std::size_t i = 0; i < at; ++i) line += text[i] == '\n' ? 1 : 0;
  return line;
}

/// Runs f, expecting an exception E whose what() contains every one of parts.
template <typename E>
void expect_throw_with(const std::function<void()>& f, const std::vector<std::string>& parts) {
  try {
    f();
    ADD_FAILURE() << "no exception";
  } catch (const E& e) {
    const std::string what = e.what();
    for (const std::string& p : parts) {
      EXPECT_NE(what.find(p), std::string::npos) << "'" << p << "' not in: " << what;
    }
  } catch (const std::exception& e) {
    ADD_FAILURE() << "another exception: " << e.what();
  }
}

std::vector<BagMessage> read_all(const BagReader& bag, const std::vector<std::string>& topics) {
  std::vector<BagMessage> out;
  bag.read(topics, [&](const BagMessage& m) {
    out.push_back(m);
    return true;
  });
  return out;
}

BagMessage first_of(const BagReader& bag, const std::string& topic) {
  BagMessage out;
  bag.read({topic}, [&](const BagMessage& m) {
    out = m;
    return false;
  });
  return out;
}

// ---- the bag as a whole
// --------------------------------------------------------------------------

struct ExpectedTopic {
  const char* name;
  const char* type;
  std::size_t count;
  std::int64_t first_ns, last_ns;
};
// Names, types and counts: README and metadata.yaml; first/last: python oracle
// (SELECT topic_id, COUNT(*), MIN(timestamp), MAX(timestamp) ... GROUP BY topic_id). The bag's
// metadata.yaml agrees: starting_time is /scan's first, starting_time + duration is /odom's last.
const std::vector<ExpectedTopic> kTopics = {
    {"/cmd_vel", "geometry_msgs/msg/Twist", 192, 1663967385827760851, 1663967418033956202},
    {"/odom", "nav_msgs/msg/Odometry", 920, 1663967375865899650, 1663967421750980061},
    {"/robot_description", "std_msgs/msg/String", 1, 1663967375552048905, 1663967375552048905},
    {"/scan", "sensor_msgs/msg/LaserScan", 357, 1663967375548411329, 1663967421699541859},
    {"/tf", "tf2_msgs/msg/TFMessage", 953, 1663967375893621616, 1663967421748808930},
    {"/tf_static", "tf2_msgs/msg/TFMessage", 2, 1663967375564913914, 1663967376153481824},
};

void expect_olin_topics(const std::vector<BagTopic>& topics, std::size_t times = 1) {
  ASSERT_EQ(topics.size(), kTopics.size());
  for (std::size_t i = 0; i < kTopics.size(); ++i) {
    SCOPED_TRACE(kTopics[i].name);
    EXPECT_EQ(topics[i].name, kTopics[i].name);  // sorted by name
    EXPECT_EQ(topics[i].type, kTopics[i].type);
    EXPECT_EQ(topics[i].count, kTopics[i].count * times);
    EXPECT_EQ(topics[i].first_ns, kTopics[i].first_ns);
    EXPECT_EQ(topics[i].last_ns, kTopics[i].last_ns);
  }
}

TEST(Ros2Bag, TopicsCountsAndTimeSpans) {
  REQUIRE_BAG();
  const auto bag = BagReader::open(kBag.string());
  EXPECT_EQ(bag->format(), BagFormat::kRos2);
  EXPECT_EQ(bag->path(), kBag.string());
  expect_olin_topics(bag->topics());
}

TEST(Ros2Bag, OpensTheFolderItsMetadataOrItsDb3Alike) {
  REQUIRE_BAG();
  for (const fs::path& p : {kBag / "metadata.yaml", kDb3}) {
    SCOPED_TRACE(p.string());
    const auto bag = BagReader::open(p.string());
    EXPECT_EQ(bag->path(), p.string());
    expect_olin_topics(bag->topics());
  }
}

TEST(Ros2Bag, SizeIsTheSumOfItsFiles) {
  REQUIRE_BAG();
  // `ls -l`: the .db3 has 3317760 bytes, metadata.yaml 2891.
  EXPECT_EQ(BagReader::open(kBag.string())->size_bytes(), 3317760U + 2891U);
}

TEST(Ros2Bag, ReadsEveryMessageInTimeOrder) {
  REQUIRE_BAG();
  const auto bag = BagReader::open(kBag.string());
  const std::vector<BagMessage> all = read_all(*bag, {});
  ASSERT_EQ(all.size(), 2425U);  // metadata.yaml's message_count
  std::map<std::string, std::size_t> counts;
  std::size_t bytes = 0;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const BagMessage& m = all[i];
    ++counts[m.topic];
    bytes += m.data.size();
    EXPECT_EQ(m.format, BagFormat::kRos2);
    if (i > 0) {
      EXPECT_LE(all[i - 1].recorded_ns, m.recorded_ns) << i;
    }
    // Every message starts with the little-endian CDR encapsulation 00 01 00 00.
    ASSERT_GE(m.data.size(), 4U);
    EXPECT_EQ(m.data[0], 0);
    EXPECT_EQ(m.data[1], 1);
  }
  for (const ExpectedTopic& t : kTopics) EXPECT_EQ(counts[t.name], t.count) << t.name;
  EXPECT_EQ(bytes, 2981952U);  // python oracle: SELECT SUM(LENGTH(data)) FROM messages

  // python oracle: the first six and the last two messages (topic, timestamp, bytes).
  const std::vector<std::tuple<std::string, std::int64_t, std::size_t>> head = {
      {"/scan", 1663967375548411329, 5828},      {"/robot_description", 1663967375552048905, 32488},
      {"/tf_static", 1663967375564913914, 3628}, {"/scan", 1663967375681808980, 5828},
      {"/scan", 1663967375805426935, 5828},      {"/odom", 1663967375865899650, 724}};
  for (std::size_t i = 0; i < head.size(); ++i) {
    EXPECT_EQ(all[i].topic, std::get<0>(head[i])) << i;
    EXPECT_EQ(all[i].recorded_ns, std::get<1>(head[i])) << i;
    EXPECT_EQ(all[i].data.size(), std::get<2>(head[i])) << i;
  }
  EXPECT_EQ(all[0].type, "sensor_msgs/msg/LaserScan");
  EXPECT_EQ(all[2].type, "tf2_msgs/msg/TFMessage");
  EXPECT_EQ(all[5].type, "nav_msgs/msg/Odometry");
  EXPECT_EQ(all[all.size() - 2].topic, "/tf");
  EXPECT_EQ(all[all.size() - 2].recorded_ns, 1663967421748808930);
  EXPECT_EQ(all.back().topic, "/odom");
  EXPECT_EQ(all.back().recorded_ns, 1663967421750980061);
}

TEST(Ros2Bag, ReadsTheTopicsAskedAndStopsWhenVisitSaysSo) {
  REQUIRE_BAG();
  const auto bag = BagReader::open(kBag.string());
  const std::vector<BagMessage> statics = read_all(*bag, {"/tf_static"});
  ASSERT_EQ(statics.size(), 2U);
  EXPECT_EQ(statics[0].recorded_ns, 1663967375564913914);
  EXPECT_EQ(statics[1].recorded_ns, 1663967376153481824);

  const std::vector<BagMessage> two = read_all(*bag, {"/scan", "/odom"});
  EXPECT_EQ(two.size(), 357U + 920U);
  for (const BagMessage& m : two) EXPECT_TRUE(m.topic == "/scan" || m.topic == "/odom");
  EXPECT_EQ(two.front().topic, "/scan");
  EXPECT_EQ(two.back().recorded_ns, 1663967421750980061);

  EXPECT_TRUE(read_all(*bag, {"/not_in_the_bag"}).empty());

  std::size_t visits = 0;
  bag->read({}, [&](const BagMessage&) { return ++visits < 10; });
  EXPECT_EQ(visits, 10U);
}

TEST(Ros2Bag, WritesNothingIntoTheBagFolder) {
  REQUIRE_BAG();
  // The bag's database is in WAL mode: a reader that lets sqlite open it normally leaves -shm
  // and -wal files beside it (or fails in a read-only folder).
  auto listing = [] {
    std::set<std::string> names;
    for (const auto& e : fs::directory_iterator(kBag)) names.insert(e.path().filename().string());
    return names;
  };
  const std::set<std::string> before = listing();
  {
    const auto bag = BagReader::open(kBag.string());
    (void)read_all(*bag, {"/tf_static"});
    EXPECT_EQ(listing(), before);
  }
  EXPECT_EQ(listing(), before);
}

// ---- decoding the bag's messages
// -----------------------------------------------------------------

TEST(Ros2Bag, DecodesTheFirstScanFieldByField) {
  REQUIRE_BAG();
  const auto bag = BagReader::open(kBag.string());
  const BagMessage m = first_of(*bag, "/scan");
  const vdtnav::ros::LaserScanMsg s = vdtnav::ros::decode_laser_scan(m);
  // python oracle: header (1663967375, 543606542, 'rplidar_link'), the seven float32 fields,
  // 720 ranges and 720 intensities.
  EXPECT_EQ(s.header.stamp_ns, 1663967375543606542);
  EXPECT_EQ(s.header.frame_id, "rplidar_link");
  EXPECT_EQ(s.angle_min, -3.1241393089294434F);
  EXPECT_EQ(s.angle_max, 3.1415927410125732F);
  EXPECT_EQ(s.angle_increment, 0.008714509196579456F);
  EXPECT_EQ(s.time_increment, 0.0001870909472927451F);
  EXPECT_EQ(s.scan_time, 0.13451839983463287F);
  EXPECT_EQ(s.range_min, 0.15000000596046448F);
  EXPECT_EQ(s.range_max, 12.0F);
  ASSERT_EQ(s.ranges.size(), 720U);
  ASSERT_EQ(s.intensities.size(), 720U);
  EXPECT_EQ(s.ranges[0], 3.1480000019073486F);
  EXPECT_EQ(s.ranges[1], 3.140000104904175F);
  EXPECT_EQ(s.ranges[359], 0.6340000033378601F);
  EXPECT_EQ(s.ranges[719], 3.1519999504089355F);
  EXPECT_EQ(s.intensities[0], 47.0F);
  EXPECT_EQ(s.intensities[359], 47.0F);
  // python oracle: 545 finite ranges summing to 1448.526003361, 175 infinite, intensities 25615.
  std::size_t finite = 0, inf = 0;
  double sum = 0.0, isum = 0.0;
  for (const float r : s.ranges) {
    if (std::isfinite(r)) {
      ++finite;
      sum += r;
    } else if (std::isinf(r)) {
      ++inf;
    }
  }
  for (const float i : s.intensities) isum += i;
  EXPECT_EQ(finite, 545U);
  EXPECT_EQ(inf, 175U);
  EXPECT_NEAR(sum, 1448.526003361, 1e-6);
  EXPECT_EQ(isum, 25615.0);
}

TEST(Ros2Bag, EveryScanHasTheReadmesGeometry) {
  REQUIRE_BAG();
  const auto bag = BagReader::open(kBag.string());
  std::size_t n = 0;
  bag->read({"/scan"}, [&](const BagMessage& m) {
    const vdtnav::ros::LaserScanMsg s = vdtnav::ros::decode_laser_scan(m);
    ++n;
    // README: frame rplidar_link, 720 beams over [-3.124, 3.142], 0.15-12 m.
    EXPECT_EQ(s.header.frame_id, "rplidar_link");
    EXPECT_EQ(s.ranges.size(), 720U);
    EXPECT_NEAR(s.angle_min, -3.124, 1e-3);
    EXPECT_NEAR(s.angle_max, 3.142, 1e-3);
    EXPECT_NEAR(s.range_min, 0.15, 1e-6);
    EXPECT_NEAR(s.range_max, 12.0, 1e-6);
    // The stamp is the sensor's, within a second of the recording time (a little before or,
    // the two clocks differing, up to a millisecond after).
    EXPECT_LT(std::abs(s.header.stamp_ns - m.recorded_ns), 1000000000) << m.recorded_ns;
    return true;
  });
  EXPECT_EQ(n, 357U);
}

TEST(Ros2Bag, DecodesTfStaticWithTheLidarMount) {
  REQUIRE_BAG();
  const auto bag = BagReader::open(kBag.string());
  const std::vector<BagMessage> statics = read_all(*bag, {"/tf_static"});
  ASSERT_EQ(statics.size(), 2U);
  const vdtnav::ros::TfMsg a = vdtnav::ros::decode_tf(statics[0]);
  const vdtnav::ros::TfMsg b = vdtnav::ros::decode_tf(statics[1]);
  EXPECT_EQ(a.transforms.size(), 33U);  // python oracle
  EXPECT_EQ(b.transforms.size(), 23U);
  const vdtnav::ros::TransformStampedMsg* lidar = nullptr;
  for (const auto& t : a.transforms) {
    if (t.child_frame_id == "rplidar_link") lidar = &t;
  }
  ASSERT_NE(lidar, nullptr);
  EXPECT_EQ(lidar->header.frame_id, "base_link");
  // README: (0.004, 0, 0.139) with yaw +90 deg.
  EXPECT_NEAR(lidar->translation.x(), 0.004, 5e-4);
  EXPECT_NEAR(lidar->translation.y(), 0.0, 1e-12);
  EXPECT_NEAR(lidar->translation.z(), 0.139, 5e-4);
  const Eigen::Matrix3d r = lidar->rotation.toRotationMatrix();
  EXPECT_NEAR(std::atan2(r(1, 0), r(0, 0)), EIGEN_PI / 2, 1e-9);
  // python oracle: exact values and stamp (1663952504, 700581349).
  EXPECT_EQ(lidar->translation.x(), 0.00393584);
  EXPECT_EQ(lidar->translation.z(), 0.13949272000000001);
  EXPECT_EQ(lidar->rotation.z(), 0.7071067811865475);
  EXPECT_EQ(lidar->rotation.w(), 0.7071067811865476);
  EXPECT_EQ(lidar->header.stamp_ns, 1663952504700581349);
  // python oracle: the first transform of the first message.
  EXPECT_EQ(a.transforms[0].child_frame_id, "bump_front_center");
  EXPECT_EQ(a.transforms[0].translation.z(), 0.039200000000000006);
}

TEST(Ros2Bag, DecodesTfWithTheReadmesTwoTransforms) {
  REQUIRE_BAG();
  const auto bag = BagReader::open(kBag.string());
  std::set<std::pair<std::string, std::string>> pairs;
  std::size_t n = 0;
  bag->read({"/tf"}, [&](const BagMessage& m) {
    for (const auto& t : vdtnav::ros::decode_tf(m).transforms) {
      pairs.emplace(t.header.frame_id, t.child_frame_id);
    }
    ++n;
    return true;
  });
  EXPECT_EQ(n, 953U);
  const std::set<std::pair<std::string, std::string>> want = {{"odom", "base_link"},
                                                              {"odom", "base_footprint"}};
  EXPECT_EQ(pairs, want);

  // python oracle: the first /tf message.
  const vdtnav::ros::TfMsg tf = vdtnav::ros::decode_tf(first_of(*bag, "/tf"));
  ASSERT_EQ(tf.transforms.size(), 2U);
  const auto& t = tf.transforms[0];
  EXPECT_EQ(t.header.stamp_ns, 1663967370849346434);
  EXPECT_EQ(t.child_frame_id, "base_link");
  EXPECT_EQ(t.translation,
            Eigen::Vector3d(6.539614677429199, -8.85838508605957, 0.05175676941871643));
  EXPECT_EQ(t.rotation.coeffs(), Eigen::Vector4d(0.003152786288410425, 0.0011337457690387964,
                                                 0.7530895471572876, 0.6579095721244812));
  EXPECT_EQ(tf.transforms[1].child_frame_id, "base_footprint");
  EXPECT_EQ(tf.transforms[1].translation.x(), 6.539809420080768);
}

TEST(Ros2Bag, DecodesTheFirstOdometryFieldByField) {
  REQUIRE_BAG();
  const auto bag = BagReader::open(kBag.string());
  const vdtnav::ros::OdometryMsg o = vdtnav::ros::decode_odometry(first_of(*bag, "/odom"));
  // python oracle.
  EXPECT_EQ(o.header.stamp_ns, 1663967375744427509);
  EXPECT_EQ(o.header.frame_id, "odom");
  EXPECT_EQ(o.child_frame_id, "base_link");
  EXPECT_EQ(o.pose.pose.position,
            Eigen::Vector3d(6.539614677429199, -8.85838508605957, 0.05175676941871643));
  EXPECT_EQ(o.pose.pose.orientation.coeffs(),
            Eigen::Vector4d(0.003152786288410425, 0.0011337457690387964, 0.7530895471572876,
                            0.6579095721244812));
  for (const double c : o.pose.covariance) EXPECT_EQ(c, 0.0);
  EXPECT_EQ(o.twist.linear, Eigen::Vector3d::Zero());
  EXPECT_EQ(o.twist.angular, Eigen::Vector3d(0.0, -9.96996618596313e-09, 0.0));
  for (const double c : o.twist.covariance) EXPECT_EQ(c, 0.0);

  std::size_t n = 0;
  bag->read({"/odom"}, [&](const BagMessage& m) {
    const vdtnav::ros::OdometryMsg x = vdtnav::ros::decode_odometry(m);
    EXPECT_EQ(x.child_frame_id, "base_link");
    EXPECT_NEAR(x.pose.pose.orientation.norm(), 1.0, 1e-6);
    ++n;
    return true;
  });
  EXPECT_EQ(n, 920U);
}

TEST(Ros2Bag, RefusesAMessageOfAnotherType) {
  REQUIRE_BAG();
  const auto bag = BagReader::open(kBag.string());
  const BagMessage odom = first_of(*bag, "/odom");
  const BagMessage scan = first_of(*bag, "/scan");
  // The topic, the type asked, the type held and the bag time 1663967375.865899650.
  expect_throw_with<FormatError>([&] { (void)vdtnav::ros::decode_laser_scan(odom); },
                                 {"/odom", "expected sensor_msgs/msg/LaserScan",
                                  "nav_msgs/msg/Odometry", "1663967375.865899650"});
  expect_throw_with<FormatError>([&] { (void)vdtnav::ros::decode_odometry(scan); },
                                 {"/scan", "nav_msgs/msg/Odometry", "sensor_msgs/msg/LaserScan"});
  expect_throw_with<FormatError>([&] { (void)vdtnav::ros::decode_tf(scan); }, {"TFMessage"});
  expect_throw_with<FormatError>([&] { (void)vdtnav::ros::decode_imu(scan); }, {"Imu"});
  expect_throw_with<FormatError>([&] { (void)vdtnav::ros::decode_point_cloud2(scan); },
                                 {"PointCloud2"});
  expect_throw_with<FormatError>([&] { (void)vdtnav::ros::decode_pose_stamped(odom); },
                                 {"PoseStamped"});
  expect_throw_with<FormatError>(
      [&] { (void)vdtnav::ros::decode_pose_with_covariance_stamped(odom); },
      {"PoseWithCovarianceStamped"});
  // The ROS 1 spelling of the same type is accepted.
  BagMessage ros1_spelled = scan;
  ros1_spelled.type = "sensor_msgs/LaserScan";
  EXPECT_EQ(vdtnav::ros::decode_laser_scan(ros1_spelled).ranges.size(), 720U);
}

TEST(Ros2Bag, RefusesTruncatedOrCorruptCdr) {
  REQUIRE_BAG();
  const auto bag = BagReader::open(kBag.string());
  const BagMessage scan = first_of(*bag, "/scan");
  ASSERT_EQ(scan.data.size(), 5828U);
  // Cut in the encapsulation, the header, the frame id, the fixed fields, the ranges and the
  // last intensity.
  for (const std::size_t keep : {0, 2, 4, 10, 20, 40, 62, 1000, 2944, 5827}) {
    SCOPED_TRACE(keep);
    BagMessage cut = scan;
    cut.data.resize(keep);
    expect_throw_with<FormatError>([&] { (void)vdtnav::ros::decode_laser_scan(cut); },
                                   {"/scan", "LaserScan"});
  }
  // python oracle: the ranges' uint32 length (720, little-endian) is at byte 60 (4 encapsulation,
  // 8 stamp, 4 + 13 frame id, 3 padding, 7 float32). An absurd length is refused before any
  // allocation.
  BagMessage corrupt = scan;
  ASSERT_EQ(corrupt.data[60], 720 % 256);
  ASSERT_EQ(corrupt.data[61], 720 / 256);
  for (int i = 0; i < 4; ++i) corrupt.data[60 + i] = 0xFF;
  expect_throw_with<FormatError>([&] { (void)vdtnav::ros::decode_laser_scan(corrupt); },
                                 {"ranges", "4294967295"});
  // An encapsulation that is not plain CDR (0x00 0x06: XCDR2 little-endian).
  BagMessage xcdr2 = scan;
  xcdr2.data[1] = 6;
  expect_throw_with<FormatError>([&] { (void)vdtnav::ros::decode_laser_scan(xcdr2); }, {"/scan"});
}

// ---- CDR serialized here with Fast CDR
// -----------------------------------------------------------

/// Serializes a message with Fast CDR in the given endianness, as a bag message.
BagMessage serialize(eprosima::fastcdr::Cdr::Endianness endianness, const std::string& type,
                     const std::function<void(eprosima::fastcdr::Cdr&)>& body) {
  std::vector<char> buffer(1 << 16);
  eprosima::fastcdr::FastBuffer fb(buffer.data(), buffer.size());
  eprosima::fastcdr::Cdr cdr(fb, endianness, eprosima::fastcdr::Cdr::DDS_CDR);
  cdr.serialize_encapsulation();
  body(cdr);
  BagMessage m;
  m.format = BagFormat::kRos2;
  m.topic = "/made_here";
  m.type = type;
  m.recorded_ns = 1;
  m.data.assign(buffer.begin(),
                buffer.begin() + static_cast<std::ptrdiff_t>(cdr.getSerializedDataLength()));
  return m;
}

void header(eprosima::fastcdr::Cdr& c, std::int32_t sec, std::uint32_t nsec,
            const std::string& frame) {
  c.serialize(sec);
  c.serialize(nsec);
  c.serialize(frame);
}

const eprosima::fastcdr::Cdr::Endianness kBig = eprosima::fastcdr::Cdr::BIG_ENDIANNESS;
const eprosima::fastcdr::Cdr::Endianness kLittle = eprosima::fastcdr::Cdr::LITTLE_ENDIANNESS;

TEST(Ros2Cdr, LaserScanInEitherEndianness) {
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> ranges = {1.5F, inf, 2.25F, 0.125F}, intensities = {7.0F, 8.0F, 9.0F, 10.0F};
  for (const auto e : {kBig, kLittle}) {
    const BagMessage m = serialize(e, "sensor_msgs/msg/LaserScan", [&](auto& c) {
      header(c, -3, 999999999U, "laser_be");
      for (const float f : {-1.0F, 1.25F, 0.5F, 0.001F, 0.1F, 0.2F, 30.0F}) c.serialize(f);
      c.serialize(static_cast<std::uint32_t>(ranges.size()));
      c.serializeArray(ranges.data(), ranges.size());
      c.serialize(static_cast<std::uint32_t>(intensities.size()));
      c.serializeArray(intensities.data(), intensities.size());
    });
    EXPECT_EQ(m.data[1], e == kBig ? 0 : 1);  // the encapsulation names the endianness
    const vdtnav::ros::LaserScanMsg s = vdtnav::ros::decode_laser_scan(m);
    EXPECT_EQ(s.header.stamp_ns, -3 * 1000000000LL + 999999999LL);
    EXPECT_EQ(s.header.frame_id, "laser_be");
    EXPECT_EQ(s.angle_min, -1.0F);
    EXPECT_EQ(s.angle_max, 1.25F);
    EXPECT_EQ(s.angle_increment, 0.5F);
    EXPECT_EQ(s.time_increment, 0.001F);
    EXPECT_EQ(s.scan_time, 0.1F);
    EXPECT_EQ(s.range_min, 0.2F);
    EXPECT_EQ(s.range_max, 30.0F);
    EXPECT_EQ(s.ranges, ranges);
    EXPECT_EQ(s.intensities, intensities);
  }
}

TEST(Ros2Cdr, ReserializingTheFirstScanGivesTheBagsBytes) {
  REQUIRE_BAG();
  const auto bag = BagReader::open(kBag.string());
  const BagMessage scan = first_of(*bag, "/scan");
  vdtnav::ros::LaserScanMsg s = vdtnav::ros::decode_laser_scan(scan);
  const BagMessage again = serialize(kLittle, scan.type, [&](auto& c) {
    header(c, static_cast<std::int32_t>(s.header.stamp_ns / 1000000000),
           static_cast<std::uint32_t>(s.header.stamp_ns % 1000000000), s.header.frame_id);
    for (const float f : {s.angle_min, s.angle_max, s.angle_increment, s.time_increment,
                          s.scan_time, s.range_min, s.range_max}) {
      c.serialize(f);
    }
    c.serialize(static_cast<std::uint32_t>(s.ranges.size()));
    c.serializeArray(s.ranges.data(), s.ranges.size());
    c.serialize(static_cast<std::uint32_t>(s.intensities.size()));
    c.serializeArray(s.intensities.data(), s.intensities.size());
  });
  EXPECT_EQ(again.data, scan.data);
}

TEST(Ros2Cdr, OtherMessagesInEitherEndianness) {
  const std::array<double, 36> cov = [] {
    std::array<double, 36> a{};
    for (std::size_t i = 0; i < a.size(); ++i) a[i] = 0.5 * static_cast<double>(i) - 3.0;
    return a;
  }();
  auto pose = [](auto& c, double k) {
    for (const double v : {1.0 * k, 2.0 * k, 3.0 * k, 0.0, 0.6, 0.0, 0.8}) c.serialize(v);
  };
  for (const auto e : {kBig, kLittle}) {
    SCOPED_TRACE(e == kBig ? "big-endian" : "little-endian");
    // geometry_msgs/msg/PoseStamped.
    const auto ps = vdtnav::ros::decode_pose_stamped(
        serialize(e, "geometry_msgs/msg/PoseStamped", [&](auto& c) {
          header(c, 5, 6U, "map");
          pose(c, 1.0);
        }));
    EXPECT_EQ(ps.header.stamp_ns, 5000000006);
    EXPECT_EQ(ps.header.frame_id, "map");
    EXPECT_EQ(ps.pose.position, Eigen::Vector3d(1, 2, 3));
    EXPECT_EQ(ps.pose.orientation.coeffs(), Eigen::Vector4d(0.0, 0.6, 0.0, 0.8));

    // geometry_msgs/msg/PoseWithCovarianceStamped (the covariance after 7 float64: no padding).
    const auto pc = vdtnav::ros::decode_pose_with_covariance_stamped(
        serialize(e, "geometry_msgs/msg/PoseWithCovarianceStamped", [&](auto& c) {
          header(c, 7, 8U, "map_odd");  // a frame of 8 bytes with the NUL
          pose(c, -1.0);
          c.serializeArray(cov.data(), cov.size());
        }));
    EXPECT_EQ(pc.header.frame_id, "map_odd");
    EXPECT_EQ(pc.pose.pose.position, Eigen::Vector3d(-1, -2, -3));
    EXPECT_EQ(pc.pose.covariance, cov);

    // sensor_msgs/msg/Imu.
    const auto imu = vdtnav::ros::decode_imu(serialize(e, "sensor_msgs/msg/Imu", [&](auto& c) {
      header(c, 1, 2U, "imu_link");
      for (const double v : {0.0, 0.0, 0.6, 0.8}) c.serialize(v);
      for (int i = 0; i < 9; ++i) c.serialize(-1.0 * i);
      for (const double v : {0.1, 0.2, 0.3}) c.serialize(v);
      for (int i = 0; i < 9; ++i) c.serialize(10.0 + i);
      for (const double v : {9.7, 9.8, 9.9}) c.serialize(v);
      for (int i = 0; i < 9; ++i) c.serialize(20.0 + i);
    }));
    EXPECT_EQ(imu.header.frame_id, "imu_link");
    EXPECT_EQ(imu.orientation.coeffs(), Eigen::Vector4d(0.0, 0.0, 0.6, 0.8));
    EXPECT_EQ(imu.orientation_covariance[8], -8.0);
    EXPECT_EQ(imu.angular_velocity, Eigen::Vector3d(0.1, 0.2, 0.3));
    EXPECT_EQ(imu.angular_velocity_covariance[0], 10.0);
    EXPECT_EQ(imu.linear_acceleration, Eigen::Vector3d(9.7, 9.8, 9.9));
    EXPECT_EQ(imu.linear_acceleration_covariance[8], 28.0);

    // sensor_msgs/msg/PointCloud2 with two fields and 2 points of 12 bytes.
    const std::vector<std::uint8_t> data = {1,  2,  3,  4,  5,  6,  7,  8,  9,  10, 11, 12,
                                            13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24};
    const auto pc2 =
        vdtnav::ros::decode_point_cloud2(serialize(e, "sensor_msgs/msg/PointCloud2", [&](auto& c) {
          header(c, 3, 4U, "velodyne");
          c.serialize(std::uint32_t{1});
          c.serialize(std::uint32_t{2});
          c.serialize(std::uint32_t{2});
          c.serialize(std::string("x"));
          c.serialize(std::uint32_t{0});
          c.serialize(std::uint8_t{7});
          c.serialize(std::uint32_t{1});
          c.serialize(std::string("ring"));
          c.serialize(std::uint32_t{8});
          c.serialize(std::uint8_t{4});
          c.serialize(std::uint32_t{1});
          c.serialize(false);
          c.serialize(std::uint32_t{12});
          c.serialize(std::uint32_t{24});
          c.serialize(static_cast<std::uint32_t>(data.size()));
          c.serializeArray(data.data(), data.size());
          c.serialize(true);
        }));
    EXPECT_EQ(pc2.header.frame_id, "velodyne");
    EXPECT_EQ(pc2.height, 1U);
    EXPECT_EQ(pc2.width, 2U);
    ASSERT_EQ(pc2.fields.size(), 2U);
    EXPECT_EQ(pc2.fields[0].name, "x");
    EXPECT_EQ(pc2.fields[0].datatype, 7);
    EXPECT_EQ(pc2.fields[1].name, "ring");
    EXPECT_EQ(pc2.fields[1].offset, 8U);
    EXPECT_EQ(pc2.fields[1].datatype, 4);
    EXPECT_EQ(pc2.fields[1].count, 1U);
    EXPECT_FALSE(pc2.is_bigendian);
    EXPECT_EQ(pc2.point_step, 12U);
    EXPECT_EQ(pc2.row_step, 24U);
    EXPECT_EQ(pc2.data, data);
    EXPECT_TRUE(pc2.is_dense);

    // tf2_msgs/msg/TFMessage with one transform.
    const auto tf = vdtnav::ros::decode_tf(serialize(e, "tf2_msgs/msg/TFMessage", [&](auto& c) {
      c.serialize(std::uint32_t{1});
      header(c, 9, 10U, "odom");
      c.serialize(std::string("base_link"));
      pose(c, 2.0);
    }));
    ASSERT_EQ(tf.transforms.size(), 1U);
    EXPECT_EQ(tf.transforms[0].header.stamp_ns, 9000000010);
    EXPECT_EQ(tf.transforms[0].child_frame_id, "base_link");
    EXPECT_EQ(tf.transforms[0].translation, Eigen::Vector3d(2, 4, 6));
    EXPECT_EQ(tf.transforms[0].rotation.coeffs(), Eigen::Vector4d(0.0, 0.6, 0.0, 0.8));
  }
}

// ---- broken bags made here
// -----------------------------------------------------------------------

/// A copy of the olin bag in dir, with metadata.yaml's text passed through edit.
void copy_bag(
    const fs::path& dir,
    const std::function<std::string(std::string)>& edit = [](std::string s) { return s; }) {
  copy_writable(kDb3, dir / kDb3.filename());
  write_text(dir / "metadata.yaml", edit(read_text(kBag / "metadata.yaml")));
}

TEST(Ros2Bag, RefusesMcapStorageNamingTheConversion) {
  REQUIRE_BAG();
  {
    TempDir dir("mcap_metadata");
    copy_bag(dir.path(), [](std::string s) {
      s = replace_all(s, "storage_identifier: sqlite3", "storage_identifier: mcap");
      return replace_all(s, ".db3", ".mcap");
    });
    const std::string yaml = read_text(dir.path() / "metadata.yaml");
    try {
      (void)BagReader::open(dir.path().string());
      ADD_FAILURE() << "no exception";
    } catch (const FormatError& e) {
      EXPECT_NE(std::string(e.what()).find("sqlite3"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("ros2 bag convert"), std::string::npos) << e.what();
      EXPECT_EQ(e.file(), (dir.path() / "metadata.yaml").string());
      EXPECT_EQ(e.line(), line_of(yaml, "storage_identifier"));
    }
  }
  {
    // A folder with a .mcap file and no metadata.yaml; and the .mcap file given directly.
    TempDir dir("mcap_file");
    write_text(dir.path() / "bag_0.mcap", "\x89MCAP0\r\n");
    expect_throw_with<FormatError>([&] { (void)BagReader::open(dir.path().string()); },
                                   {"sqlite3", "bag_0.mcap"});
    expect_throw_with<FormatError>(
        [&] { (void)BagReader::open((dir.path() / "bag_0.mcap").string()); }, {"sqlite3"});
  }
}

TEST(Ros2Bag, RefusesCompressedBags) {
  REQUIRE_BAG();
  TempDir dir("zstd");
  copy_bag(dir.path(), [](std::string s) {
    s = replace_all(s, "compression_format: \"\"", "compression_format: zstd");
    return replace_all(s, "compression_mode: \"\"", "compression_mode: FILE");
  });
  const std::string yaml = read_text(dir.path() / "metadata.yaml");
  try {
    (void)BagReader::open(dir.path().string());
    ADD_FAILURE() << "no exception";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("zstd"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("compress"), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), line_of(yaml, "compression_format"));
  }
}

TEST(Ros2Bag, RefusesOtherSerializationFormats) {
  REQUIRE_BAG();
  TempDir dir("ser");
  copy_bag(dir.path(), [](std::string s) {
    const std::string from = "serialization_format: cdr";
    return s.replace(s.find(from), from.size(), "serialization_format: ros1");
  });
  expect_throw_with<FormatError>([&] { (void)BagReader::open(dir.path().string()); },
                                 {"metadata.yaml", "cdr", "ros1", "/odom"});
}

TEST(Ros2Bag, RefusesMissingTruncatedOrForeignDatabases) {
  REQUIRE_BAG();
  {
    TempDir dir("missing");
    write_text(dir.path() / "metadata.yaml", read_text(kBag / "metadata.yaml"));
    expect_throw_with<FormatError>([&] { (void)BagReader::open(dir.path().string()); },
                                   {"macfirst_floor_take_2_0.db3"});
  }
  for (const std::uintmax_t keep : {std::uintmax_t{50}, std::uintmax_t{4096 * 3},
                                    std::uintmax_t{3317760 / 2}, std::uintmax_t{3317760 - 1}}) {
    SCOPED_TRACE(keep);
    TempDir dir("truncated");
    copy_bag(dir.path());
    const fs::path db3 = dir.path() / kDb3.filename();
    fs::resize_file(db3, keep);
    try {
      (void)BagReader::open(dir.path().string());
      ADD_FAILURE() << "no exception";
    } catch (const FormatError& e) {
      EXPECT_NE(std::string(e.what()).find(db3.string()), std::string::npos) << e.what();
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(db3.string()), std::string::npos) << e.what();
    }
  }
  {
    TempDir dir("not_sqlite");
    copy_bag(dir.path());
    const fs::path db3 = dir.path() / kDb3.filename();
    write_text(db3,
               std::string("this is not a sqlite database, only text\n") + std::string(200, 'x'));
    expect_throw_with<FormatError>([&] { (void)BagReader::open(dir.path().string()); },
                                   {db3.string(), "sqlite"});
    expect_throw_with<FormatError>([&] { (void)BagReader::open(db3.string()); }, {db3.string()});
  }
}

// ---- other layouts
// -------------------------------------------------------------------------------

TEST(Ros2Bag, WithoutMetadataReadsTheDatabasesTopics) {
  REQUIRE_BAG();
  TempDir dir("no_metadata");
  copy_writable(kDb3, dir.path() / kDb3.filename());
  const auto bag = BagReader::open(dir.path().string());
  expect_olin_topics(bag->topics());
  EXPECT_EQ(read_all(*bag, {}).size(), 2425U);
  EXPECT_EQ(bag->size_bytes(), 3317760U);
}

TEST(Ros2Bag, MergesSeveralDatabasesByTime) {
  REQUIRE_BAG();
  // The same database twice under two names: concatenating them would go back in time at the
  // second file; merging gives every timestamp twice in a row.
  TempDir dir("two_files");
  copy_writable(kDb3, dir.path() / "two_0.db3");
  copy_writable(kDb3, dir.path() / "two_1.db3");
  write_text(dir.path() / "metadata.yaml",
             replace_all(read_text(kBag / "metadata.yaml"), "- macfirst_floor_take_2_0.db3",
                         "- two_0.db3\n    - two_1.db3"));
  const auto bag = BagReader::open(dir.path().string());
  expect_olin_topics(bag->topics(), 2);
  const std::vector<BagMessage> all = read_all(*bag, {});
  ASSERT_EQ(all.size(), 2 * 2425U);
  for (std::size_t i = 0; i + 1 < all.size(); i += 2) {
    EXPECT_EQ(all[i].recorded_ns, all[i + 1].recorded_ns) << i;
    EXPECT_EQ(all[i].data, all[i + 1].data) << i;
    if (i > 0) {
      EXPECT_LT(all[i - 1].recorded_ns, all[i].recorded_ns) << i;
    }
  }
  EXPECT_EQ(bag->size_bytes(), 2 * 3317760U + fs::file_size(dir.path() / "metadata.yaml"));
}

// ---- speed
// ---------------------------------------------------------------------------------------

TEST(Ros2Bag, ReadSpeed) {
  REQUIRE_BAG();
  const auto bag = BagReader::open(kBag.string());
  constexpr int kRuns = 5;
  std::size_t messages = 0, bytes = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int run = 0; run < kRuns; ++run) {
    bag->read({}, [&](const BagMessage& m) {
      ++messages;
      bytes += m.data.size();
      return true;
    });
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto t1 = std::chrono::steady_clock::now();
  std::size_t scans = 0;
  for (int run = 0; run < kRuns; ++run) {
    bag->read({"/scan"}, [&](const BagMessage& m) {
      scans += vdtnav::ros::decode_laser_scan(m).ranges.size() > 0 ? 1 : 0;
      return true;
    });
  }
  const double s_scan =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  std::printf(
      "olin-tb4-ros2, all messages: %.1f MB/s of the bag's %.2f MB, %.0f messages/s "
      "(%zu messages, %.1f MB of CDR in %.3f s); read + decode /scan: %.0f scans/s\n",
      static_cast<double>(bag->size_bytes()) * kRuns / s / 1e6,
      static_cast<double>(bag->size_bytes()) / 1e6, static_cast<double>(messages) / s, messages,
      static_cast<double>(bytes) / 1e6, s, static_cast<double>(scans) / s_scan);
  EXPECT_EQ(messages, kRuns * 2425U);
  EXPECT_EQ(scans, kRuns * 357U);
}

}  // namespace
