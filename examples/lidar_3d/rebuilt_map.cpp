// The map a user would have: `vdtnav map3d` of the cloud of a separate mapping drive, its scans
// registered at the map builder's noisy poses.
#include <algorithm>
#include <cstdio>
#include <random>
#include <vector>

#include "lidar_3d_study.hpp"
#include "vdtnav/pcl/point_cloud_conversion.hpp"
#include "vdtnav/sim/route_planner.hpp"

namespace lidar3d {

using namespace vdtnav;

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

}  // namespace lidar3d
