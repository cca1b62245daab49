// vdtnav_lidar_3d: a 3D LiDAR moving through a 3D map, localized scan by scan.
//
// A simulated Velodyne VLP-16 (16 rings over +-15 deg, 0.2 deg azimuth, 10 Hz, sigma_r 0.03 m,
// 100 m; sim::simulate_lidar3d_scan) rides 1 m above the floor along a tour planned through the
// map's free space (sim::plan_tour on the floor's 2D footprint), rolling and pitching a few
// degrees as on uneven ground; odometry and an IMU's roll and pitch are noisy. Every scan becomes
// observations through the point cloud front end (observations_from_cloud, voxel-downsampled to
// about --points readings) and goes to two localizers on the same map (one pyramid):
//   vdt-opt-6dof  VdtOptimizationLocalizer3 (in RecoveringLocalizer3), the full pose;
//   vdt-opt-4dof  the same with x, y, z, yaw estimated and roll/pitch held at the IMU's.
// Map: the generated 3D room (default) or --map FILE (.bt/.ot OctoMap, or a point cloud). The
// scans are ray cast in that very voxel grid: on it the map has no error but its quantisation
// ("simulated scans on the map"). So the same drive is also localized on the map a user would
// have, rows *-rebuilt: `vdtnav map3d` of the cloud of a separate mapping drive (another tour),
// its simulated scans registered at the map builder's noisy poses (--map-pose-sigma per axis in
// metres, a tenth of it in radians), voxelized as map3d does with its defaults (0.1 m voxels,
// walls thinned to their surfaces: occupancy_from_point_cloud). The rebuilt rows run what
// `vdtnav localize3d` runs on such a map (cloud_settings()) told the builder's pose error
// (map_pose_sigma), over the drive's first --rebuilt-scans scans: on a map blurred by the
// builder's pose error the solves stop at their iteration limit and the multi-start follows,
// ~50x the exact map's time per scan (README, 3D LiDAR).
// Then global localization (GlobalLocalizer3) from one scan at --global-trials poses drawn over
// the map (global_trials.cpp): global.csv, global_trials.csv.
// Writes to --out: table.csv (method,scans,pos_rmse_m,att_rmse_rad,anees,anees_lo,anees_hi,
// lost_pct,ms_per_scan,anees_left_out,ms_median,ms_p99,ms_max,nees_inside_95_pct,converged_pct,
// iterations_median,iterations_p99), table.md,
// trajectory.png (top view), errors.png (errors with +-2 sigma).
// With --scans DIR --poses FILE (KITTI or TUM, as `vdtnav map3d --scans` reads them) it runs on a
// real sequence instead (real_scans.cpp): the odd scans make the map, the even ones are localized
// on it from a noisy odometry prediction; the same table.csv columns, rows *-real.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "lidar_3d_study.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/estimation/recovering_localizer3d.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/pcl/cloud_observations.hpp"
#include "vdtnav/sim/lidar3d_simulator.hpp"
#include "vdtnav/sim/route_planner.hpp"
#include "vdtnav/sim/trajectory.hpp"

namespace {

using namespace vdtnav;
using Clock = std::chrono::steady_clock;

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"vdtnav_lidar_3d: a simulated VLP-16 localized scan by scan in a 3D map"};
  std::string out = "lidar_3d_out", map_path;
  unsigned seed = 1;
  int scans = 300;
  std::string scans_arg;
  lidar3d::RealScans real;
  std::size_t points = 2000;
  double speed = 1.0;
  app.add_option("--out", out, "output folder")->capture_default_str();
  app.add_option("--map", map_path,
                 "3D map to drive in: OctoMap (.bt/.ot) or point cloud (.pcd/.ply/.vtk/.csv); "
                 "default: the generated 3D room");
  app.add_option("--seed", seed, "seed of the room, the tour and the noise")->capture_default_str();
  app.add_option("--scans", scans_arg,
                 "scans of the simulated drive (10 Hz; default 300), or a folder of real scans "
                 "(with --poses: the odd ones make the map, the even ones are localized)");
  app.add_option("--poses", real.poses,
                 "--scans DIR: the scans' reference poses, KITTI (3x4 row-major, a line per scan "
                 "in name order) or TUM (stamps matched to the scans' numeric names)");
  app.add_option("--odom", real.odom,
                 "--scans DIR: the odometry's pose of each scan (KITTI or TUM, as --poses): the "
                 "even scans are predicted by its increments (default: drawn from --poses with "
                 "the simulated drive's noise)");
  app.add_option("--resolution", real.resolution, "--scans DIR: the map's voxel edge, metres")
      ->capture_default_str();
  app.add_option("--sigma-range", real.sigma_range,
                 "--scans DIR: the sensor's range noise standard deviation, metres")
      ->capture_default_str();
  app.add_option("--points", points, "readings per scan after voxel downsampling (about)")
      ->capture_default_str();
  app.add_option("--speed", speed, "cruise speed, m/s")->capture_default_str();
  double map_pose_sigma = 0.02;
  int rebuilt_scans = 50;
  app.add_option("--rebuilt-scans", rebuilt_scans,
                 "scans of the drive localized on the rebuilt map (the first ones; they cost 50x "
                 "the exact map's, see the file comment)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--map-pose-sigma", map_pose_sigma,
                 "the rebuilt map's builder pose error per axis: metres (a tenth of it in "
                 "radians)")
      ->capture_default_str();
  VdtLocalizer3Options o6;
  app.add_option("--max-iterations", o6.optimizer.max_iterations, "solver iterations per solve")
      ->capture_default_str();
  app.add_option("--tolerance", o6.optimizer.function_tolerance, "relative cost change to stop")
      ->capture_default_str();
  app.add_option("--gate-rounds", o6.optimizer.gate_rounds, "re-gating rounds per solve")
      ->capture_default_str();
  int global_trials = 40;
  app.add_option("--global-trials", global_trials,
                 "global localization from one scan with no prior, at this many poses drawn "
                 "over the map (global.csv; 0: none)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  // --scans N (a count) or --scans DIR (a real sequence).
  const bool real_run =
      !scans_arg.empty() && scans_arg.find_first_not_of("0123456789") != std::string::npos;
  if (!scans_arg.empty() && !real_run) scans = std::stoi(scans_arg);
  if (real_run != !real.poses.empty()) {
    std::fprintf(stderr, "error: --poses FILE goes with --scans DIR (a folder of real scans)\n");
    return 2;
  }
  const auto t_start = Clock::now();
  const auto seconds = [&] {
    return std::chrono::duration<double>(Clock::now() - t_start).count();
  };
  try {
    std::filesystem::create_directories(out);
    if (real_run) {
      real.dir = scans_arg;
      real.out = out;
      real.points = app.count("--points") > 0 ? points : 0;  // default: a reading per voxel
      real.seed = seed;
      lidar3d::run_real_scans(real);
      std::printf("wrote %s/table.csv, table.md (%.1f s)\n", out.c_str(), seconds());
      return 0;
    }
    // ------------------------------------------------------------------ the world (= the map)
    std::string world_name;
    const OccupancyGrid<3> world = lidar3d::load_world(map_path, seed, &world_name);
    std::fprintf(stderr, "[lidar_3d] %s: %d x %d x %d voxels of %.3f m; building its VDT\n",
                 world_name.c_str(), world.size().x(), world.size().y(), world.size().z(),
                 world.resolution());
    const VdtMap3 vdt = VdtMap3::build(world);

    // ------------------------------------------------------------------ the tour
    const lidar3d::Footprint fp = lidar3d::footprint(world);
    const std::vector<Eigen::Vector2d> path = sim::plan_tour(fp.blocked, 8, 0.6, seed);
    sim::TrajectoryOptions to;
    to.speed = speed;
    to.rate_hz = 10.0;
    std::vector<sim::TimedPose> tour = sim::follow_path(path, fp.blocked, to);
    if (static_cast<int>(tour.size()) > scans) tour.resize(static_cast<std::size_t>(scans));
    const std::vector<Pose3> truth = lidar3d::true_poses(tour, fp.floor_z);
    std::fprintf(stderr, "[lidar_3d] tour of %zu scans (%.0f s at 10 Hz), floor at z = %.2f m\n",
                 truth.size(), tour.back().t, fp.floor_z);

    // ------------------------------------------------------------------ the localizers
    VdtLocalizer3Options o4 = o6;
    o4.optimizer.four_dof = true;
    RecoveringLocalizer3 loc6(vdt, o6);
    RecoveringLocalizer3 loc4(loc6.tracker().optimizer(), o4);  // the same pyramid

    // ------------------------------------------------------------------ the rebuilt map
    std::size_t mapping_scans = 0;
    const auto m0 = Clock::now();
    const OccupancyGrid<3> rebuilt_grid = lidar3d::rebuilt_map(
        world, fp, speed, sim::Lidar3dSpec{}, map_pose_sigma, seed + 1000, &mapping_scans);
    const VdtMap3 rebuilt = VdtMap3::build(rebuilt_grid);
    std::fprintf(stderr,
                 "[lidar_3d] rebuilt map: %zu scans of a mapping drive registered with %.3f m / "
                 "%.4f rad of pose error, %d x %d x %d voxels (%.1f s)\n",
                 mapping_scans, map_pose_sigma, 0.1 * map_pose_sigma, rebuilt_grid.size().x(),
                 rebuilt_grid.size().y(), rebuilt_grid.size().z(),
                 std::chrono::duration<double>(Clock::now() - m0).count());
    // What `vdtnav localize3d` runs on a map of scans (cloud_settings()), told the map
    // builder's pose error.
    VdtLocalizer3Options o6r = o6, o4r = o4;
    o6r.optimizer = cloud_settings().vdt_opt;
    o6r.optimizer.sensor.map_pose_sigma = map_pose_sigma;
    o4r.optimizer = o6r.optimizer;
    o4r.optimizer.four_dof = true;
    RecoveringLocalizer3 loc6r(rebuilt, o6r);
    RecoveringLocalizer3 loc4r(loc6r.tracker().optimizer(), o4r);
    Matrix6d p0 = Matrix6d::Zero();
    p0.diagonal() << 0.05 * 0.05, 0.05 * 0.05, 0.05 * 0.05, 0.02 * 0.02, 0.02 * 0.02, 0.02 * 0.02;
    std::mt19937 rng(seed);
    std::normal_distribution<double> n01(0.0, 1.0);
    Vector6d start_error;
    for (int k = 0; k < 6; ++k) start_error[k] = std::sqrt(p0(k, k)) * n01(rng);
    const Pose3 start = oplus(truth.front(), start_error);
    RecoveringLocalizer3* locs[4] = {&loc6, &loc4, &loc6r, &loc4r};
    lidar3d::Run runs[lidar3d::kRuns];
    for (int m = 0; m < lidar3d::kRuns; ++m) {
      locs[m]->reset(start, p0);
      runs[m].name = locs[m]->name() + (m >= 2 ? "-rebuilt" : "");
    }

    const sim::Lidar3dSpec vlp16;
    double voxel = -1.0;
    double sim_seconds = 0.0;
    std::size_t readings_sum = 0;
    for (std::size_t k = 0; k < truth.size(); ++k) {
      const auto t0 = Clock::now();
      const sim::Lidar3dScan scan = sim::simulate_lidar3d_scan(world, truth[k], vlp16, rng);
      sim_seconds += std::chrono::duration<double>(Clock::now() - t0).count();
      const pcl::PointCloud<pcl::PointXYZ> cloud = lidar3d::to_pcl(scan, vlp16.rings);
      if (voxel < 0.0) voxel = lidar3d::voxel_for(cloud, points);
      CloudObservationOptions co;
      co.sigma_range = vlp16.sigma_range;
      co.range_max = vlp16.range_max;
      co.voxel = voxel;
      const ObservationSet3 obs = observations_from_cloud(cloud, co);
      readings_sum += obs.size();
      const OdometryStep3 odo =
          k == 0 ? OdometryStep3{} : o6.noisy_odometry(truth[k - 1], truth[k], 0.1, rng);
      for (int m = 0; m < lidar3d::kRuns; ++m) {
        if (m >= 2 && k >= static_cast<std::size_t>(rebuilt_scans)) continue;
        const auto s0 = Clock::now();
        const LocalizationResult3 r = locs[m]->update(odo, obs);
        runs[m].record(r, truth[k], std::chrono::duration<double>(Clock::now() - s0).count());
      }
      if ((k + 1) % 50 == 0 || k + 1 == truth.size())
        std::fprintf(stderr, "[lidar_3d] scan %zu / %zu (%.0f s)\n", k + 1, truth.size(),
                     seconds());
    }

    // ------------------------------------------------------------------ tables and figures
    lidar3d::write_tables(out, world_name, truth, speed, readings_sum, voxel, vlp16, o6,
                          mapping_scans, map_pose_sigma, runs, sim_seconds);
    lidar3d::draw_figures(out, fp, tour, truth, runs);
    if (global_trials > 0) {
      lidar3d::GlobalTrials g;
      g.out = out;
      g.trials = global_trials;
      g.voxel = voxel;
      g.sigma_gravity = o6.sigma_imu_attitude;
      g.seed = seed;
      lidar3d::run_global_trials(world,
                                 {{"vdt-global-3d", &vdt, o6.optimizer, 0.1, 1.0},
                                  {"vdt-global-3d-rebuilt", &rebuilt, o6r.optimizer, 0.25, 2.0}},
                                 fp, g);
    }
    std::printf("wrote %s/table.csv, table.md, trajectory.png, errors.png%s (%.1f s)\n",
                out.c_str(), global_trials > 0 ? ", global.csv, global_trials.csv" : "", seconds());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
