// vdtnav::ros on the shared real bags: how fast the bag readers go (every message of the bag,
// MB/s and messages/s, both formats), and the node's path, LiveLocalizer, over a whole bag in
// the order the messages were recorded: the time per scan localized and the share of the work
// that reading and decoding the bag's scans and transforms is (issue target: <= 5 %).
// Skips when ../shared/data/rosbags is absent.
#include <benchmark/benchmark.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros/live_localizer.hpp"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const fs::path kBags = fs::path(VDTNAV_DATA_DIR) / "rosbags";

std::string bag_path(int which) {
  return which == 0 ? (kBags / "ist-pioneer3dx" / "test1.bag").string()
                    : (kBags / "olin-tb4-ros2" / "macfirst_floor_take_2").string();
}

/// Every message of the bag, read (ROS 1: rosbag_storage; ROS 2: sqlite3), not decoded.
void BM_RosBagRead(benchmark::State& state) {
  const std::string path = bag_path(static_cast<int>(state.range(0)));
  if (!fs::exists(path)) {
    state.SkipWithError(("no " + path).c_str());
    return;
  }
  const auto bag = vdtnav::ros::BagReader::open(path);
  std::size_t messages = 0, bytes = 0;
  for (auto _ : state) {
    bag->read({}, [&](const vdtnav::ros::BagMessage& m) {
      ++messages;
      bytes += m.data.size();
      return true;
    });
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(messages));  // messages/s
  state.SetBytesProcessed(static_cast<std::int64_t>(bytes));     // payload MB/s
  state.SetLabel(bag->format() == vdtnav::ros::BagFormat::kRos1 ? "ROS 1 ist-pioneer3dx"
                                                                : "ROS 2 olin-tb4-ros2");
}
BENCHMARK(BM_RosBagRead)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

/// The node's path on the IST bag (ROS 1): /scan and /tf read and decoded in recorded order and
/// fed to a LiveLocalizer started where `vdtnav localize --init global` names the best pose
/// (the corridors are ambiguous), the scanner at base_link (the bag has no mounting).
void BM_LiveLocalizerIstBag(benchmark::State& state) {
  const fs::path dir = kBags / "ist-pioneer3dx";
  if (!fs::exists(dir / "test1.bag")) {
    state.SkipWithError(("no " + dir.string()).c_str());
    return;
  }
  const vdtnav::RosMap map = vdtnav::load_ros_map((dir / "map.yaml").string());
  const auto bag = vdtnav::ros::BagReader::open((dir / "test1.bag").string());
  vdtnav::ros::LiveLocalizerOptions o;
  o.laser_pose = vdtnav::Pose2::Zero();
  double read_s = 0.0, localize_s = 0.0;
  std::size_t localized = 0, converged = 0;
  for (auto _ : state) {
    state.PauseTiming();
    vdtnav::ros::LiveLocalizer loc(map, vdtnav::log_settings(), o);  // the VDT build left out
    loc.set_pose(vdtnav::Pose2(-22.86, -7.67, 1.28),
                 Eigen::Vector3d(0.01, 0.01, 0.0025).asDiagonal());
    state.ResumeTiming();
    auto t = Clock::now();
    bag->read({"/scan", "/tf"}, [&](const vdtnav::ros::BagMessage& m) {
      const bool scan = m.topic == "/scan";
      const vdtnav::ros::LaserScanMsg s =
          scan ? vdtnav::ros::decode_laser_scan(m) : vdtnav::ros::LaserScanMsg{};
      const vdtnav::ros::TfMsg tf = scan ? vdtnav::ros::TfMsg{} : vdtnav::ros::decode_tf(m);
      const auto t1 = Clock::now();
      read_s += std::chrono::duration<double>(t1 - t).count();
      const std::vector<vdtnav::ros::LiveEstimate> e =
          scan ? loc.add_scan(s) : loc.add_transforms(tf, false);
      for (const auto& x : e) {
        if (x.event != vdtnav::ros::LiveEstimate::Event::kLocalized) continue;
        ++localized;
        converged += x.result.status == vdtnav::LocalizationStatus::kConverged;
      }
      t = Clock::now();
      localize_s += std::chrono::duration<double>(t - t1).count();
      return true;
    });
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["scans_localized"] = static_cast<double>(localized) / n;
  state.counters["converged"] = static_cast<double>(converged) / n;
  state.counters["ms_per_scan"] = 1e3 * localize_s / static_cast<double>(localized);
  state.counters["read_share"] = read_s / localize_s;  // reading and decoding / localizing
}
BENCHMARK(BM_LiveLocalizerIstBag)->Unit(benchmark::kMillisecond);

}  // namespace
