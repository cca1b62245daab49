// `vdtnav bag info` and `vdtnav localize --bag` on the shared real bags (../shared/data/rosbags),
// as a user runs them: what the bag holds (the README's counts and frames), where a run starts
// (the README: the TurtleBot's first scan lies about 0.5 m / 4 degrees from its odometry pose in
// the map frame), one pose-table row per scan, and errors that name what the bag has.
// Skips when the data is absent.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "imu_runs.hpp"
#include "vdtnav/io/tum_trajectory.hpp"
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros/cloud_points.hpp"
#include "vdtnav/ros/scan_sequence.hpp"
#include "vdtnav/sim/lidar3d_simulator.hpp"

namespace vdtnav {
namespace {

namespace fs = std::filesystem;
using test::contains;
using test::read_all;
using test::run_cli;

const fs::path kBags = fs::path(VDTNAV_DATA_DIR) / "rosbags";
const fs::path kOlin = kBags / "olin-tb4-ros2";
const fs::path kIst = kBags / "ist-pioneer3dx";
const fs::path kLz4 = kBags / "embag-lz4" / "test.bag";

fs::path work_dir(const std::string& name) {
  const fs::path d = fs::path(VDTNAV_TEST_TMP) / (name + "_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

std::size_t lines_of(const fs::path& p) {
  std::ifstream in(p);
  std::size_t n = 0;
  for (std::string l; std::getline(in, l);) n += l.empty() ? 0 : 1;
  return n;
}

TEST(CliBags, BagInfoListsTopicsCountsAndTheTfTreeOfBothFormats) {
  if (!fs::exists(kOlin)) GTEST_SKIP() << "no " << kOlin;
  const fs::path d = work_dir("bag_info");
  ASSERT_EQ(run_cli("bag info " + (kOlin / "macfirst_floor_take_2").string(), d / "olin.txt"), 0)
      << read_all(d / "olin.txt");
  const std::string olin = read_all(d / "olin.txt");
  EXPECT_TRUE(contains(olin, "ROS 2 bag")) << olin;
  EXPECT_TRUE(contains(olin, "/scan                  357 msgs")) << olin;
  EXPECT_TRUE(contains(olin, "/odom                  920 msgs")) << olin;
  EXPECT_TRUE(contains(olin, "rplidar_link <- base_link")) << olin;
  EXPECT_TRUE(contains(olin, "base_footprint <- odom")) << olin;
  if (!fs::exists(kIst / "test1.bag")) return;
  ASSERT_EQ(run_cli("bag info " + (kIst / "test1.bag").string(), d / "ist.txt"), 0)
      << read_all(d / "ist.txt");
  const std::string ist = read_all(d / "ist.txt");
  EXPECT_TRUE(contains(ist, "ROS 1 bag")) << ist;
  EXPECT_TRUE(contains(ist, "311 msgs")) << ist;
  EXPECT_TRUE(contains(ist, "base_link <- odom")) << ist;
  EXPECT_FALSE(contains(ist, "<- base_link")) << ist;  // no mounting transform in that bag
  fs::remove_all(d);
}

TEST(CliBags, LocalizesTheTurtlebotBagFromNoPriorWhereItsOdometryStarts) {
  if (!fs::exists(kOlin)) GTEST_SKIP() << "no " << kOlin;
  const fs::path d = work_dir("bag_olin");
  const fs::path bag = kOlin / "macfirst_floor_take_2";
  const std::string args = "localize --map " + (kOlin / "mac_1st_floor_final.yaml").string() +
                           " --bag " + bag.string() + " --init global --quiet --out " +
                           (d / "olin.tum").string() + " --cov " + (d / "olin.csv").string();
  ASSERT_EQ(run_cli(args, d / "olin.txt"), 0) << read_all(d / "olin.txt");
  // One pose-table row per scan the run holds (the bag's scans with odometry at their stamps).
  const std::unique_ptr<ros::BagReader> reader = ros::BagReader::open(bag.string());
  const ros::ScanSequence seq = ros::read_scan_sequence(*reader, {});
  EXPECT_EQ(seq.scans.size() + seq.skipped_no_odometry, 357U);
  // One pose-table row per input scan: those without odometry at their stamp too (no_odometry).
  EXPECT_EQ(lines_of(d / "olin.csv"), 1U + 357U);
  const std::string table = read_all(d / "olin.csv");
  std::size_t without = 0;
  for (std::size_t at = table.find(",no_odometry,"); at != std::string::npos;
       at = table.find(",no_odometry,", at + 1)) {
    ++without;
  }
  EXPECT_EQ(without, seq.skipped_no_odometry);
  EXPECT_EQ(seq.skipped_no_odometry, 1U);  // the last scan comes after the last /tf
  // The first pose: the map frame is the odometry's within the README's 0.5 m / 4 degrees.
  const std::vector<StampedPose3> tum = load_tum_trajectory((d / "olin.tum").string()).poses;
  ASSERT_FALSE(tum.empty());
  const Pose2 odom0 = seq.odometry.front();
  EXPECT_NEAR(tum.front().t, seq.scans.front().time, 1e-3);
  const Eigen::Vector3d t = tum.front().pose.translation();
  EXPECT_LT(std::hypot(t.x() - odom0[0], t.y() - odom0[1]), 1.0);
  EXPECT_LT(std::abs(wrap_angle(ros::planar(tum.front().pose)[2] - odom0[2])), 0.15);
  fs::remove_all(d);
}

// The two things a user's own bag meets first (issue 59): a scan older than the first mounting
// transform, and a second LaserScan topic. The TurtleBot 4 bag rewritten as a ROS 1 bag whose
// mounting base_link -> rplidar_link is on /tf from the second scan's stamp on (not /tf_static),
// with a /scan_raw beside /scan whose ranges are 10 % long: the first scan is a no_transform row,
// /scan is taken and said, and every other row equals the original bag's run from its second
// scan on.
::ros::Time ros_time(std::int64_t ns) {
  ::ros::Time t;
  t.fromNSec(static_cast<std::uint64_t>(ns));
  return t;
}

geometry_msgs::TransformStamped to_ros1(const ros::TransformStampedMsg& s) {
  geometry_msgs::TransformStamped o;
  o.header.stamp = ros_time(s.header.stamp_ns);
  o.header.frame_id = s.header.frame_id;
  o.child_frame_id = s.child_frame_id;
  o.transform.translation.x = s.translation.x();
  o.transform.translation.y = s.translation.y();
  o.transform.translation.z = s.translation.z();
  o.transform.rotation.x = s.rotation.x();
  o.transform.rotation.y = s.rotation.y();
  o.transform.rotation.z = s.rotation.z();
  o.transform.rotation.w = s.rotation.w();
  return o;
}

sensor_msgs::LaserScan to_ros1(const ros::LaserScanMsg& s, float range_scale) {
  sensor_msgs::LaserScan o;
  o.header.stamp = ros_time(s.header.stamp_ns);
  o.header.frame_id = s.header.frame_id;
  o.angle_min = s.angle_min;
  o.angle_max = s.angle_max;
  o.angle_increment = s.angle_increment;
  o.time_increment = s.time_increment;
  o.scan_time = s.scan_time;
  o.range_min = s.range_min;
  o.range_max = s.range_max;
  for (const float r : s.ranges) o.ranges.push_back(r * range_scale);
  o.intensities = s.intensities;
  return o;
}

/// The rows of a --cov table by stamp (its first column), the header left out.
std::vector<std::string> rows_of(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> rows;
  std::string l;
  std::getline(in, l);
  while (std::getline(in, l)) rows.push_back(l);
  return rows;
}

TEST(CliBags, AScanBeforeTheFirstMountingTransformIsARowAndTheTopicNamedScanIsTaken) {
  if (!fs::exists(kOlin)) GTEST_SKIP() << "no " << kOlin;
  const fs::path d = work_dir("bag_mount");
  const fs::path original = kOlin / "macfirst_floor_take_2";
  const std::unique_ptr<ros::BagReader> reader = ros::BagReader::open(original.string());
  std::vector<std::int64_t> scan_stamps;
  std::optional<ros::TransformStampedMsg> mount;
  {
    rosbag::Bag out((d / "late_mount.bag").string(), rosbag::bagmode::Write);
    reader->read({"/scan", "/tf", "/tf_static"}, [&](const ros::BagMessage& m) {
      const ::ros::Time at = ros_time(m.recorded_ns);
      if (m.topic == "/scan") {
        const ros::LaserScanMsg s = ros::decode_laser_scan(m);
        scan_stamps.push_back(s.header.stamp_ns);
        out.write("/scan", at, to_ros1(s, 1.0F));
        out.write("/scan_raw", at, to_ros1(s, 1.1F));
        return true;
      }
      tf2_msgs::TFMessage tf;
      for (const ros::TransformStampedMsg& t : ros::decode_tf(m).transforms) {
        if (t.child_frame_id == "rplidar_link") {
          mount = t;
          continue;
        }
        tf.transforms.push_back(to_ros1(t));
      }
      if (!tf.transforms.empty()) out.write(m.topic, at, tf);
      return true;
    });
    ASSERT_TRUE(mount) << "the bag's /tf_static holds base_link -> rplidar_link";
    ASSERT_GT(scan_stamps.size(), 2U);
    // The mounting from the second scan's stamp on, at 10 Hz, to a second after the last scan.
    for (std::int64_t t = scan_stamps[1]; t < scan_stamps.back() + 1'000'000'000;
         t += 100'000'000) {
      ros::TransformStampedMsg m = *mount;
      m.header.stamp_ns = t;
      tf2_msgs::TFMessage tf;
      tf.transforms.push_back(to_ros1(m));
      out.write("/tf", ros_time(t), tf);
    }
    out.close();
  }
  const std::string map = (kOlin / "mac_1st_floor_final.yaml").string();
  const auto localize = [&](const fs::path& bag, const std::string& name, const std::string& more) {
    return run_cli("localize --map " + map + " --bag " + bag.string() + " --init global --out " +
                       (d / (name + ".tum")).string() + " --cov " + (d / (name + ".csv")).string() +
                       more,
                   d / (name + ".txt"));
  };
  // The original from its second scan on: the run the rewritten bag must give.
  char from[64];
  std::snprintf(from, sizeof from, " --from %.6f",
                static_cast<double>(scan_stamps[1]) * 1e-9 - 0.001);
  ASSERT_EQ(localize(original, "original", from), 0) << read_all(d / "original.txt");
  ASSERT_EQ(localize(d / "late_mount.bag", "late", ""), 0) << read_all(d / "late.txt");
  const std::string said = read_all(d / "late.txt");
  EXPECT_TRUE(contains(said, "/scan of 2 LaserScan topics")) << said;
  EXPECT_TRUE(contains(said, "1 scans older than the first mounting transform left out")) << said;

  const std::vector<std::string> was = rows_of(d / "original.csv");
  const std::vector<std::string> now = rows_of(d / "late.csv");
  ASSERT_EQ(was.size() + 1, scan_stamps.size());
  ASSERT_EQ(now.size(), scan_stamps.size());  // a row for every scan
  EXPECT_TRUE(contains(now[0], ",no_transform,")) << now[0];
  for (std::size_t i = 1; i < now.size(); ++i) EXPECT_EQ(now[i], was[i - 1]) << "row " << i;
  EXPECT_EQ(read_all(d / "late.tum"), read_all(d / "original.tum"));

  // Named, the other topic is taken (and its long ranges move the poses).
  ASSERT_EQ(run_cli("localize --map " + map + " --bag " + (d / "late_mount.bag").string() +
                        " --scan-topic /scan_raw --init global --out " + (d / "raw.tum").string(),
                    d / "raw.txt"),
            0)
      << read_all(d / "raw.txt");
  EXPECT_FALSE(contains(read_all(d / "raw.txt"), "LaserScan topics")) << read_all(d / "raw.txt");
  EXPECT_NE(read_all(d / "raw.tum"), read_all(d / "original.tum"));
  fs::remove_all(d);
}

TEST(CliBags, ErrorsNameWhatTheBagHas) {
  if (!fs::exists(kOlin)) GTEST_SKIP() << "no " << kOlin;
  const fs::path d = work_dir("bag_errors");
  const std::string base = "localize --map " + (kOlin / "mac_1st_floor_final.yaml").string() +
                           " --bag " + (kOlin / "macfirst_floor_take_2").string() + " --out " +
                           (d / "out.tum").string();
  EXPECT_EQ(run_cli(base, d / "noinit.txt"), 2) << read_all(d / "noinit.txt");  // no --init
  EXPECT_TRUE(contains(read_all(d / "noinit.txt"), "--init")) << read_all(d / "noinit.txt");
  EXPECT_EQ(run_cli(base + " --init 0,0,0 --scan-topic /nope", d / "topic.txt"), 1);
  EXPECT_TRUE(contains(read_all(d / "topic.txt"), "/scan (sensor_msgs/msg/LaserScan, 357)"))
      << read_all(d / "topic.txt");
  EXPECT_EQ(
      run_cli(base + " --init 0,0,0 --base-frame chassis --odom-topic /cmd_vel", d / "odom.txt"),
      1);
  EXPECT_TRUE(contains(read_all(d / "odom.txt"), "not nav_msgs/Odometry"))
      << read_all(d / "odom.txt");
  if (fs::exists(kIst / "test1.bag")) {
    // No base_link -> laser transform in this bag: the error says so and what to give.
    EXPECT_EQ(run_cli("localize --map " + (kIst / "map.yaml").string() + " --bag " +
                          (kIst / "test1.bag").string() + " --init 0,0,0 --out " +
                          (d / "ist.tum").string(),
                      d / "ist.txt"),
              1);
    const std::string ist = read_all(d / "ist.txt");
    EXPECT_TRUE(contains(ist, "base_link -> laser")) << ist;
    EXPECT_TRUE(contains(ist, "--laser-pose")) << ist;
  }
  EXPECT_EQ(test::files_in(d).size(), 3U + (fs::exists(kIst / "test1.bag") ? 1U : 0U))
      << "a failed run leaves no output";
  fs::remove_all(d);
}

TEST(CliBags, Localize3dTakesABagsCloudsOneRowEach) {
  if (!fs::exists(kLz4)) GTEST_SKIP() << "no " << kLz4;
  if (run_cli("localize3d --help", fs::path(VDTNAV_TEST_TMP) / "l3d_help.txt") != 0) {
    GTEST_SKIP() << "built without the 3D commands";
  }
  const fs::path d = work_dir("bag_3d");
  // The map: the bag's first Luminar cloud itself, written as text by the library's reader; that
  // cloud must then come out at the identity, the ones after it with a row each.
  std::int64_t first_stamp = 0;
  {
    std::ofstream xyz(d / "first.xyz");
    const auto bag = ros::BagReader::open(kLz4.string());
    bag->read({"/luminar_pointcloud"}, [&](const ros::BagMessage& m) {
      const ros::PointCloud2Msg msg = ros::decode_point_cloud2(m);
      first_stamp = msg.header.stamp_ns;
      for (const Eigen::Vector3d& p : ros::cloud_points(msg, m.topic).points)
        xyz << p.x() << ' ' << p.y() << ' ' << p.z() << '\n';
      return false;
    });
  }
  const std::string base = "localize3d --map " + (d / "first.xyz").string() +
                           " --resolution 0.2 --crop -40,-40,-10,40,40,10 --max-range 40 --bag " +
                           kLz4.string() + " --odom-topic none --init 0,0,0,0,0,0 --quiet";
  // No mounting transform in the bag: the error names the clouds' frame and the flag.
  EXPECT_EQ(run_cli(base + " --out " + (d / "nomount").string(), d / "nomount.txt"), 1);
  EXPECT_TRUE(contains(read_all(d / "nomount.txt"), "--lidar-pose")) << read_all(d / "nomount.txt");
  EXPECT_FALSE(fs::exists(d / "nomount"));
  ASSERT_EQ(
      run_cli(base + " --lidar-pose 0,0,0,0,0,0 --out " + (d / "out").string(), d / "out.txt"), 0)
      << read_all(d / "out.txt");
  EXPECT_EQ(lines_of(d / "out" / "status.csv"), 1U + 5U);  // a row per cloud, whatever its status
  const std::vector<StampedPose3> tum =
      load_tum_trajectory((d / "out" / "trajectory.tum").string()).poses;
  ASSERT_FALSE(tum.empty());
  EXPECT_NEAR(tum.front().t, 1e-9 * static_cast<double>(first_stamp), 1e-5);
  EXPECT_LT(tum.front().pose.translation().norm(), 0.05);
  EXPECT_LT(Eigen::AngleAxisd(tum.front().pose.linear()).angle(), 0.01);
  fs::remove_all(d);
}

// A ROS 1 bag as a spinning LiDAR and an IMU record it: the slalom of imu_runs.hpp scanned every
// 0.5 s (PointCloud2 in base_link, no odometry) with sensor_msgs/Imu at 200 Hz (rates,
// accelerations, orientation), localized with --imu-topic: the rates are preintegrated between
// the clouds as --imu does with a CSV; without them (constant velocity) the slalom is lost.
TEST(CliBags, Localize3dPreintegratesABagsImuBetweenItsClouds) {
  if (run_cli("localize3d --help", fs::path(VDTNAV_TEST_TMP) / "l3d_help.txt") != 0) {
    GTEST_SKIP() << "built without the 3D commands";
  }
  const fs::path d = work_dir("bag_imu");
  const OccupancyGrid<3> world = test::write_room_map(d / "room.csv");
  std::mt19937 rng(8);
  std::vector<Pose3> truth;
  {
    rosbag::Bag bag((d / "run.bag").string(), rosbag::bagmode::Write);
    for (const ImuSample& s : test::imu_along(test::slalom, 100.0, rng)) {
      sensor_msgs::Imu m;
      m.header.stamp = ::ros::Time(s.t);
      m.header.frame_id = "base_link";
      const Eigen::Quaterniond q(test::slalom(s.t - 100.0).pose.linear());
      m.orientation.x = q.x();
      m.orientation.y = q.y();
      m.orientation.z = q.z();
      m.orientation.w = q.w();
      m.angular_velocity.x = s.gyro.x();
      m.angular_velocity.y = s.gyro.y();
      m.angular_velocity.z = s.gyro.z();
      m.linear_acceleration.x = s.accel.x();
      m.linear_acceleration.y = s.accel.y();
      m.linear_acceleration.z = s.accel.z();
      bag.write("/imu", ::ros::Time(s.t), m);
    }
    sim::Lidar3dSpec spec;
    spec.azimuth_step = kPi / 180.0;
    for (int k = 0; k <= 8; ++k) {
      const double t = 100.0 + 0.5 * k;
      truth.push_back(test::slalom(t - 100.0).pose);
      const sim::Lidar3dScan scan = sim::simulate_lidar3d_scan(world, truth.back(), spec, rng);
      std::vector<float> xyz;
      for (const Eigen::Vector3d& p : scan.points) {
        if (!p.allFinite()) continue;
        xyz.insert(xyz.end(), {static_cast<float>(p.x()), static_cast<float>(p.y()),
                               static_cast<float>(p.z())});
      }
      sensor_msgs::PointCloud2 c;
      c.header.stamp = ::ros::Time(t);
      c.header.frame_id = "base_link";
      c.height = 1;
      c.width = static_cast<std::uint32_t>(xyz.size() / 3);
      c.point_step = 12;
      c.row_step = 12 * c.width;
      c.is_dense = true;
      for (const auto& [name, offset] : {std::pair<const char*, int>{"x", 0}, {"y", 4}, {"z", 8}}) {
        sensor_msgs::PointField f;
        f.name = name;
        f.offset = offset;
        f.datatype = sensor_msgs::PointField::FLOAT32;
        f.count = 1;
        c.fields.push_back(f);
      }
      c.data.resize(xyz.size() * sizeof(float));
      std::memcpy(c.data.data(), xyz.data(), c.data.size());
      bag.write("/points", ::ros::Time(t), c);
    }
    bag.close();
  }
  const std::string base = "localize3d --map " + (d / "room.csv").string() + " --bag " +
                           (d / "run.bag").string() +
                           " --odom-topic none --init 5.6,5.1,1.2,0,0,1.6";
  const auto worst = [&](const fs::path& out, std::size_t* poses) {
    const std::vector<StampedPose3> tum =
        load_tum_trajectory((out / "trajectory.tum").string()).poses;
    *poses = tum.size();
    double w = 0.0;
    for (const StampedPose3& p : tum) {
      const auto i = static_cast<std::size_t>(std::lround((p.t - 100.0) / 0.5));
      w = std::max(w, (p.pose.translation() - truth[i].translation()).norm());
    }
    return w;
  };
  ASSERT_EQ(run_cli(base + " --imu-topic /imu --out " + (d / "with").string(), d / "with.txt"), 0)
      << read_all(d / "with.txt");
  EXPECT_TRUE(contains(read_all(d / "with.txt"), "IMU: 8 of the 8 scans after the first"))
      << read_all(d / "with.txt");
  std::size_t n = 0;
  const double with = worst(d / "with", &n);
  EXPECT_EQ(n, 9U);
  EXPECT_LT(with, 0.03);
  run_cli(base + " --out " + (d / "without").string(), d / "without.txt");
  const double without = worst(d / "without", &n);
  std::printf(
      "bag with --imu-topic: 9 clouds within %.3f m; constant velocity: %zu converged, "
      "worst %.3f m\n",
      with, n, without);
  EXPECT_TRUE(n < 9 || without > 0.1);
  fs::remove_all(d);
}

}  // namespace
}  // namespace vdtnav
