// The shared ROS bags (../shared/data/rosbags) localized on their maps, as `vdtnav localize --bag`
// does, without a ROS master: the TurtleBot 4's ROS 2 bag at Olin College and the Pioneer 3-DX's
// ROS 1 bag at IST Lisbon (its bag has no mounting transform: the robot's launch file publishes
// identity, given here as the laser pose). Both start with no prior (`--init global`): global
// localization on the first 50 scans, tracking with vdt-opt and log_settings() (lost detection
// and recovery on) from the first scan accepted.
//
// Writes table.csv (bag,scans,localized_pct,lost,mean_explained,ms_per_scan; localized_pct =
// converged scans / scans in the bag's run, mean_explained over the scans tracked,
// ms_per_scan the whole localization, global search included, per scan; ms_median, ms_p99
// (nearest rank) and ms_max of the tracked scans' updates), table.md
// (also where the run was acquired and every status), and <bag>_trajectory.png (the track on the
// map) and <bag>_scans.png (the scans reprojected from it). Bag reading time is reported apart
// (read_ms) against the localization's.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "plots.hpp"
#include "vdtnav/estimation/global_localization.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"
#include "vdtnav/io/log_odometry.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/ros/bag_reader.hpp"
#include "vdtnav/ros/scan_sequence.hpp"

using namespace vdtnav;

namespace {

struct Case {
  std::string name, bag, map;
  std::optional<Pose2> laser_pose;
};

struct Row {
  std::string bag;
  std::size_t scans = 0;
  std::optional<std::size_t> acquired;  // the first scan accepted by global localization
  std::map<LocalizationStatus, int> statuses;
  double explained_sum = 0.0, localize_ms = 0.0, read_ms = 0.0;
  int tracked = 0;
  std::vector<double> update_ms;  // each tracked scan's update
};

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

Row run(const Case& c, const std::filesystem::path& out) {
  Row row;
  row.bag = c.name;
  std::printf("[ros_bags] %s: %s on %s\n", c.name.c_str(), c.bag.c_str(), c.map.c_str());
  const RosMap ros_map = load_ros_map(c.map);
  const OccupancyGrid<2> grid = occupancy(ros_map);
  const VdtMap2 vdt = VdtMap2::build(grid);

  const auto t_read = std::chrono::steady_clock::now();
  const std::unique_ptr<ros::BagReader> bag = ros::BagReader::open(c.bag);
  ros::ScanSequenceOptions so;
  so.laser_pose = c.laser_pose;
  const ros::ScanSequence seq = ros::read_scan_sequence(*bag, so);
  row.read_ms = ms_since(t_read);
  row.scans = seq.scans.size();
  std::printf(
      "[ros_bags]   %zu scans of %s, odometry from %s, mounting from %s (read in %.0f ms)\n",
      row.scans, seq.scan_topic.c_str(), seq.odometry_source.c_str(), seq.mount_source.c_str(),
      row.read_ms);

  // --init global: the first scan global localization accepts (unambiguous), among the first 50.
  const LocalizerSettings settings = log_settings();
  GlobalLocalizationOptions g = settings.global;
  g.optimizer = settings.vdt_opt;
  const MapKnowledge knowledge(ros_map.cells);
  const GlobalLocalizer global(vdt, grid, g, knowledge);
  LocalizationResult start;
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < std::min<std::size_t>(row.scans, 50) && !row.acquired; ++k) {
    const GlobalLocalizationResult r = global.localize(scan_points(seq.scans[k]));
    if (r.result.status != LocalizationStatus::kConverged) continue;
    row.acquired = k;
    start = r.result;
  }
  std::vector<Pose2> track;
  std::vector<LaserScan> scans;
  if (row.acquired) {
    const std::vector<double> times = [&] {
      std::vector<double> t;
      for (const LaserScan& s : seq.scans) t.push_back(s.time);
      return t;
    }();
    const std::vector<OdometryStep> steps = odometry_steps(times, seq.odometry);
    const std::unique_ptr<Localizer2D> loc =
        make_localizer("vdt-opt", vdt, grid, settings, knowledge);
    loc->reset(start.pose, start.has_covariance
                               ? start.covariance
                               : Eigen::Matrix3d(Eigen::Vector3d(0.01, 0.01, 0.0025).asDiagonal()));
    for (std::size_t k = *row.acquired; k < row.scans; ++k) {
      const auto u0 = std::chrono::steady_clock::now();
      const LocalizationResult r =
          loc->update(k == *row.acquired ? OdometryStep{} : steps[k], seq.scans[k]);
      row.update_ms.push_back(ms_since(u0));
      ++row.statuses[r.status];
      ++row.tracked;
      if (r.explained >= 0.0) row.explained_sum += r.explained;
      track.push_back(r.pose);
      scans.push_back(seq.scans[k]);
    }
  }
  row.localize_ms = ms_since(t0);
  if (!track.empty()) {
    tools::plot_trajectories((out / (c.name + "_trajectory.png")).string(), ros_map,
                             {{"vdt-opt", track, false}}, c.name + ": vdt-opt from --init global");
    tools::plot_reprojected_scans((out / (c.name + "_scans.png")).string(), ros_map, track, scans,
                                  c.name + ": scans reprojected from the vdt-opt poses");
  }
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The shared ROS bags localized on their maps from no prior"};
  std::string data = "../shared/data", out = "out/ros_bags";
  app.add_option("--data", data, "The data folder (rosbags/ inside)")->capture_default_str();
  app.add_option("--out", out, "Output folder")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  const std::filesystem::path bags = std::filesystem::path(data) / "rosbags";
  const std::vector<Case> cases = {
      {"olin-tb4-ros2", (bags / "olin-tb4-ros2/macfirst_floor_take_2").string(),
       (bags / "olin-tb4-ros2/mac_1st_floor_final.yaml").string(), std::nullopt},
      {"ist-pioneer3dx", (bags / "ist-pioneer3dx/test1.bag").string(),
       (bags / "ist-pioneer3dx/map.yaml").string(), Pose2::Zero()}};
  std::filesystem::create_directories(out);
  std::vector<Row> rows;
  for (const Case& c : cases) {
    if (!std::filesystem::exists(c.bag)) {
      std::printf("[ros_bags] %s: not here (%s), skipped\n", c.name.c_str(), c.bag.c_str());
      continue;
    }
    rows.push_back(run(c, out));
  }
  std::ofstream csv(std::filesystem::path(out) / "table.csv");
  std::ofstream md(std::filesystem::path(out) / "table.md");
  csv << "bag,scans,localized_pct,lost,mean_explained,ms_per_scan,ms_median,ms_p99,ms_max,"
         "published_pct\n";
  md << "The shared ROS bags, vdt-opt from --init global (log_settings()):\n\n"
     << "| bag | scans | acquired at scan | converged | bridged | not converged | refused | lost | "
        "mean explained | ms/scan | update ms: median, p99 (max) | bag read (ms) |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    const int conv = r.statuses.count(LocalizationStatus::kConverged) > 0
                         ? r.statuses.at(LocalizationStatus::kConverged)
                         : 0;
    const auto count = [&](LocalizationStatus s) {
      return r.statuses.count(s) > 0 ? r.statuses.at(s) : 0;
    };
    const double pct = r.scans > 0 ? 100.0 * conv / static_cast<double>(r.scans) : 0.0;
    const double expl = r.tracked > 0 ? r.explained_sum / r.tracked : std::nan("");
    const double ms = r.localize_ms / static_cast<double>(std::max<std::size_t>(r.scans, 1));
    eval::ErrorStatistics u = eval::error_statistics(r.update_ms);
    if (r.update_ms.empty()) u.median = u.p99 = u.max = std::nan("");  // nothing tracked
    char line[320];
    // published: the poses the default outputs hold (converged, bridged).
    const int published = conv + count(LocalizationStatus::kBridged);
    const double published_pct =
        r.scans > 0 ? 100.0 * published / static_cast<double>(r.scans) : 0.0;
    std::snprintf(line, sizeof line, "%s,%zu,%.1f,%d,%.3f,%.3f,%.3f,%.3f,%.3f,%.1f\n",
                  r.bag.c_str(), r.scans, pct, count(LocalizationStatus::kLost), expl, ms, u.median,
                  u.p99, u.max, published_pct);
    csv << line;
    std::snprintf(
        line, sizeof line,
        "| %s | %zu | %s | %d | %d | %d | %d | %d | %.3f | %.2f | %.2f, %.1f (%.1f) | %.0f |\n",
        r.bag.c_str(), r.scans,
        r.acquired ? std::to_string(*r.acquired).c_str() : "never (first 50)", conv,
        count(LocalizationStatus::kBridged), count(LocalizationStatus::kNotConverged),
        count(LocalizationStatus::kRefused), count(LocalizationStatus::kLost), expl, ms, u.median,
        u.p99, u.max, r.read_ms);
    md << line;
    std::printf("%s", line);
  }
  std::printf("[ros_bags] wrote %s/table.csv, table.md and the PNGs\n", out.c_str());
  return 0;
}
