// The ROS 2 node `vdtnav_ros2_localizer` on a ROS 2 graph, as nav2 starts amcl: the node with
// `--ros-args -r __node:=amcl --params-file nav2_params.yaml` (amcl's parameter names), the map
// on /map (transient local, as map_server publishes it), and the real TurtleBot 4 bag
// (olin-tb4-ros2: CDR written by a ROS 2 system) played with its payloads as recorded by
// `vdtnav bag play`. Every
// `amcl_pose` must equal `vdtnav localize --bag`'s pose of the same scan (the CLI's published
// scans, to 1e-9), and map -> odom must be on /tf. Every DDS participant is on the loopback
// interface (ROS_LOCALHOST_ONLY=1: unicast discovery on 127.0.0.1, no multicast), in a domain of
// its own per test process; every process the test starts is stopped by it.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "../../child_process.hpp"
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros2/dds.hpp"

namespace {

namespace fs = std::filesystem;
namespace vr = vdtnav::ros;
namespace v2 = vdtnav::ros2;
using Clock = std::chrono::steady_clock;
using vdtnav::testing::Child;

const fs::path kOlin = fs::path(VDTNAV_DATA_DIR) / "rosbags" / "olin-tb4-ros2";
const fs::path kBag = kOlin / "macfirst_floor_take_2";
const fs::path kMap = kOlin / "mac_1st_floor_final.yaml";
// Where `vdtnav localize --bag ... --init global` finds the first scan (its first TUM pose).
constexpr double kInit[3] = {6.878, -8.426, 1.777};

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Pose {
  double x = 0, y = 0, qz = 0, qw = 1;
};

/// A TUM file's poses by stamp (ns, rounded: the CLI prints the stamp in seconds).
std::map<std::int64_t, Pose> read_tum(const fs::path& p) {
  std::map<std::int64_t, Pose> out;
  std::ifstream in(p);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    long double t = 0;
    double z = 0, qx = 0, qy = 0;
    Pose q;
    s >> t >> q.x >> q.y >> z >> qx >> qy >> q.qz >> q.qw;
    out[static_cast<std::int64_t>(std::llround(t * 1e6L))] = q;  // microseconds
  }
  return out;
}

class Ros2Node : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // Loopback only, and a domain of this process's own (tests may run side by side).
    ::setenv("ROS_LOCALHOST_ONLY", "1", 1);
    ::setenv("ROS_DOMAIN_ID", std::to_string(10 + ::getpid() % 200).c_str(), 1);
  }

  void SetUp() override {
    if (!fs::exists(kBag / "metadata.yaml")) GTEST_SKIP() << "no " << kBag;
    dir_ = fs::path(VDTNAV_TEST_TMP) / ("ros2_node_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }

  fs::path dir_;
};

TEST_F(Ros2Node, AmclPoseEqualsTheCliOnTheTurtleBot4Bag) {
  // The CLI on the same bag, map and start.
  char init[96];
  std::snprintf(init, sizeof init, "%.17g,%.17g,%.17g", kInit[0], kInit[1], kInit[2]);
  const fs::path cli_tum = dir_ / "cli.tum";
  {
    Child cli({VDTNAV_CLI, "localize", "--bag", kBag.string(), "--map", kMap.string(), "--init",
               init, "--base-frame", "base_link", "--out", cli_tum.string()},
              dir_ / "cli.log");
    int st = 0;
    ASSERT_TRUE(cli.wait_exit(300.0, &st));
    ASSERT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0) << read(dir_ / "cli.log");
  }
  const std::map<std::int64_t, Pose> cli = read_tum(cli_tum);
  ASSERT_GT(cli.size(), 300U) << read(dir_ / "cli.log");

  // nav2's way: a params file with an `amcl: ros__parameters:` block (nested keys: dotted).
  const fs::path params = dir_ / "nav2_params.yaml";
  {
    char start[160];
    std::snprintf(start, sizeof start, "      x: %.17g\n      y: %.17g\n      yaw: %.17g\n",
                  kInit[0], kInit[1], kInit[2]);
    std::ofstream(params) << "amcl:\n  ros__parameters:\n    base_frame_id: \"base_link\"\n"
                          << "    odom_frame_id: \"odom\"\n    global_frame_id: \"map\"\n"
                          << "    scan_topic: scan\n    transform_tolerance: 1.0\n"
                          << "    set_initial_pose: true\n    initial_pose:\n"
                          << start;
  }

  v2::ParticipantOptions po;
  po.name = "ros2_node_test";
  v2::Participant graph(po);
  ASSERT_TRUE(graph.loopback());
  std::mutex m;
  std::map<std::int64_t, vr::PoseWithCovarianceStampedMsg> heard;
  std::vector<vr::TransformStampedMsg> map_to_odom;
  Clock::time_point last = Clock::now();
  auto poses = graph.reader(
      "/amcl_pose", "geometry_msgs/msg/PoseWithCovarianceStamped",
      v2::Qos{v2::Qos::Reliability::kReliable, v2::Qos::Durability::kTransientLocal, 1000},
      [&](const v2::Sample& s) {
        vr::BagMessage msg{vr::BagFormat::kRos2, "/amcl_pose",
                           "geometry_msgs/msg/PoseWithCovarianceStamped", 0, s.cdr};
        const auto p = vr::decode_pose_with_covariance_stamped(msg);
        std::lock_guard<std::mutex> lock(m);
        heard[p.header.stamp_ns] = p;
        last = Clock::now();
      });
  auto tf = graph.reader(
      "/tf", "tf2_msgs/msg/TFMessage",
      v2::Qos{v2::Qos::Reliability::kReliable, v2::Qos::Durability::kVolatile, 1000},
      [&](const v2::Sample& s) {
        vr::BagMessage msg{vr::BagFormat::kRos2, "/tf", "tf2_msgs/msg/TFMessage", 0, s.cdr};
        std::lock_guard<std::mutex> lock(m);
        for (const auto& t : vr::decode_tf(msg).transforms) {
          if (t.header.frame_id == "map" && t.child_frame_id == "odom") map_to_odom.push_back(t);
        }
      });
  const fs::path log = dir_ / "node.log";
  Child node({VDTNAV_ROS2_LOCALIZER, "--ros-args", "-r", "__node:=amcl", "--params-file",
              params.string(), "--log-level", "info"},
             log);

  // The other vendor's peer (Cyclone DDS, its type support generated from ROS 2's message
  // definitions) hears what the node publishes.
  const fs::path peer_log = dir_ / "peer.log";
  std::unique_ptr<Child> peer;
#ifdef VDTNAV_ROS2_PEER
  peer = std::make_unique<Child>(
      std::vector<std::string>{VDTNAV_ROS2_PEER, "--domain", std::getenv("ROS_DOMAIN_ID"),
                               "--listen", "amcl_pose:pose_with_covariance_stamped:reliable",
                               "--listen", "tf:tf:reliable", "--timeout", "0"},
      peer_log);
  const auto peer_until = Clock::now() + std::chrono::seconds(30);
  while (read(peer_log).find("rt/amcl_pose: 1 writer(s) matched") == std::string::npos &&
         Clock::now() < peer_until) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
#endif
  // `vdtnav bag play` as a user runs it: the map first (as map_server), then the bag's payloads
  // as recorded, once the node subscribes.
  {
    Child play({VDTNAV_CLI, "bag", "play", kBag.string(), "--topics", "/scan,/tf,/tf_static",
                "--map", kMap.string(), "--rate", "3", "--wait-for-readers", "30"},
               dir_ / "play.log");
    int st = 0;
    ASSERT_TRUE(play.wait_exit(120.0, &st)) << "bag play did not finish";
    ASSERT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0) << read(dir_ / "play.log");
  }
  EXPECT_NE(read(dir_ / "play.log").find("1313 messages"), std::string::npos)  // 1 + 357 + 953 + 2
      << read(dir_ / "play.log");
  // Until the node has been silent for 3 s.
  for (;;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    std::lock_guard<std::mutex> lock(m);
    if (Clock::now() - last > std::chrono::seconds(3)) break;
  }
  node.stop();
  if (peer) peer->stop();

  std::lock_guard<std::mutex> lock(m);
  std::size_t compared = 0;
  double worst = 0.0;
  for (const auto& [stamp_ns, p] : heard) {
    // The CLI prints stamps to 17 digits (0.1 us): the nearest within 1 us.
    auto it = cli.lower_bound(stamp_ns / 1000 - 1);
    ASSERT_TRUE(it != cli.end() && std::llabs(it->first - stamp_ns / 1000) <= 1)
        << "a pose the CLI does not publish, at " << stamp_ns << " ns";
    const Pose& c = it->second;
    EXPECT_EQ(p.header.frame_id, "map");
    worst = std::max({worst, std::abs(p.pose.pose.position.x() - c.x),
                      std::abs(p.pose.pose.position.y() - c.y),
                      std::abs(p.pose.pose.orientation.z() - c.qz),
                      std::abs(p.pose.pose.orientation.w() - c.qw)});
    ++compared;
  }
  for (const auto& [us, c] : cli) {
    const auto h = heard.lower_bound(us * 1000 - 1000);
    if (h == heard.end() || std::llabs(h->first / 1000 - us) > 1) {
      std::printf("the CLI's pose at %lld us is not on amcl_pose\n", static_cast<long long>(us));
    }
  }
  EXPECT_EQ(compared, cli.size()) << "poses heard from the node / published by the CLI; log:\n"
                                  << read(log);
  EXPECT_LT(worst, 1e-9);
  std::printf("compared %zu poses with the CLI's, largest difference %.3g\n", compared, worst);
  EXPECT_GE(map_to_odom.size(), cli.size());

#ifdef VDTNAV_ROS2_PEER
  // The peer's lines: "amcl_pose SEC.NSEC FRAME x y z qx qy qz qw c0 .. c35" and
  // "tf SEC.NSEC PARENT CHILD tx ty tz qx qy qz qw", doubles to 17 digits (exact).
  std::size_t peer_poses = 0, peer_equal = 0, peer_map_to_odom = 0;
  std::istringstream lines(read(peer_log));
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream f(line);
    std::string topic, stamp, frame;
    f >> topic >> stamp >> frame;
    if (topic == "tf") {
      std::string child;
      f >> child;
      peer_map_to_odom += frame == "map" && child == "odom";
      continue;
    }
    if (topic != "amcl_pose") continue;
    ++peer_poses;
    const std::size_t dot = stamp.find('.');
    const std::int64_t ns =
        std::stoll(stamp.substr(0, dot)) * 1000000000LL + std::stoll(stamp.substr(dot + 1));
    double x = 0, y = 0, z = 0, qx = 0, qy = 0, qz = 0, qw = 0, c0 = 0;
    f >> x >> y >> z >> qx >> qy >> qz >> qw >> c0;
    const auto h = heard.find(ns);
    if (h == heard.end()) continue;
    const auto& p = h->second.pose;
    peer_equal += frame == "map" && x == p.pose.position.x() && y == p.pose.position.y() &&
                  qz == p.pose.orientation.z() && qw == p.pose.orientation.w() &&
                  c0 == p.covariance[0];
  }
  EXPECT_EQ(peer_poses, heard.size()) << read(peer_log).substr(0, 2000);
  EXPECT_EQ(peer_equal, heard.size());
  EXPECT_GE(peer_map_to_odom, heard.size());
  std::printf("the Cyclone DDS peer heard %zu poses (%zu equal to Fast DDS's), %zu map -> odom\n",
              peer_poses, peer_equal, peer_map_to_odom);
#endif
}

}  // namespace
