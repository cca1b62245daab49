// The maps of the global localization study and their scans: the generated floor plan, the
// hospital section and fetch-office with scans simulated at random free poses, and the Intel lab
// with its real scans and odometry.
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "kidnapped_study.hpp"
#include "vdtnav/io/carmen_log.hpp"
#include "vdtnav/io/log_odometry.hpp"
#include "vdtnav/io/occupancy_image.hpp"
#include "vdtnav/io/odometry_table.hpp"
#include "vdtnav/io/ros_map.hpp"
#include "vdtnav/mapping/occupancy_mapper.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/sim/lidar_simulator.hpp"

namespace study {

using namespace vdtnav;

namespace {}  // namespace

std::vector<Case> load_cases(const std::string& data, unsigned seed, int trials) {
  std::vector<Case> cases;
  {
    Case c;
    c.map = "generated";
    c.scans = "simulated";
    sim::FloorPlanOptions o;
    o.seed = seed;
    c.grid = sim::generate_floor_plan(o).occupancy;
    cases.push_back(std::move(c));
  }
  const std::string hospital = data + "/stage_maps/hospital_section.png";
  if (!data.empty() && std::filesystem::exists(hospital)) {
    Case c;
    c.map = "hospital-section";
    c.scans = "simulated";
    c.grid = load_occupancy_image(hospital, Eigen::Vector2d(40.0, 18.0), 0.05);
    cases.push_back(std::move(c));
  }
  const std::string office = data + "/ros-maps/fetch-office/4_26_15.yaml";
  if (!data.empty() && std::filesystem::exists(office)) {
    Case c;
    c.map = "fetch-office";
    c.scans = "simulated";
    c.grid = occupancy(load_ros_map(office));
    cases.push_back(std::move(c));
  }
  const std::string intel = data + "/intel-lab/intel.gfs.log.gz";
  if (!data.empty() && std::filesystem::exists(intel)) {
    // The map from every corrected scan; trials: scans at random times, truth the corrected pose.
    const CarmenLog log = load_carmen_log(intel);
    std::vector<Pose2> poses;
    std::vector<LaserScan> scans;
    for (const auto& l : log.lasers) {
      poses.push_back(l.pose);
      scans.push_back(l.scan);
    }
    Case c;
    c.map = "intel";
    c.scans = "real";
    c.grid = mapping::build_occupancy_map(poses, scans, {}).occupancy;
    c.settings = log_settings();
    // The drive: the log's scans with the raw odometry of the table joined to it.
    const std::string table = data + "/intel-lab/intel_910_odom_vs_corrected.txt";
    const JoinedLogs logs = join_odometry_table(log, load_odometry_table(table), table);
    std::vector<std::size_t> all(logs.raw.lasers.size());
    std::vector<double> times;
    for (std::size_t i = 0; i < all.size(); ++i) {
      all[i] = i;
      times.push_back(logs.raw.lasers[i].time);
    }
    c.drive.odometry = odometry_steps(times, log_odometry(logs.raw, all).poses);
    for (std::size_t i = 0; i < all.size(); ++i) {
      LaserScan scan = logs.raw.lasers[i].scan;
      scan.sigma_range = 0.02;  // as the Intel study and `vdtnav localize`
      c.drive.scans.push_back(scan_points(scan));
      c.drive.truth.push_back(logs.corrected.lasers[i].pose);
    }
    std::mt19937 rng(seed);
    std::uniform_int_distribution<std::size_t> pick(0, log.lasers.size() - 1);
    for (int k = 0; k < trials; ++k) {
      const std::size_t i = pick(rng);
      c.observations.push_back(scan_points(log.lasers[i].scan));
      c.truth.push_back(log.lasers[i].pose);
    }
    cases.push_back(std::move(c));
  }

  for (std::size_t i = 0; i < cases.size(); ++i) cases[i].id = static_cast<unsigned>(i);
  return cases;
}

void simulate(Case& c, const VdtMap2& map, int trials, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> x(0, c.grid.size().x() - 1), y(0, c.grid.size().y() - 1);
  std::uniform_real_distribution<double> yaw(-kPi, kPi);
  std::vector<sim::TimedPose> poses;
  while (static_cast<int>(poses.size()) < trials) {
    const Eigen::Vector2i i(x(rng), y(rng));
    if (c.grid(i)) continue;
    const Eigen::Vector2d p = c.grid.cell_center(i);
    if (map.value(p).norm() < 0.3) continue;
    sim::TimedPose t;
    t.t = static_cast<double>(poses.size());
    t.pose = Pose2(p.x(), p.y(), yaw(rng));
    poses.push_back(t);
  }
  const sim::SimulatedRun run = sim::simulate_run(c.grid, poses, sim::LidarOptions{},
                                                  sim::NoiseProfile::table_3_2_sigma(), seed);
  for (std::size_t k = 0; k < run.size(); ++k) {
    c.observations.push_back(scan_points(run.scans[k]));
    c.truth.push_back(run.truth[k]);
  }
}

}  // namespace study
