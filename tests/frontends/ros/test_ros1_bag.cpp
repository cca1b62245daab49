// The ROS 1 bag reader (format 2.0, through rosbag_storage) on the shared real bags, on broken
// copies the tests make of them, and on bags the tests write with rosbag::Bag (bz2, lz4,
// uncompressed) holding messages of every decoded type with known values.
//
// The facts about the real bags come from the data README and, for times and field values, from
// Debian's python3-rosbag (a pure-Python reader independent of rosbag_storage's C++), e.g.
//   /usr/bin/python3 -c "import rosbag; b = rosbag.Bag('test1.bag'); ..."
// printing per topic count, first and last recorded time (secs * 1e9 + nsecs) and the first
// messages' fields; the values are hard-coded below.

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>
#include <unistd.h>

#include "vdtnav/core/error.hpp"
#include "vdtnav/ros/bag_reader.hpp"

namespace {

namespace fs = std::filesystem;
using vdtnav::FormatError;
using vdtnav::ros::BagFormat;
using vdtnav::ros::BagMessage;
using vdtnav::ros::BagReader;
using vdtnav::ros::BagTopic;

const std::string kBags = std::string(VDTNAV_DATA_DIR) + "/rosbags";
const std::string kTest1 = kBags + "/ist-pioneer3dx/test1.bag";
const std::string kDemo = kBags + "/scan-tools-demo/demo.bag";
const std::string kOld = kBags + "/scan-tools-demo/old_format_v1.2.bag";
const std::string kEmbag = kBags + "/embag-lz4/test.bag";

#define SKIP_WITHOUT(file) \
  if (!fs::exists(file)) GTEST_SKIP() << (file) << " is not there"

/// \brief A fresh folder under the system's temp folder, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    path_ = fs::temp_directory_path() /
            ("vdtnav_test_ros1_" + std::to_string(::getpid()) + "_" + std::to_string(counter++) +
             "_" + std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

std::vector<char> slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void spit(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::uint32_t u32_at(const std::vector<char>& b, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, b.data() + at, 4);  // little-endian host, as the bag format
  return v;
}

/// \brief A tiny record reader for the tests (independent of the library): the record at pos,
/// its header fields, where its data starts and how long it says it is.
struct Record {
  std::map<std::string, std::string> fields;
  std::size_t data_pos = 0;
  std::uint32_t data_len = 0;
  [[nodiscard]] std::uint8_t op() const { return static_cast<std::uint8_t>(fields.at("op")[0]); }
  [[nodiscard]] std::uint32_t u32(const std::string& name) const {
    std::uint32_t v = 0;
    std::memcpy(&v, fields.at(name).data(), 4);
    return v;
  }
};

Record record_at(const std::vector<char>& b, std::size_t pos) {
  Record r;
  const std::uint32_t header_len = u32_at(b, pos);
  for (std::size_t at = pos + 4; at < pos + 4 + header_len;) {
    const std::uint32_t len = u32_at(b, at);
    const std::string field(b.data() + at + 4, len);
    r.fields[field.substr(0, field.find('='))] = field.substr(field.find('=') + 1);
    at += 4 + len;
  }
  r.data_len = u32_at(b, pos + 4 + header_len);
  r.data_pos = pos + 8 + header_len;
  return r;
}

std::vector<BagMessage> read_all(const BagReader& bag, const std::vector<std::string>& topics) {
  std::vector<BagMessage> out;
  bag.read(topics, [&](const BagMessage& m) {
    out.push_back(m);
    return true;
  });
  return out;
}

const BagTopic* find_topic(const BagReader& bag, const std::string& name) {
  for (const BagTopic& t : bag.topics()) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

/// \brief Opening path throws FormatError whose message names the file and holds `words`.
void expect_format_error(const std::string& path, const std::string& words) {
  try {
    auto bag = BagReader::open(path);
    read_all(*bag, {});  // a broken bag that opens must fail when read, not crash
    ADD_FAILURE() << path << ": no FormatError";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    EXPECT_EQ(e.file(), path);
  }
}

// ------------------------------------------------------------------------- the real bags

TEST(Ros1Bag, Test1TopicsCountsTypesAndTimes) {
  SKIP_WITHOUT(kTest1);
  auto bag = BagReader::open(kTest1);
  EXPECT_EQ(bag->format(), BagFormat::kRos1);
  EXPECT_EQ(bag->path(), kTest1);
  EXPECT_EQ(bag->size_bytes(), 1501183U);  // ls -l
  // rosbag info: 14 topics (/diagnostics has 2 connections, merged), 3241 messages.
  ASSERT_EQ(bag->topics().size(), 14U);
  std::size_t total = 0;
  for (std::size_t i = 0; i < bag->topics().size(); ++i) {
    total += bag->topics()[i].count;
    if (i > 0) {
      EXPECT_LT(bag->topics()[i - 1].name, bag->topics()[i].name);
    }
  }
  EXPECT_EQ(total, 3241U);
  struct Expected {
    const char* name;
    const char* type;
    std::size_t count;
    std::int64_t first_ns, last_ns;
  };
  // python3-rosbag: count, min and max recorded time of each topic.
  for (const Expected& e : {
           Expected{"/scan", "sensor_msgs/LaserScan", 311, 1684338971955073772,
                    1684339002984094826},
           Expected{"/tf", "tf2_msgs/TFMessage", 317, 1684338971717898718, 1684339003061898798},
           Expected{"/pose", "nav_msgs/Odometry", 313, 1684338971718040859, 1684339002963751811},
           Expected{"/diagnostics", "diagnostic_msgs/DiagnosticArray", 61, 1684338971953491054,
                    1684339002224670079},
       }) {
    const BagTopic* t = find_topic(*bag, e.name);
    ASSERT_NE(t, nullptr) << e.name;
    EXPECT_EQ(t->type, e.type);
    EXPECT_EQ(t->count, e.count) << e.name;
    EXPECT_EQ(t->first_ns, e.first_ns) << e.name;
    EXPECT_EQ(t->last_ns, e.last_ns) << e.name;
  }
}

TEST(Ros1Bag, Test1ReadsAllInRecordedOrderAndStopsEarly) {
  SKIP_WITHOUT(kTest1);
  auto bag = BagReader::open(kTest1);
  const std::vector<BagMessage> all = read_all(*bag, {});
  ASSERT_EQ(all.size(), 3241U);
  for (std::size_t i = 1; i < all.size(); ++i) {
    ASSERT_LE(all[i - 1].recorded_ns, all[i].recorded_ns) << i;
  }
  // python3-rosbag's first and last three messages (no two share a time in this bag).
  EXPECT_EQ(all[0].topic, "/urg_node/parameter_updates");
  EXPECT_EQ(all[0].recorded_ns, 1684338971717513462);
  EXPECT_EQ(all[1].topic, "/sonar");
  EXPECT_EQ(all[1].recorded_ns, 1684338971717513704);
  EXPECT_EQ(all[3240].topic, "/tf");
  EXPECT_EQ(all[3240].recorded_ns, 1684339003061898798);
  EXPECT_EQ(all[3239].topic, "/scan");
  for (const BagMessage& m : all) {
    EXPECT_EQ(m.format, BagFormat::kRos1);
    EXPECT_FALSE(m.data.empty());
  }

  // A topic subset, in order, and an early stop.
  const std::vector<BagMessage> some = read_all(*bag, {"/scan", "/pose"});
  EXPECT_EQ(some.size(), 311U + 313U);
  for (const BagMessage& m : some) EXPECT_TRUE(m.topic == "/scan" || m.topic == "/pose");
  std::size_t seen = 0;
  bag->read({"/tf"}, [&](const BagMessage&) { return ++seen < 5; });
  EXPECT_EQ(seen, 5U);
  EXPECT_TRUE(read_all(*bag, {"/no_such_topic"}).empty());
}

TEST(Ros1Bag, Test1FirstScanFieldByField) {
  SKIP_WITHOUT(kTest1);
  auto bag = BagReader::open(kTest1);
  std::vector<BagMessage> scans = read_all(*bag, {"/scan"});
  ASSERT_EQ(scans.size(), 311U);
  const vdtnav::ros::LaserScanMsg s = vdtnav::ros::decode_laser_scan(scans.front());
  // python3-rosbag, first /scan (seq 5739).
  EXPECT_EQ(scans.front().recorded_ns, 1684338971955073772);
  EXPECT_EQ(s.header.stamp_ns, 1684338971918498586);
  EXPECT_EQ(s.header.frame_id, "laser");
  EXPECT_FLOAT_EQ(s.angle_min, -2.356194496154785F);
  EXPECT_FLOAT_EQ(s.angle_max, 2.0923497676849365F);
  EXPECT_FLOAT_EQ(s.angle_increment, 0.006135923322290182F);
  EXPECT_FLOAT_EQ(s.time_increment, 9.765627328306437e-05F);
  EXPECT_FLOAT_EQ(s.scan_time, 0.10000000149011612F);
  EXPECT_FLOAT_EQ(s.range_min, 0.019999999552965164F);
  EXPECT_FLOAT_EQ(s.range_max, 5.599999904632568F);
  ASSERT_EQ(s.ranges.size(), 726U);
  EXPECT_TRUE(s.intensities.empty());
  EXPECT_FLOAT_EQ(s.ranges[0], 0.01899999938905239F);
  EXPECT_FLOAT_EQ(s.ranges[426], 2.74399995803833F);
  EXPECT_FLOAT_EQ(s.ranges[500], 1.215000033378601F);
  EXPECT_FLOAT_EQ(s.ranges[600], 0.859000027179718F);
  EXPECT_FLOAT_EQ(s.ranges[725], 0.8759999871253967F);
  EXPECT_TRUE(std::isnan(s.ranges[100]));
  EXPECT_TRUE(std::isnan(s.ranges[363]));
  // The last scan.
  const vdtnav::ros::LaserScanMsg last = vdtnav::ros::decode_laser_scan(scans.back());
  EXPECT_EQ(last.header.stamp_ns, 1684339002947382781);
  EXPECT_FLOAT_EQ(last.ranges[363], 0.006000000052154064F);
  // Every scan decodes with the README's shape.
  for (const BagMessage& m : scans) {
    const auto scan = vdtnav::ros::decode_laser_scan(m);
    ASSERT_EQ(scan.ranges.size(), 726U);
    ASSERT_EQ(scan.header.frame_id, "laser");
  }
}

TEST(Ros1Bag, Test1FirstOdometryAndTransform) {
  SKIP_WITHOUT(kTest1);
  auto bag = BagReader::open(kTest1);
  std::vector<BagMessage> pose = read_all(*bag, {"/pose"});
  ASSERT_EQ(pose.size(), 313U);
  const vdtnav::ros::OdometryMsg o = vdtnav::ros::decode_odometry(pose.front());
  // python3-rosbag, first /pose.
  EXPECT_EQ(o.header.stamp_ns, 1684338971563856935);
  EXPECT_EQ(o.header.frame_id, "odom");
  EXPECT_EQ(o.child_frame_id, "base_link");
  EXPECT_DOUBLE_EQ(o.pose.pose.position.x(), -2.787);
  EXPECT_DOUBLE_EQ(o.pose.pose.position.y(), -8.908);
  EXPECT_DOUBLE_EQ(o.pose.pose.position.z(), 0.0);
  EXPECT_DOUBLE_EQ(o.pose.pose.orientation.z(), 0.5150380749100544);
  EXPECT_DOUBLE_EQ(o.pose.pose.orientation.w(), -0.8571673007021122);
  EXPECT_DOUBLE_EQ(o.pose.covariance[0], 0.001);
  EXPECT_DOUBLE_EQ(o.pose.covariance[7], 0.001);
  EXPECT_DOUBLE_EQ(o.pose.covariance[14], 1e6);
  EXPECT_DOUBLE_EQ(o.pose.covariance[35], 1000.0);
  EXPECT_DOUBLE_EQ(o.twist.covariance[35], 1000.0);
  EXPECT_TRUE(o.twist.linear.isZero());

  std::vector<BagMessage> tf = read_all(*bag, {"/tf"});
  ASSERT_EQ(tf.size(), 317U);
  const vdtnav::ros::TfMsg t = vdtnav::ros::decode_tf(tf.front());
  ASSERT_EQ(t.transforms.size(), 1U);
  const auto& odom_base = t.transforms[0];
  EXPECT_EQ(odom_base.header.stamp_ns, 1684338971263663104);
  EXPECT_EQ(odom_base.header.frame_id, "odom");
  EXPECT_EQ(odom_base.child_frame_id, "base_link");
  EXPECT_DOUBLE_EQ(odom_base.translation.x(), -2.787);
  EXPECT_DOUBLE_EQ(odom_base.translation.y(), -8.908);
  EXPECT_DOUBLE_EQ(odom_base.rotation.x(), -0.0);
  EXPECT_DOUBLE_EQ(odom_base.rotation.z(), 0.5150380749100544);
  EXPECT_DOUBLE_EQ(odom_base.rotation.w(), -0.8571673007021122);
  // README: /tf holds odom->base_link only.
  for (const BagMessage& m : tf) {
    for (const auto& x : vdtnav::ros::decode_tf(m).transforms) {
      ASSERT_EQ(x.header.frame_id, "odom");
      ASSERT_EQ(x.child_frame_id, "base_link");
    }
  }
}

TEST(Ros1Bag, DecodersRefuseOtherTypesAndBrokenBytes) {
  SKIP_WITHOUT(kTest1);
  auto bag = BagReader::open(kTest1);
  std::vector<BagMessage> tf = read_all(*bag, {"/tf"});
  std::vector<BagMessage> scan = read_all(*bag, {"/scan"});
  ASSERT_FALSE(tf.empty());
  ASSERT_FALSE(scan.empty());
  try {
    (void)vdtnav::ros::decode_laser_scan(tf.front());
    ADD_FAILURE() << "no FormatError";
  } catch (const FormatError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("/tf"), std::string::npos) << what;
    EXPECT_NE(what.find("expected sensor_msgs/LaserScan"), std::string::npos) << what;
    EXPECT_NE(what.find("tf2_msgs/TFMessage"), std::string::npos) << what;
    EXPECT_NE(what.find("1684338971.717898718"), std::string::npos) << what;
  }
  EXPECT_THROW((void)vdtnav::ros::decode_odometry(scan.front()), FormatError);
  EXPECT_THROW((void)vdtnav::ros::decode_imu(scan.front()), FormatError);
  EXPECT_THROW((void)vdtnav::ros::decode_point_cloud2(scan.front()), FormatError);
  EXPECT_THROW((void)vdtnav::ros::decode_pose_stamped(scan.front()), FormatError);
  EXPECT_THROW((void)vdtnav::ros::decode_pose_with_covariance_stamped(scan.front()), FormatError);
  EXPECT_THROW((void)vdtnav::ros::decode_tf(scan.front()), FormatError);

  // The ROS 2 spelling of the type is accepted for ROS 1 bytes.
  BagMessage renamed = scan.front();
  renamed.type = "sensor_msgs/msg/LaserScan";
  EXPECT_EQ(vdtnav::ros::decode_laser_scan(renamed).ranges.size(), 726U);

  // Every cut of the bytes is refused (stream overrun), never read past the buffer.
  const std::size_t n = scan.front().data.size();
  for (const std::size_t keep : {std::size_t{0}, std::size_t{1}, std::size_t{4}, std::size_t{11},
                                 std::size_t{30}, n / 2, n - 1}) {
    BagMessage cut = scan.front();
    cut.data.resize(keep);
    EXPECT_THROW((void)vdtnav::ros::decode_laser_scan(cut), FormatError) << keep;
  }
  BagMessage cut_tf = tf.front();
  cut_tf.data.resize(cut_tf.data.size() - 3);
  EXPECT_THROW((void)vdtnav::ros::decode_tf(cut_tf), FormatError);
}

TEST(Ros1Bag, DemoBagWithOverlongIndexLengthsReadsEveryMessage) {
  SKIP_WITHOUT(kDemo);
  // The premise (README): its index records declare more data than their entries take.
  const std::vector<char> bytes = slurp(kDemo);
  const Record header = record_at(bytes, 13);
  const Record chunk = record_at(bytes, header.data_pos + header.data_len);
  ASSERT_EQ(chunk.op(), 0x05);
  const Record index = record_at(bytes, chunk.data_pos + chunk.data_len);
  ASSERT_EQ(index.op(), 0x04);
  EXPECT_EQ(index.u32("count"), 278U);
  EXPECT_EQ(index.data_len, 5560U);

  auto bag = BagReader::open(kDemo);
  ASSERT_EQ(bag->topics().size(), 1U);
  const BagTopic& t = bag->topics()[0];
  EXPECT_EQ(t.name, "/scan");
  EXPECT_EQ(t.type, "sensor_msgs/LaserScan");
  EXPECT_EQ(t.count, 360U);
  EXPECT_EQ(t.first_ns, 1282836371069930698);  // python3-rosbag
  EXPECT_EQ(t.last_ns, 1282836406881212710);
  const std::vector<BagMessage> scans = read_all(*bag, {});
  ASSERT_EQ(scans.size(), 360U);
  const auto first = vdtnav::ros::decode_laser_scan(scans.front());
  EXPECT_EQ(first.header.stamp_ns, 1282836370970876375);
  EXPECT_EQ(first.header.frame_id, "/laser");
  EXPECT_FLOAT_EQ(first.angle_min, -2.0862138271331787F);
  EXPECT_FLOAT_EQ(first.angle_max, 2.0862138271331787F);
  EXPECT_FLOAT_EQ(first.ranges[0], 3.002000093460083F);
  EXPECT_FLOAT_EQ(first.ranges[340], 0.9419999718666077F);
  for (const BagMessage& m : scans) {
    const auto s = vdtnav::ros::decode_laser_scan(m);
    ASSERT_EQ(s.ranges.size(), 681U);
    ASSERT_EQ(s.header.frame_id, "/laser");
  }
  EXPECT_EQ(scans.back().recorded_ns, 1282836406881212710);
}

TEST(Ros1Bag, EmbagLz4PointClouds) {
  SKIP_WITHOUT(kEmbag);
  auto bag = BagReader::open(kEmbag);
  ASSERT_EQ(bag->topics().size(), 3U);
  const BagTopic* t = find_topic(*bag, "/luminar_pointcloud");
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(t->type, "sensor_msgs/PointCloud2");
  EXPECT_EQ(t->count, 5U);
  EXPECT_EQ(t->first_ns, 1604515190231374463);  // python3-rosbag
  EXPECT_EQ(t->last_ns, 1604515190592366241);
  const std::vector<BagMessage> clouds = read_all(*bag, {"/luminar_pointcloud"});
  ASSERT_EQ(clouds.size(), 5U);
  const auto c = vdtnav::ros::decode_point_cloud2(clouds.front());
  EXPECT_EQ(c.header.stamp_ns, 1583971570015299642);
  EXPECT_EQ(c.header.frame_id, "luminar_lidar");
  EXPECT_EQ(c.height, 1U);
  EXPECT_EQ(c.width, 35707U);
  EXPECT_EQ(c.point_step, 32U);
  EXPECT_EQ(c.row_step, 1142624U);
  EXPECT_FALSE(c.is_bigendian);
  EXPECT_TRUE(c.is_dense);
  ASSERT_EQ(c.data.size(), 35707U * 32U);
  struct Field {
    const char* name;
    std::uint32_t offset;
    std::uint8_t datatype;
  };
  const std::vector<Field> fields = {
      {"x", 0, 7},         {"y", 4, 7},          {"z", 8, 7},        {"intensity", 16, 7},
      {"time_sec", 20, 6}, {"time_nsec", 24, 6}, {"laser_id", 28, 4}};
  ASSERT_EQ(c.fields.size(), fields.size());
  for (std::size_t i = 0; i < fields.size(); ++i) {
    EXPECT_EQ(c.fields[i].name, fields[i].name);
    EXPECT_EQ(c.fields[i].offset, fields[i].offset);
    EXPECT_EQ(c.fields[i].datatype, fields[i].datatype);
    EXPECT_EQ(c.fields[i].count, 1U);
  }
  float xyz[3];
  std::memcpy(xyz, c.data.data(), sizeof(xyz));
  EXPECT_FLOAT_EQ(xyz[0], 38.32744216918945F);
  EXPECT_FLOAT_EQ(xyz[1], 41.32063674926758F);
  EXPECT_FLOAT_EQ(xyz[2], 2.6648621559143066F);
  // python3-rosbag: the widths of the five clouds (the README's "35 707 points each" holds for
  // the first only).
  const std::uint32_t widths[5] = {35707, 36055, 36267, 36457, 36336};
  for (std::size_t i = 0; i < clouds.size(); ++i) {
    const auto cloud = vdtnav::ros::decode_point_cloud2(clouds[i]);
    EXPECT_EQ(cloud.height, 1U);
    EXPECT_EQ(cloud.width, widths[i]);
    EXPECT_EQ(cloud.data.size(), std::size_t{widths[i]} * 32U);
    EXPECT_EQ(cloud.fields.size(), 7U);
  }
}

// ------------------------------------------------------------------------ broken bags

TEST(Ros1Bag, OldFormatIsRefused) {
  SKIP_WITHOUT(kOld);
  expect_format_error(kOld, "only ROS bag format 2.0");
  try {
    (void)BagReader::open(kOld);
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("1.2"), std::string::npos) << e.what();
  }
}

TEST(Ros1Bag, TruncatedCopiesAreRefused) {
  SKIP_WITHOUT(kTest1);
  const std::vector<char> bytes = slurp(kTest1);
  TempDir dir;
  // The first chunk spans bytes 4166..790739; the connection and chunk info records are the last
  // ~22 KB (own walk of the records).
  for (const std::size_t keep :
       {std::size_t{400000}, std::size_t{790800}, bytes.size() - 10, bytes.size() - 200,
        bytes.size() - 3000, std::size_t{20}, std::size_t{13}, std::size_t{5}}) {
    const std::string path = dir.file("cut_" + std::to_string(keep) + ".bag");
    spit(path, std::vector<char>(bytes.begin(), bytes.begin() + static_cast<long>(keep)));
    SCOPED_TRACE(keep);
    expect_format_error(path, "truncated");
  }
}

TEST(Ros1Bag, UnknownCompressionIsRefused) {
  SKIP_WITHOUT(kEmbag);
  std::vector<char> bytes = slurp(kEmbag);
  const Record header = record_at(bytes, 13);
  const std::size_t chunk_pos = header.data_pos + header.data_len;
  const std::string needle = "compression=lz4";
  const auto at = std::search(bytes.begin() + static_cast<long>(chunk_pos), bytes.end(),
                              needle.begin(), needle.end());
  ASSERT_NE(at, bytes.end());
  ASSERT_LT(at - bytes.begin(), static_cast<long>(chunk_pos + 64));  // in the first chunk's header
  std::memcpy(&*(at + 12), "xz9", 3);
  TempDir dir;
  const std::string path = dir.file("xz9.bag");
  spit(path, bytes);
  expect_format_error(path, "unknown chunk compression 'xz9'");
}

TEST(Ros1Bag, CorruptIndexIsRefused) {
  SKIP_WITHOUT(kTest1);
  const std::vector<char> bytes = slurp(kTest1);
  const Record header = record_at(bytes, 13);
  const std::size_t chunk_pos = header.data_pos + header.data_len;
  const Record chunk = record_at(bytes, chunk_pos);
  ASSERT_EQ(chunk.op(), 0x05);
  const std::size_t index_pos = chunk.data_pos + chunk.data_len;
  const Record index = record_at(bytes, index_pos);
  ASSERT_EQ(index.op(), 0x04);
  TempDir dir;
  {  // A message offset past the end of its chunk.
    std::vector<char> b = bytes;
    const std::uint32_t offset = 0xFFFFFF00U;
    std::memcpy(b.data() + index.data_pos + 8, &offset, 4);
    const std::string path = dir.file("offset.bag");
    spit(path, b);
    expect_format_error(path, "corrupt index");
  }
  {  // A message offset inside a message record of an uncompressed chunk (points at its bytes).
    for (const std::uint32_t shift : {2U, 30U, 200U}) {
      std::vector<char> b = bytes;
      const std::uint32_t offset = u32_at(b, index.data_pos + 8) + shift;
      std::memcpy(b.data() + index.data_pos + 8, &offset, 4);
      const std::string path = dir.file("inside_" + std::to_string(shift) + ".bag");
      spit(path, b);
      SCOPED_TRACE(shift);
      expect_format_error(path, "corrupt");
    }
  }
  {  // An entry count larger than the record holds.
    std::vector<char> b = bytes;
    const std::string needle = std::string("count=") + index.fields.at("count");
    const auto at = std::search(b.begin() + static_cast<long>(index_pos), b.end(), needle.begin(),
                                needle.end());
    ASSERT_NE(at, b.end());
    const std::uint32_t count = 100000;
    std::memcpy(&*(at + 6), &count, 4);
    const std::string path = dir.file("count.bag");
    spit(path, b);
    expect_format_error(path, "entries");
  }
  {  // A field of a connection header longer than the header (ros::Header::parse, which
     // rosbag_storage calls, would read past its buffer: found by a fuzzing run under ASan).
    std::vector<char> b = bytes;
    std::uint64_t index_at = 0;
    std::memcpy(&index_at, header.fields.at("index_pos").data(), 8);
    const Record connection = record_at(b, index_at);
    ASSERT_EQ(connection.op(), 0x07);
    const std::uint32_t len = 0x7FFF;
    std::memcpy(b.data() + connection.data_pos, &len, 4);
    const std::string path = dir.file("connection_header.bag");
    spit(path, b);
    expect_format_error(path, "corrupt");
  }
  {  // The bag header's index position pointing into a chunk.
    std::vector<char> b = bytes;
    const std::string needle = "index_pos=";
    const auto at = std::search(b.begin() + 13, b.end(), needle.begin(), needle.end());
    ASSERT_NE(at, b.end());
    const std::uint64_t pos = 500000;
    std::memcpy(&*(at + 10), &pos, 8);
    const std::string path = dir.file("index_pos.bag");
    spit(path, b);
    expect_format_error(path, "corrupt");
  }
}

// ------------------------------------------------------------- bags written by the test

sensor_msgs::LaserScan make_scan(std::uint32_t i) {
  sensor_msgs::LaserScan s;
  s.header.seq = i;
  s.header.stamp = ::ros::Time(1700000000 + i, 250000000U + i);
  s.header.frame_id = "front_laser";
  s.angle_min = -1.5F;
  s.angle_max = 1.5F;
  s.angle_increment = 0.25F;
  s.time_increment = 0.001F;
  s.scan_time = 0.1F;
  s.range_min = 0.1F;
  s.range_max = 30.0F;
  for (int k = 0; k < 13; ++k) {
    s.ranges.push_back(1.0F + static_cast<float>(k) * 0.5F + static_cast<float>(i));
    s.intensities.push_back(static_cast<float>(100 + k));
  }
  return s;
}

class WrittenBag : public ::testing::TestWithParam<rosbag::compression::CompressionType> {};

TEST_P(WrittenBag, EveryDecodedTypeReadsBackFieldByField) {
  TempDir dir;
  const std::string path = dir.file("written.bag");
  constexpr std::uint32_t kScans = 40;
  {
    rosbag::Bag out(path, rosbag::bagmode::Write);
    out.setCompression(GetParam());
    out.setChunkThreshold(2048);  // several chunks
    for (std::uint32_t i = 0; i < kScans; ++i) {
      out.write("/scan", ::ros::Time(1700000000 + i, 500000000U), make_scan(i));
    }
    nav_msgs::Odometry o;
    o.header.stamp = ::ros::Time(1700000100, 7);
    o.header.frame_id = "odom";
    o.child_frame_id = "base_link";
    o.pose.pose.position.x = 1.5;
    o.pose.pose.position.y = -2.25;
    o.pose.pose.position.z = 0.125;
    o.pose.pose.orientation.z = std::sin(0.3);
    o.pose.pose.orientation.w = std::cos(0.3);
    for (std::size_t k = 0; k < 36; ++k) {
      o.pose.covariance[k] = static_cast<double>(k);
      o.twist.covariance[k] = -static_cast<double>(k);
    }
    o.twist.twist.linear.x = 0.5;
    o.twist.twist.angular.z = -0.1;
    out.write("/odom", ::ros::Time(1700000100, 9), o);

    tf2_msgs::TFMessage tf;
    geometry_msgs::TransformStamped t;
    t.header.stamp = ::ros::Time(1700000101, 3);
    t.header.frame_id = "map";
    t.child_frame_id = "odom";
    t.transform.translation.x = 10.0;
    t.transform.translation.y = 20.0;
    t.transform.translation.z = 30.0;
    t.transform.rotation.x = 0.5;
    t.transform.rotation.y = 0.5;
    t.transform.rotation.z = 0.5;
    t.transform.rotation.w = 0.5;
    tf.transforms.push_back(t);
    t.child_frame_id = "odom2";
    tf.transforms.push_back(t);
    out.write("/tf", ::ros::Time(1700000101, 4), tf);

    geometry_msgs::PoseStamped ps;
    ps.header.stamp = ::ros::Time(1700000102, 1);
    ps.header.frame_id = "map";
    ps.pose.position.x = 3.0;
    ps.pose.orientation.w = 1.0;
    out.write("/goal", ::ros::Time(1700000102, 2), ps);

    geometry_msgs::PoseWithCovarianceStamped pc;
    pc.header.stamp = ::ros::Time(1700000103, 1);
    pc.header.frame_id = "map";
    pc.pose.pose.position.y = 4.0;
    pc.pose.pose.orientation.w = 1.0;
    pc.pose.covariance[35] = 0.07;
    out.write("/initialpose", ::ros::Time(1700000103, 2), pc);

    sensor_msgs::Imu imu;
    imu.header.stamp = ::ros::Time(1700000104, 1);
    imu.header.frame_id = "imu";
    imu.orientation.w = 1.0;
    imu.orientation_covariance[0] = -1.0;
    imu.angular_velocity.z = 0.25;
    imu.angular_velocity_covariance[8] = 0.01;
    imu.linear_acceleration.x = 9.81;
    imu.linear_acceleration_covariance[4] = 0.02;
    out.write("/imu", ::ros::Time(1700000104, 2), imu);

    sensor_msgs::PointCloud2 pc2;
    pc2.header.stamp = ::ros::Time(1700000105, 1);
    pc2.header.frame_id = "lidar";
    pc2.height = 1;
    pc2.width = 2;
    sensor_msgs::PointField f;
    f.name = "x";
    f.offset = 0;
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    pc2.fields.push_back(f);
    pc2.point_step = 4;
    pc2.row_step = 8;
    pc2.is_dense = 1;
    const float xs[2] = {1.25F, -7.5F};
    pc2.data.resize(8);
    std::memcpy(pc2.data.data(), xs, 8);
    out.write("/points", ::ros::Time(1700000105, 2), pc2);
    out.close();
  }

  auto bag = BagReader::open(path);
  const BagTopic* scans_topic = find_topic(*bag, "/scan");
  ASSERT_NE(scans_topic, nullptr);
  EXPECT_EQ(scans_topic->count, kScans);
  EXPECT_EQ(scans_topic->first_ns, 1700000000500000000);
  EXPECT_EQ(scans_topic->last_ns, 1700000039500000000);
  EXPECT_EQ(bag->topics().size(), 7U);
  EXPECT_EQ(bag->size_bytes(), fs::file_size(path));

  const std::vector<BagMessage> scans = read_all(*bag, {"/scan"});
  ASSERT_EQ(scans.size(), kScans);
  for (std::uint32_t i = 0; i < kScans; ++i) {
    const auto s = vdtnav::ros::decode_laser_scan(scans[i]);
    const auto e = make_scan(i);
    EXPECT_EQ(scans[i].recorded_ns, 1700000000500000000 + std::int64_t{i} * 1000000000);
    EXPECT_EQ(s.header.stamp_ns, (1700000000LL + i) * 1000000000LL + 250000000LL + i);
    EXPECT_EQ(s.header.frame_id, "front_laser");
    EXPECT_EQ(s.angle_min, e.angle_min);
    EXPECT_EQ(s.angle_max, e.angle_max);
    EXPECT_EQ(s.angle_increment, e.angle_increment);
    EXPECT_EQ(s.time_increment, e.time_increment);
    EXPECT_EQ(s.scan_time, e.scan_time);
    EXPECT_EQ(s.range_min, e.range_min);
    EXPECT_EQ(s.range_max, e.range_max);
    EXPECT_EQ(s.ranges, e.ranges);
    EXPECT_EQ(s.intensities, e.intensities);
  }

  const std::vector<BagMessage> all = read_all(*bag, {});
  ASSERT_EQ(all.size(), kScans + 6);
  std::map<std::string, BagMessage> by_topic;
  for (const BagMessage& m : all) by_topic[m.topic] = m;

  const auto o = vdtnav::ros::decode_odometry(by_topic.at("/odom"));
  EXPECT_EQ(by_topic.at("/odom").recorded_ns, 1700000100000000009);
  EXPECT_EQ(o.header.stamp_ns, 1700000100000000007);
  EXPECT_EQ(o.header.frame_id, "odom");
  EXPECT_EQ(o.child_frame_id, "base_link");
  EXPECT_EQ(o.pose.pose.position, Eigen::Vector3d(1.5, -2.25, 0.125));
  EXPECT_EQ(o.pose.pose.orientation.z(), std::sin(0.3));
  EXPECT_EQ(o.pose.pose.orientation.w(), std::cos(0.3));
  for (std::size_t k = 0; k < 36; ++k) {
    EXPECT_EQ(o.pose.covariance[k], static_cast<double>(k));
    EXPECT_EQ(o.twist.covariance[k], -static_cast<double>(k));
  }
  EXPECT_EQ(o.twist.linear, Eigen::Vector3d(0.5, 0, 0));
  EXPECT_EQ(o.twist.angular, Eigen::Vector3d(0, 0, -0.1));

  const auto tf = vdtnav::ros::decode_tf(by_topic.at("/tf"));
  ASSERT_EQ(tf.transforms.size(), 2U);
  EXPECT_EQ(tf.transforms[0].header.stamp_ns, 1700000101000000003);
  EXPECT_EQ(tf.transforms[0].header.frame_id, "map");
  EXPECT_EQ(tf.transforms[0].child_frame_id, "odom");
  EXPECT_EQ(tf.transforms[1].child_frame_id, "odom2");
  EXPECT_EQ(tf.transforms[0].translation, Eigen::Vector3d(10, 20, 30));
  EXPECT_EQ(tf.transforms[0].rotation.coeffs(), Eigen::Vector4d(0.5, 0.5, 0.5, 0.5));

  const auto ps = vdtnav::ros::decode_pose_stamped(by_topic.at("/goal"));
  EXPECT_EQ(ps.header.stamp_ns, 1700000102000000001);
  EXPECT_EQ(ps.pose.position, Eigen::Vector3d(3, 0, 0));
  EXPECT_EQ(ps.pose.orientation.w(), 1.0);

  const auto pc = vdtnav::ros::decode_pose_with_covariance_stamped(by_topic.at("/initialpose"));
  EXPECT_EQ(pc.header.frame_id, "map");
  EXPECT_EQ(pc.pose.pose.position, Eigen::Vector3d(0, 4, 0));
  EXPECT_EQ(pc.pose.covariance[35], 0.07);
  EXPECT_EQ(pc.pose.covariance[0], 0.0);

  const auto imu = vdtnav::ros::decode_imu(by_topic.at("/imu"));
  EXPECT_EQ(imu.header.stamp_ns, 1700000104000000001);
  EXPECT_EQ(imu.header.frame_id, "imu");
  EXPECT_EQ(imu.orientation.w(), 1.0);
  EXPECT_EQ(imu.orientation_covariance[0], -1.0);
  EXPECT_EQ(imu.angular_velocity, Eigen::Vector3d(0, 0, 0.25));
  EXPECT_EQ(imu.angular_velocity_covariance[8], 0.01);
  EXPECT_EQ(imu.linear_acceleration, Eigen::Vector3d(9.81, 0, 0));
  EXPECT_EQ(imu.linear_acceleration_covariance[4], 0.02);

  const auto cloud = vdtnav::ros::decode_point_cloud2(by_topic.at("/points"));
  EXPECT_EQ(cloud.header.frame_id, "lidar");
  EXPECT_EQ(cloud.width, 2U);
  ASSERT_EQ(cloud.fields.size(), 1U);
  EXPECT_EQ(cloud.fields[0].name, "x");
  EXPECT_EQ(cloud.fields[0].datatype, 7);
  EXPECT_TRUE(cloud.is_dense);
  ASSERT_EQ(cloud.data.size(), 8U);
  float back[2];
  std::memcpy(back, cloud.data.data(), 8);
  EXPECT_EQ(back[0], 1.25F);
  EXPECT_EQ(back[1], -7.5F);

  // The chunks really are compressed the way asked (own walk of the first chunk's header).
  const std::vector<char> bytes = slurp(path);
  const Record header = record_at(bytes, 13);
  const Record chunk = record_at(bytes, header.data_pos + header.data_len);
  ASSERT_EQ(chunk.op(), 0x05);
  const char* expected = GetParam() == rosbag::compression::BZ2   ? "bz2"
                         : GetParam() == rosbag::compression::LZ4 ? "lz4"
                                                                  : "none";
  EXPECT_EQ(chunk.fields.at("compression"), expected);
}

INSTANTIATE_TEST_SUITE_P(Compression, WrittenBag,
                         ::testing::Values(rosbag::compression::Uncompressed,
                                           rosbag::compression::BZ2, rosbag::compression::LZ4));

TEST(Ros1Bag, WrittenBz2BagCutInAChunkIsRefused) {
  TempDir dir;
  const std::string path = dir.file("bz2.bag");
  {
    rosbag::Bag out(path, rosbag::bagmode::Write);
    out.setCompression(rosbag::compression::BZ2);
    for (std::uint32_t i = 0; i < 5; ++i) out.write("/scan", ::ros::Time(1 + i, 0), make_scan(i));
  }
  std::vector<char> bytes = slurp(path);
  const Record header = record_at(bytes, 13);
  const Record chunk = record_at(bytes, header.data_pos + header.data_len);
  ASSERT_EQ(chunk.fields.at("compression"), "bz2");
  // Scramble the compressed bytes in the middle of the chunk: the structure is intact, the bz2
  // stream is not; reading must fail with FormatError, not crash.
  for (std::size_t k = chunk.data_pos + 20; k < chunk.data_pos + chunk.data_len - 4; ++k) {
    bytes[k] = static_cast<char>(bytes[k] ^ 0x5A);
  }
  const std::string broken = dir.file("bz2_scrambled.bag");
  spit(broken, bytes);
  expect_format_error(broken, "reading a message");
}

TEST(Ros1Bag, WrittenLz4BagWithScrambledChunkIsRefused) {
  TempDir dir;
  const std::string path = dir.file("lz4.bag");
  {
    rosbag::Bag out(path, rosbag::bagmode::Write);
    out.setCompression(rosbag::compression::LZ4);
    for (std::uint32_t i = 0; i < 5; ++i) out.write("/scan", ::ros::Time(1 + i, 0), make_scan(i));
  }
  std::vector<char> bytes = slurp(path);
  const Record header = record_at(bytes, 13);
  const Record chunk = record_at(bytes, header.data_pos + header.data_len);
  ASSERT_EQ(chunk.fields.at("compression"), "lz4");
  for (std::size_t k = chunk.data_pos + 20; k < chunk.data_pos + chunk.data_len - 4; ++k) {
    bytes[k] = static_cast<char>(bytes[k] ^ 0x5A);
  }
  const std::string broken = dir.file("lz4_scrambled.bag");
  spit(broken, bytes);
  expect_format_error(broken, "reading a message");
}

// -------------------------------------------------------------------------- read speed

TEST(Ros1Bag, ReadSpeed) {
  for (const std::string& path : {kTest1, kEmbag}) {
    if (!fs::exists(path)) continue;
    auto bag = BagReader::open(path);
    std::size_t messages = 0, bytes = 0;
    const int kRepeats = 5;
    const auto start = std::chrono::steady_clock::now();
    for (int r = 0; r < kRepeats; ++r) {
      bag->read({}, [&](const BagMessage& m) {
        ++messages;
        bytes += m.data.size();
        return true;
      });
    }
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double file_mb = static_cast<double>(bag->size_bytes()) * kRepeats / 1e6;
    std::cout << "[ speed    ] " << fs::path(path).filename().string() << ": " << file_mb / s
              << " MB/s of file, " << static_cast<double>(bytes) / 1e6 / s << " MB/s of messages, "
              << static_cast<double>(messages) / s << " messages/s\n";
    EXPECT_GT(messages, 0U);
  }
}

}  // namespace

namespace vdtnav::ros {
namespace {

// fuzz_ros_messages found it: a LaserScan whose ranges claim ~1e9 floats in 90 bytes. The
// decoder refuses the length before allocating anything (ros::serialization allocated 4 GB).
TEST(Ros1Decode, ALengthLargerThanTheBytesLeftIsRefusedBeforeAllocating) {
  std::ifstream in(
      std::string(VDTNAV_FUZZ_REGRESSIONS) + "/ros_messages-ros1-scan-huge-length.fuzz",
      std::ios::binary);
  ASSERT_TRUE(in);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), {});
  ASSERT_GT(bytes.size(), 1U);
  BagMessage m;
  m.format = BagFormat::kRos1;
  m.topic = "/scan";
  m.type = "sensor_msgs/LaserScan";
  m.data.assign(bytes.begin() + 1, bytes.end());  // the fuzzer's first byte picks the decoder
  try {
    (void)decode_laser_scan(m);
    FAIL() << "decoded";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("claims"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vdtnav::ros
