// Global localization in 3D (GlobalLocalizer3) from one simulated VLP-16 scan taken anywhere in
// the map: `--global-trials N` poses drawn over the footprint's free columns, 0.5-2 m above the
// floor and at least 0.5 m from any surface, any heading, rolled and pitched up to 3 degrees; roll
// and pitch given to the search from a gravity reading with the IMU's noise (sigma_imu_attitude).
// A trial succeeds when the pose is accepted within 0.1 m and 1 degree of the truth (0.25 m and 2
// degrees on the rebuilt map, itself off the truth by its builder's error: the drive's RMSE there
// is ~0.1 m); an accepted pose farther off is a wrong pose accepted; a refusal (scan unexplained,
// or ambiguous) is neither. Writes global.csv (a row: the success rate, refusals, wrong poses
// accepted, the median, 90th-percentile and longest wall time) per map: vdt-global-3d on the map
// the scans are cast in, vdt-global-3d-rebuilt on the map of the mapping drive (rebuilt_map.cpp),
// and global_trials.csv (a row per trial and map).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <random>
#include <vector>

#include "lidar_3d_study.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/global_localization3d.hpp"
#include "vdtnav/pcl/cloud_observations.hpp"

namespace lidar3d {

using namespace vdtnav;

namespace {

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(std::lround(q * static_cast<double>(v.size() - 1)))];
}

}  // namespace

void run_global_trials(const OccupancyGrid<3>& world, const std::vector<TrialMap>& maps,
                       const Footprint& fp, const GlobalTrials& o) {
  using Clock = std::chrono::steady_clock;
  VDTNAV_CHECK(!maps.empty(), "global trials: no map");
  // One search per map (its pyramid built once) and its tally.
  struct Tally {
    std::unique_ptr<GlobalLocalizer3> global;
    double build_seconds = 0.0;
    int success = 0, refused = 0, wrong = 0, ambiguous = 0;
    std::vector<double> seconds;
  };
  std::vector<Tally> tallies(maps.size());
  for (std::size_t m = 0; m < maps.size(); ++m) {
    const auto b0 = Clock::now();
    GlobalLocalization3Options go;
    go.optimizer = maps[m].optimizer;
    tallies[m].global = std::make_unique<GlobalLocalizer3>(*maps[m].map, go);
    tallies[m].build_seconds = std::chrono::duration<double>(Clock::now() - b0).count();
    const GlobalLocalizer3& g = *tallies[m].global;
    const Eigen::Vector3i n = g.search_size();
    std::fprintf(stderr,
                 "[lidar_3d] global localization on %s: %d x %d x %d search cells of %.2f m (%zu "
                 "where the sensor may be), %d levels, built in %.1f s\n",
                 maps[m].name.c_str(), n.x(), n.y(), n.z(), g.search_frame().resolution(),
                 g.free_cells(), g.levels(), tallies[m].build_seconds);
  }
  // The free columns of the footprint.
  std::vector<Eigen::Vector2d> columns;
  const Eigen::Vector2i fs = fp.blocked.size();
  for (int j = 0; j < fs.y(); ++j) {
    for (int i = 0; i < fs.x(); ++i) {
      if (fp.blocked(Eigen::Vector2i(i, j)) == 0)
        columns.push_back(fp.blocked.frame().cell_center(Eigen::Vector2i(i, j)));
    }
  }
  VDTNAV_CHECK(!columns.empty(), "global trials: the map has no free column");
  std::mt19937 rng(o.seed + 2000);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> gravity(0.0, o.sigma_gravity);
  const sim::Lidar3dSpec vlp16;
  std::ofstream trials_csv(o.out + "/global_trials.csv");
  trials_csv << "method,trial,x,y,z,roll,pitch,yaw,status,ambiguous,pos_err_m,att_err_rad,"
                "explained,nodes,search_s,total_s\n";
  const VdtField3& world_map = *maps.front().map;
  for (int t = 0; t < o.trials; ++t) {
    Pose3 truth;
    for (;;) {
      const Eigen::Vector2d c = columns[static_cast<std::size_t>(u(rng) * columns.size())];
      const double z = fp.floor_z + 0.5 + 1.5 * u(rng);
      const double deg = kPi / 180.0;
      truth = pose3_from_xyz_rpy(c.x(), c.y(), z, 3 * deg * (2 * u(rng) - 1),
                                 3 * deg * (2 * u(rng) - 1), kPi * (2 * u(rng) - 1));
      bool inside = false;
      if (world_map.value(truth.translation(), &inside).norm() >= 0.5 && inside) break;
    }
    const sim::Lidar3dScan scan = sim::simulate_lidar3d_scan(world, truth, vlp16, rng);
    const pcl::PointCloud<pcl::PointXYZ> cloud = to_pcl(scan, vlp16.rings);
    CloudObservationOptions co;
    co.sigma_range = vlp16.sigma_range;
    co.range_max = vlp16.range_max;
    co.voxel = o.voxel;
    const ObservationSet3 obs = observations_from_cloud(cloud, co);
    const Eigen::Vector3d rpy = rpy_of(truth.linear());
    const double roll = rpy.x() + gravity(rng), pitch = rpy.y() + gravity(rng);
    for (std::size_t m = 0; m < maps.size(); ++m) {
      Tally& y = tallies[m];
      const GlobalLocalization3Result r = y.global->localize(obs, roll, pitch);
      const double dp = (r.result.pose.translation() - truth.translation()).norm();
      const double da = attitude_error(r.result.pose, truth);
      const bool accepted = r.result.status == LocalizationStatus::kConverged;
      const bool right = dp <= maps[m].tolerance && da <= maps[m].attitude_tolerance * kPi / 180.0;
      y.success += accepted && right;
      y.wrong += accepted && !right;
      y.refused += !accepted;
      y.ambiguous += r.ambiguous;
      y.seconds.push_back(r.seconds);
      trials_csv << maps[m].name << ',' << t << ',' << truth.translation().x() << ','
                 << truth.translation().y() << ',' << truth.translation().z() << ',' << rpy.x()
                 << ',' << rpy.y() << ',' << rpy.z() << ',' << (accepted ? "accepted" : "refused")
                 << ',' << (r.ambiguous ? 1 : 0) << ',' << dp << ',' << da << ',' << r.explained
                 << ',' << r.nodes << ',' << r.search_seconds << ',' << r.seconds << '\n';
      std::fprintf(stderr,
                   "[lidar_3d] global %2d / %d on %s: %s, %.3f m / %.4f rad off, %.0f %% "
                   "explained%s, %zu cubes, %.2f s\n",
                   t + 1, o.trials, maps[m].name.c_str(), accepted ? "accepted" : "refused", dp, da,
                   100.0 * r.explained, r.ambiguous ? " (ambiguous)" : "", r.nodes, r.seconds);
    }
  }
  const double pct = 100.0 / std::max(1, o.trials);
  std::ofstream csv(o.out + "/global.csv");
  csv << "method,trials,success_pct,refused_pct,ambiguous_pct,wrong_accepted,median_s,p90_s,"
         "max_s,build_s\n";
  for (std::size_t m = 0; m < maps.size(); ++m) {
    const Tally& y = tallies[m];
    csv << maps[m].name << ',' << o.trials << ',' << y.success * pct << ',' << y.refused * pct
        << ',' << y.ambiguous * pct << ',' << y.wrong << ',' << quantile(y.seconds, 0.5) << ','
        << quantile(y.seconds, 0.9) << ',' << quantile(y.seconds, 1.0) << ',' << y.build_seconds
        << '\n';
    std::printf(
        "%s: %d trials from one scan, no prior: %.1f %% found within %.2f m / %.0f deg, %.1f %% "
        "refused (%.1f %% ambiguous), %d wrong accepted; median %.2f s, p90 %.2f s, max %.2f s "
        "(search built in %.1f s)\n",
        maps[m].name.c_str(), o.trials, y.success * pct, maps[m].tolerance,
        maps[m].attitude_tolerance, y.refused * pct, y.ambiguous * pct, y.wrong,
        quantile(y.seconds, 0.5), quantile(y.seconds, 0.9), quantile(y.seconds, 1.0),
        y.build_seconds);
  }
}

}  // namespace lidar3d
