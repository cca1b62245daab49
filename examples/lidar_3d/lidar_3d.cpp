// vdtnav_lidar_3d: a 3D LiDAR moving through a 3D map, localized scan by scan.
//
// A simulated Velodyne VLP-16 (16 rings over +-15 deg, 0.2 deg azimuth, 10 Hz, sigma_r 0.03 m,
// 100 m; sim::simulate_lidar3d_scan) rides 1 m above the floor along a tour planned through the
// map's free space (sim::plan_tour on the floor's 2D footprint), rolling and pitching a few
// degrees as on uneven ground; odometry and an IMU's roll and pitch are noisy. Every scan becomes
// observations through the point cloud front end (observations_from_cloud, voxel-downsampled to
// about --points readings) and goes to two localizers on the same map (one pyramid):
//   vdt-opt-6dof  VdtOptimizationLocalizer3, the full pose;
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
// Writes to --out: table.csv (method,scans,pos_rmse_m,att_rmse_rad,anees,anees_lo,anees_hi,
// lost_pct,ms_per_scan,anees_left_out), table.md, trajectory.png (top view), errors.png (errors
// with +-2 sigma).
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/estimation/vdt_localizer3d.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/octomap/octree_map.hpp"
#include "vdtnav/pcl/cloud_observations.hpp"
#include "vdtnav/pcl/point_cloud_conversion.hpp"
#include "vdtnav/pcl/point_cloud_map.hpp"
#include "vdtnav/sim/lidar3d_simulator.hpp"
#include "vdtnav/sim/room3d.hpp"
#include "vdtnav/sim/route_planner.hpp"
#include "vdtnav/sim/trajectory.hpp"
#include "vdtnav/viz/plot.hpp"

namespace {

using namespace vdtnav;
using Clock = std::chrono::steady_clock;
constexpr double kPi = 3.14159265358979323846;

/// The 2D footprint the robot drives on: the floor layer, and per column whether it is free from
/// 0.2 m above the floor to 2 m and near a floor (the tour stays inside the building).
struct Footprint {
  OccupancyGrid<2> blocked;
  double floor_z = 0.0;  ///< the floor's surface (the top of its voxels), metres
};

Footprint footprint(const OccupancyGrid<3>& g) {
  const Eigen::Vector3i n = g.size();
  const double res = g.resolution();
  // The floor: the layer with the most occupied voxels in the lower half of the map.
  const int low = std::max(1, n.z() / 2);
  std::vector<long> count(static_cast<std::size_t>(low), 0);
  for (int k = 0; k < low; ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i) count[k] += g(Eigen::Vector3i(i, j, k)) != 0;
  const int kf = static_cast<int>(std::max_element(count.begin(), count.end()) - count.begin());
  Footprint f;
  f.floor_z = g.frame().cell_center(Eigen::Vector3i(0, 0, kf)).z() + 0.5 * res;
  const Eigen::Vector3d o = g.frame().origin();
  f.blocked = OccupancyGrid<2>(Eigen::Vector2i(n.x(), n.y()),
                               GridFrame<2>(res, Eigen::Vector2d(o.x(), o.y())), 0);
  const int k0 = kf + 1 + static_cast<int>(std::ceil(0.2 / res));
  const int k1 = std::min(n.z() - 1, kf + static_cast<int>(std::ceil(2.0 / res)));
  // Inside the building: a floor voxel within 0.5 m horizontally of the column, in a slab 0.5 m
  // below to 0.15 m above the floor layer (scanned floors are patchy and a few voxels thick).
  const int below = static_cast<int>(std::ceil(0.5 / res)),
            above = static_cast<int>(std::ceil(0.15 / res));
  const int reach = static_cast<int>(std::ceil(0.5 / res));
  Grid<std::uint8_t, 2> floor2(Eigen::Vector2i(n.x(), n.y()), f.blocked.frame(), 0);
  for (int j = 0; j < n.y(); ++j)
    for (int i = 0; i < n.x(); ++i)
      for (int k = std::max(0, kf - below); k <= std::min(n.z() - 1, kf + above); ++k)
        if (g(Eigen::Vector3i(i, j, k)) != 0) floor2(Eigen::Vector2i(i, j)) = 1;
  Grid<std::uint8_t, 2> near_floor = floor2;  // dilated by `reach`, one axis at a time
  for (int pass = 0; pass < 2; ++pass) {
    const Grid<std::uint8_t, 2> src = near_floor;
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i) {
        std::uint8_t v = 0;
        for (int d = -reach; d <= reach && v == 0; ++d) {
          const int ii = pass == 0 ? i + d : i, jj = pass == 0 ? j : j + d;
          if (ii >= 0 && jj >= 0 && ii < n.x() && jj < n.y()) v = src(Eigen::Vector2i(ii, jj));
        }
        near_floor(Eigen::Vector2i(i, j)) = v;
      }
  }
  for (int j = 0; j < n.y(); ++j)
    for (int i = 0; i < n.x(); ++i) {
      bool clear = true;
      for (int k = k0; k <= k1 && clear; ++k) clear = g(Eigen::Vector3i(i, j, k)) == 0;
      f.blocked(Eigen::Vector2i(i, j)) = (near_floor(Eigen::Vector2i(i, j)) != 0 && clear) ? 0 : 1;
    }
  return f;
}

/// The true 6-DOF poses along the tour: 1 m above the floor, rolling and pitching a few degrees.
std::vector<Pose3> true_poses(const std::vector<sim::TimedPose>& tour, double floor_z) {
  std::vector<Pose3> poses;
  for (const sim::TimedPose& p : tour) {
    const double t = p.t;
    poses.push_back(pose3_from_xyz_rpy(p.pose.x(), p.pose.y(),
                                       floor_z + 1.0 + 0.03 * std::sin(2 * kPi * t / 5.3),
                                       0.035 * std::sin(2 * kPi * t / 3.1),
                                       0.025 * std::sin(2 * kPi * t / 4.3 + 1.0), p.pose.z()));
  }
  return poses;
}

pcl::PointCloud<pcl::PointXYZ> to_pcl(const sim::Lidar3dScan& scan, int rings) {
  pcl::PointCloud<pcl::PointXYZ> c;
  c.reserve(scan.points.size());
  for (const Eigen::Vector3d& p : scan.points)
    c.push_back(pcl::PointXYZ(static_cast<float>(p.x()), static_cast<float>(p.y()),
                              static_cast<float>(p.z())));
  c.width = static_cast<std::uint32_t>(scan.points.size() / static_cast<std::size_t>(rings));
  c.height = static_cast<std::uint32_t>(rings);  // organized, as a driver writes it
  c.is_dense = false;
  return c;
}

/// The voxel edge that leaves about `target` readings of `cloud` (bisection on the edge).
double voxel_for(const pcl::PointCloud<pcl::PointXYZ>& cloud, std::size_t target) {
  CloudObservationOptions o;
  double lo = 0.01, hi = 5.0;
  for (int it = 0; it < 30; ++it) {
    o.voxel = std::sqrt(lo * hi);
    (observations_from_cloud(cloud, o).size() > target ? lo : hi) = o.voxel;
  }
  return std::sqrt(lo * hi);
}

/// The map a user would have (the file comment): the cloud of a mapping drive through `world`
/// along its own tour (`seed`), one scan every `every` poses, each registered at its true pose
/// moved by the map builder's error (N(0, pose_sigma^2) per axis in metres, N(0, (pose_sigma /
/// 10)^2) per axis in radians), voxelized as `vdtnav map3d` does with its defaults (0.1 m voxels,
/// or the world's if coarser; a 1 m margin).
OccupancyGrid<3> rebuilt_map(const OccupancyGrid<3>& world, const Footprint& fp, double speed,
                             const sim::Lidar3dSpec& spec, double pose_sigma, unsigned seed,
                             std::size_t* scans_used) {
  const std::vector<Eigen::Vector2d> path = sim::plan_tour(fp.blocked, 8, 0.6, seed);
  sim::TrajectoryOptions to;
  to.speed = speed;
  to.rate_hz = 10.0;
  const std::vector<Pose3> poses = true_poses(sim::follow_path(path, fp.blocked, to), fp.floor_z);
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  pcl::PointCloud<pcl::PointXYZ> cloud;
  const Eigen::Vector3d lo_box = world.frame().origin(),
                        hi_box = lo_box + world.resolution() * world.size().cast<double>();
  const std::size_t every = 5;
  *scans_used = 0;
  for (std::size_t k = 0; k < poses.size(); k += every) {
    const sim::Lidar3dScan scan = sim::simulate_lidar3d_scan(world, poses[k], spec, rng);
    Vector6d e;
    for (int c = 0; c < 6; ++c) e[c] = (c < 3 ? pose_sigma : 0.1 * pose_sigma) * n01(rng);
    const Pose3 registered = oplus(poses[k], e);  // where the map builder put the scan
    for (const Eigen::Vector3d& p : scan.points) {
      if (!p.allFinite()) continue;
      const Eigen::Vector3d w = registered * p;
      // The building's box, as `map3d --crop` keeps it.
      if (((w - lo_box).array() < 0.0).any() || ((w - hi_box).array() > 0.0).any()) continue;
      cloud.push_back(pcl::PointXYZ(static_cast<float>(w.x()), static_cast<float>(w.y()),
                                    static_cast<float>(w.z())));
    }
    ++*scans_used;
  }
  std::fprintf(stderr, "[lidar_3d] mapping drive: %zu scans, %zu points\n", *scans_used,
               cloud.size());
  PointCloudOccupancyOptions o;
  o.resolution = std::max(world.resolution(), 0.1);  // map3d's default for clouds, 0.1 m
  o.margin = 1.0;                                    // and its default margin
  return occupancy_from_point_cloud(cloud, o).occupancy;
}

struct Run {
  std::string name;
  std::vector<Pose3> estimates;
  std::vector<Matrix6d> covariances;
  std::vector<double> nees;
  std::vector<int> nees_dof;
  int lost = 0, refused = 0;
  long iterations = 0;
  double seconds = 0.0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"vdtnav_lidar_3d: a simulated VLP-16 localized scan by scan in a 3D map"};
  std::string out = "lidar_3d_out", map_path;
  unsigned seed = 1;
  int scans = 300;
  std::size_t points = 2000;
  double speed = 1.0;
  app.add_option("--out", out, "output folder")->capture_default_str();
  app.add_option("--map", map_path,
                 "3D map to drive in: OctoMap (.bt/.ot) or point cloud (.pcd/.ply/.vtk/.csv); "
                 "default: the generated 3D room");
  app.add_option("--seed", seed, "seed of the room, the tour and the noise")->capture_default_str();
  app.add_option("--scans", scans, "scans (10 Hz)")->capture_default_str();
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
  CLI11_PARSE(app, argc, argv);
  const auto t_start = Clock::now();
  const auto seconds = [&] {
    return std::chrono::duration<double>(Clock::now() - t_start).count();
  };
  try {
    std::filesystem::create_directories(out);
    // ------------------------------------------------------------------ the world (= the map)
    OccupancyGrid<3> world;
    std::string world_name;
    if (map_path.empty()) {
      sim::Room3dOptions ro;
      ro.seed = seed;
      world = sim::generate_room3d(ro).occupancy;
      world_name = "generated room";
    } else {
      const std::string ext = std::filesystem::path(map_path).extension().string();
      if (ext == ".bt" || ext == ".ot") {
        OctreeOccupancyOptions oo;
        oo.margin = 0.5;
        world = load_octree_occupancy(map_path, oo).occupancy;
      } else {
        PointCloudOccupancyOptions po;
        po.margin = 0.5;
        world = load_point_cloud_occupancy(map_path, po).occupancy;
      }
      world_name = std::filesystem::path(map_path).filename().string();
    }
    std::fprintf(stderr, "[lidar_3d] %s: %d x %d x %d voxels of %.3f m; building its VDT\n",
                 world_name.c_str(), world.size().x(), world.size().y(), world.size().z(),
                 world.resolution());
    const VdtMap3 vdt = VdtMap3::build(world);

    // ------------------------------------------------------------------ the tour
    const Footprint fp = footprint(world);
    const std::vector<Eigen::Vector2d> path = sim::plan_tour(fp.blocked, 8, 0.6, seed);
    sim::TrajectoryOptions to;
    to.speed = speed;
    to.rate_hz = 10.0;
    std::vector<sim::TimedPose> tour = sim::follow_path(path, fp.blocked, to);
    if (static_cast<int>(tour.size()) > scans) tour.resize(static_cast<std::size_t>(scans));
    const std::vector<Pose3> truth = true_poses(tour, fp.floor_z);
    std::fprintf(stderr, "[lidar_3d] tour of %zu scans (%.0f s at 10 Hz), floor at z = %.2f m\n",
                 truth.size(), tour.back().t, fp.floor_z);

    // ------------------------------------------------------------------ the localizers
    VdtLocalizer3Options o4 = o6;
    o4.optimizer.four_dof = true;
    VdtOptimizationLocalizer3 loc6(vdt, o6);
    VdtOptimizationLocalizer3 loc4(loc6.optimizer(), o4);  // the same pyramid

    // ------------------------------------------------------------------ the rebuilt map
    std::size_t mapping_scans = 0;
    const auto m0 = Clock::now();
    const OccupancyGrid<3> rebuilt_grid = rebuilt_map(world, fp, speed, sim::Lidar3dSpec{},
                                                      map_pose_sigma, seed + 1000, &mapping_scans);
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
    VdtOptimizationLocalizer3 loc6r(rebuilt, o6r);
    VdtOptimizationLocalizer3 loc4r(loc6r.optimizer(), o4r);
    Matrix6d p0 = Matrix6d::Zero();
    p0.diagonal() << 0.05 * 0.05, 0.05 * 0.05, 0.05 * 0.05, 0.02 * 0.02, 0.02 * 0.02, 0.02 * 0.02;
    std::mt19937 rng(seed);
    std::normal_distribution<double> n01(0.0, 1.0);
    Vector6d start_error;
    for (int k = 0; k < 6; ++k) start_error[k] = std::sqrt(p0(k, k)) * n01(rng);
    const Pose3 start = oplus(truth.front(), start_error);
    VdtOptimizationLocalizer3* locs[4] = {&loc6, &loc4, &loc6r, &loc4r};
    constexpr int kRuns = 4;
    Run runs[kRuns];
    for (int m = 0; m < kRuns; ++m) {
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
      const pcl::PointCloud<pcl::PointXYZ> cloud = to_pcl(scan, vlp16.rings);
      if (voxel < 0.0) voxel = voxel_for(cloud, points);
      CloudObservationOptions co;
      co.sigma_range = vlp16.sigma_range;
      co.range_max = vlp16.range_max;
      co.voxel = voxel;
      const ObservationSet3 obs = observations_from_cloud(cloud, co);
      readings_sum += obs.size();
      const OdometryStep3 odo =
          k == 0 ? OdometryStep3{} : o6.noisy_odometry(truth[k - 1], truth[k], 0.1, rng);
      for (int m = 0; m < kRuns; ++m) {
        if (m >= 2 && k >= static_cast<std::size_t>(rebuilt_scans)) continue;
        const auto s0 = Clock::now();
        const LocalizationResult3 r = locs[m]->update(odo, obs);
        runs[m].seconds += std::chrono::duration<double>(Clock::now() - s0).count();
        runs[m].estimates.push_back(r.pose);
        runs[m].covariances.push_back(r.covariance);
        int dof = 0;
        runs[m].nees.push_back(eval::nees(r.pose, truth[k], r.covariance, &dof));
        runs[m].nees_dof.push_back(dof);
        runs[m].lost += r.status == LocalizationStatus::kLost;
        runs[m].iterations += r.iterations;
        runs[m].refused += r.status == LocalizationStatus::kRefused;
      }
      if ((k + 1) % 50 == 0 || k + 1 == truth.size())
        std::fprintf(stderr, "[lidar_3d] scan %zu / %zu (%.0f s)\n", k + 1, truth.size(),
                     seconds());
    }

    // ------------------------------------------------------------------ tables
    std::ofstream csv(out + "/table.csv");
    csv << "method,scans,pos_rmse_m,att_rmse_rad,anees,anees_lo,anees_hi,lost_pct,ms_per_scan,"
           "anees_left_out\n";
    std::ofstream md(out + "/table.md");
    md << "# 3D LiDAR localization: simulated VLP-16 scans on the " << world_name << " map\n\n"
       << truth.size() << " scans at 10 Hz, " << speed << " m/s, about "
       << readings_sum / truth.size() << " readings per scan after " << voxel
       << " m voxel downsampling (of " << vlp16.rings * vlp16.rays_per_ring()
       << " rays); odometry noise 5 % per metre + 0.02 m/s, 5 % per radian + 0.01 rad/s; IMU roll "
          "and pitch sigma "
       << o6.sigma_imu_attitude
       << " rad. The scans are ray cast in the map's own voxels (no map error but quantisation); "
          "the *-rebuilt rows localize them on the map `vdtnav map3d` makes of a separate mapping "
          "drive ("
       << mapping_scans << " scans registered with " << map_pose_sigma << " m / "
       << 0.1 * map_pose_sigma
       << " rad of pose error per axis), as a real map is made. ANEES interval: 95 % (chi-square, "
          "N x dof).\n\n"
       << "| method | scans | position RMSE (m) | attitude RMSE (rad) | ANEES | 95 % interval | "
          "lost % | ms per scan |\n|---|---|---|---|---|---|---|---|\n";
    for (const Run& r : runs) {
      const std::size_t count = r.estimates.size();  // the rebuilt rows: the first scans
      double se_p = 0.0, se_a = 0.0;
      for (std::size_t k = 0; k < count; ++k) {
        se_p += (r.estimates[k].translation() - truth[k].translation()).squaredNorm();
        se_a += std::pow(attitude_error(r.estimates[k], truth[k]), 2);
      }
      const double n = static_cast<double>(count);
      const int dof = r.nees_dof.empty() ? 6 : r.nees_dof.back();
      const eval::AneesResult a = eval::anees(r.nees, dof);
      const double lost_pct = 100.0 * r.lost / n;
      const double ms = 1e3 * r.seconds / n;
      char line[512];
      std::snprintf(line, sizeof line, "%s,%zu,%.4f,%.5f,%.3f,%.3f,%.3f,%.1f,%.2f,%zu\n",
                    r.name.c_str(), count, std::sqrt(se_p / n), std::sqrt(se_a / n), a.anees,
                    a.interval.lower, a.interval.upper, lost_pct, ms, count - a.count);
      const std::string note = eval::left_out_note(a, count);
      csv << line;
      std::snprintf(line, sizeof line,
                    "| %s | %zu | %.4f | %.5f | %.2f%s | [%.2f, %.2f] | %.1f | %.2f |\n",
                    r.name.c_str(), count, std::sqrt(se_p / n), std::sqrt(se_a / n), a.anees,
                    note.empty() ? "" : (" (" + note + ")").c_str(), a.interval.lower,
                    a.interval.upper, lost_pct, ms);
      md << line;
      std::printf(
          "%s: position RMSE %.4f m, attitude RMSE %.5f rad, ANEES %.2f in [%.2f, %.2f] "
          "(%d dof), lost %.1f %%, refused %d, %.2f ms and %.1f iterations per scan\n",
          r.name.c_str(), std::sqrt(se_p / n), std::sqrt(se_a / n), a.anees, a.interval.lower,
          a.interval.upper, dof, lost_pct, r.refused, ms, static_cast<double>(r.iterations) / n);
    }
    md << "\nTimes: localizer update per scan (observations given), this machine; the ray casting "
          "of the simulated scans took "
       << 1e3 * sim_seconds / static_cast<double>(truth.size())
       << " ms per scan and is not counted.\n\nFigures: `trajectory.png` (top view), "
          "`errors.png` (errors with +-2 sigma of the reported covariance).\n";

    // ------------------------------------------------------------------ figures
    {
      const OccupancyGrid<2>& b = fp.blocked;
      viz::RgbImage img(b.size().x(), b.size().y());
      for (int j = 0; j < b.size().y(); ++j)
        for (int i = 0; i < b.size().x(); ++i)
          if (b(Eigen::Vector2i(i, j)) != 0)
            img.set(i, b.size().y() - 1 - j, viz::Rgb{170, 170, 170});
      const Eigen::Vector2d lo = b.frame().origin();
      const Eigen::Vector2d hi = lo + b.resolution() * b.size().cast<double>();
      viz::Figure fig(1300, 1100);
      viz::Axes& ax = fig.axes();
      ax.image(img, lo.x(), hi.x(), lo.y(), hi.y()).equal_aspect();
      const auto xy = [&](const std::vector<Pose3>& ps, std::vector<double>& xs,
                          std::vector<double>& ys) {
        for (const Pose3& p : ps) {
          xs.push_back(p.translation().x());
          ys.push_back(p.translation().y());
        }
      };
      std::vector<double> tx, ty;
      xy(truth, tx, ty);
      ax.line(tx, ty, viz::Style().with_color(viz::kBlack).with_label("truth"));
      for (const Run& r : runs) {
        std::vector<double> xs, ys;
        xy(r.estimates, xs, ys);
        ax.line(xs, ys, viz::Style().with_width(1.5).with_label(r.name));
      }
      ax.title("Top view: the footprint (grey: blocked from floor + 0.2 m to 2 m)")
          .xlabel("x (m)")
          .ylabel("y (m)")
          .legend(viz::LegendLocation::kUpperRight);
      fig.save_png(out + "/trajectory.png");
    }
    {
      viz::Figure fig(1600, 2200, kRuns, 2);
      fig.title("Errors against the truth, with +-2 sigma of the reported covariance (bands)");
      std::vector<double> t;
      for (const sim::TimedPose& p : tour) t.push_back(p.t);
      for (int m = 0; m < kRuns; ++m) {
        for (int part = 0; part < 2; ++part) {  // position (m), attitude (rad)
          viz::Axes& ax = fig.axes(m, part);
          const char* axis_names[3] = {part == 0 ? "x" : "roll", part == 0 ? "y" : "pitch",
                                       part == 0 ? "z" : "yaw"};
          for (int c = 0; c < 3; ++c) {
            std::vector<double> e, lo, hi;
            for (std::size_t k = 0; k < runs[m].estimates.size(); ++k) {
              const Vector6d d = ominus(runs[m].estimates[k], truth[k]);
              const double s =
                  std::sqrt(std::max(0.0, runs[m].covariances[k](3 * part + c, 3 * part + c)));
              e.push_back(d[3 * part + c]);
              lo.push_back(-2.0 * s);
              hi.push_back(2.0 * s);
            }
            const std::vector<double> tm(t.begin(), t.begin() + static_cast<long>(e.size()));
            ax.band(tm, lo, hi, viz::Style());
            ax.line(tm, e, viz::Style().with_width(1.2).with_label(axis_names[c]));
          }
          ax.title(runs[m].name + (part == 0 ? ": position, m" : ": attitude, rad"))
              .xlabel("time (s)")
              .legend(viz::LegendLocation::kUpperRight);
        }
      }
      fig.save_png(out + "/errors.png");
    }
    std::printf("wrote %s/table.csv, table.md, trajectory.png, errors.png (%.1f s)\n", out.c_str(),
                seconds());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
