#pragma once
// The parts of the 3D LiDAR example beyond main(): the world and the tour through it (world.cpp),
// the scans as point clouds (scan_cloud.cpp), the map a user would have (rebuilt_map.cpp), the
// tables (tables.cpp) and the figures (figures.cpp).

#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "vdtnav/core/pose3.hpp"
#include "vdtnav/estimation/vdt_localizer3d.hpp"
#include "vdtnav/map/grid.hpp"
#include "vdtnav/map/vdt_field.hpp"
#include "vdtnav/sim/lidar3d_simulator.hpp"
#include "vdtnav/sim/trajectory.hpp"

namespace lidar3d {

/// The world (= the map): the generated 3D room (`seed`) when `map_path` is empty, else the
/// OctoMap (.bt/.ot) or the point cloud at `map_path`; its name goes to `world_name`.
vdtnav::OccupancyGrid<3> load_world(const std::string& map_path, unsigned seed,
                                    std::string* world_name);

/// The 2D footprint the robot drives on: the floor layer, and per column whether it is free from
/// 0.2 m above the floor to 2 m and near a floor (the tour stays inside the building).
struct Footprint {
  vdtnav::OccupancyGrid<2> blocked;
  double floor_z = 0.0;  ///< the floor's surface (the top of its voxels), metres
};

Footprint footprint(const vdtnav::OccupancyGrid<3>& g);

/// The true 6-DOF poses along the tour: 1 m above the floor, rolling and pitching a few degrees.
std::vector<vdtnav::Pose3> true_poses(const std::vector<vdtnav::sim::TimedPose>& tour,
                                      double floor_z);

/// The scan as an organized cloud of `rings` rows, as a driver writes it.
pcl::PointCloud<pcl::PointXYZ> to_pcl(const vdtnav::sim::Lidar3dScan& scan, int rings);

/// The voxel edge that leaves about `target` readings of `cloud` (bisection on the edge).
double voxel_for(const pcl::PointCloud<pcl::PointXYZ>& cloud, std::size_t target);

/// The map a user would have (the file comment): the cloud of a mapping drive through `world`
/// along its own tour (`seed`), one scan every `every` poses, each registered at its true pose
/// moved by the map builder's error (N(0, pose_sigma^2) per axis in metres, N(0, (pose_sigma /
/// 10)^2) per axis in radians), voxelized as `vdtnav map3d` does with its defaults (0.1 m voxels,
/// or the world's if coarser; a 1 m margin).
vdtnav::OccupancyGrid<3> rebuilt_map(const vdtnav::OccupancyGrid<3>& world, const Footprint& fp,
                                     double speed, const vdtnav::sim::Lidar3dSpec& spec,
                                     double pose_sigma, unsigned seed, std::size_t* scans_used);

/// The localizers run on the drive: 6-DOF and 4-DOF on the map, and on the rebuilt map.
constexpr int kRuns = 4;

/// One localizer's run over the drive.
struct Run {
  std::string name;
  std::vector<vdtnav::Pose3> estimates;
  std::vector<vdtnav::Matrix6d> covariances;
  std::vector<double> nees;
  std::vector<int> nees_dof;
  int lost = 0, refused = 0, converged = 0;
  long iterations = 0;
  std::vector<double> scan_iterations;  ///< each update's solver evaluations: median and p99
  double seconds = 0.0;
  std::vector<double> scan_ms;  ///< each update's wall time: the table's median, p99 and max

  /// Adds an update's result, scored against `truth`, that took `seconds` of wall time.
  void record(const vdtnav::LocalizationResult3& r, const vdtnav::Pose3& truth, double seconds);
};

/// Writes the table.csv header and a row per run, the table.md table, and prints each run's
/// summary; `truth[k]` is the reference of every run's k-th estimate.
void write_rows(std::ostream& csv, std::ostream& md, const std::vector<vdtnav::Pose3>& truth,
                const Run* runs, std::size_t count_runs);

/// Writes table.csv and table.md and prints each run's summary.
void write_tables(const std::string& out, const std::string& world_name,
                  const std::vector<vdtnav::Pose3>& truth, double speed, std::size_t readings_sum,
                  double voxel, const vdtnav::sim::Lidar3dSpec& vlp16,
                  const vdtnav::VdtLocalizer3Options& o6, std::size_t mapping_scans,
                  double map_pose_sigma, const Run (&runs)[kRuns], double sim_seconds);

/// The study on a real sequence (real_scans.cpp): `--scans DIR --poses FILE`.
struct RealScans {
  std::string dir, poses, out;
  /// --odom FILE: the odometry's pose of each scan (KITTI or TUM, as the poses); the increments
  /// between the localized scans are the prediction (empty: drawn from the reference with noise).
  std::string odom;
  /// Readings per scan after voxel downsampling (about; the edge is fitted on the first scan);
  /// 0: one reading per map voxel, as `vdtnav localize3d` does by default.
  std::size_t points = 0;
  double voxel = -1.0;        ///< >= 0: this edge instead
  double resolution = 0.1;    ///< the map's voxel edge, metres (map3d's default)
  double sigma_range = 0.03;  ///< metres (localize3d's --sigma-range default)
  unsigned seed = 1;          ///< the odometry noise and the start's
};

/// Builds the map of the odd scans, localizes the even ones, writes table.csv and table.md.
/// \throws vdtnav::Error for a bad folder, pose file or cloud.
void run_real_scans(const RealScans& options);

/// Global localization trials (global_trials.cpp): `--global-trials N`.
struct GlobalTrials {
  std::string out;
  int trials = 40;
  double voxel = 0.0;            ///< the drive's voxel edge (readings per scan as the drive's)
  double sigma_gravity = 0.005;  ///< the IMU's roll and pitch noise, radians
  unsigned seed = 1;
};

/// A map the trials run on: its rows' name and its VDT.
struct TrialMap {
  std::string name;
  const vdtnav::VdtField3* map;
  vdtnav::VdtOptimizerOptions optimizer;  ///< the refinement: the map's tracker's
  double tolerance = 0.1;                 ///< metres: found when this near the truth
  double attitude_tolerance = 1.0;        ///< degrees: and this near
};

/// Runs the trials on each map (the first: the VDT of `world`, where the scans are cast) and
/// writes global.csv and global_trials.csv.
void run_global_trials(const vdtnav::OccupancyGrid<3>& world, const std::vector<TrialMap>& maps,
                       const Footprint& fp, const GlobalTrials& options);

/// Draws trajectory.png (top view over the footprint) and errors.png (errors with +-2 sigma).
void draw_figures(const std::string& out, const Footprint& fp,
                  const std::vector<vdtnav::sim::TimedPose>& tour,
                  const std::vector<vdtnav::Pose3>& truth, const Run (&runs)[kRuns]);

}  // namespace lidar3d
