// The world the LiDAR drives in (= the map), generated or loaded; its 2D footprint; the true
// poses along a tour over it.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "lidar_3d_study.hpp"
#include "vdtnav/octomap/octree_map.hpp"
#include "vdtnav/pcl/point_cloud_map.hpp"
#include "vdtnav/sim/room3d.hpp"

namespace lidar3d {

using namespace vdtnav;

namespace {}  // namespace

OccupancyGrid<3> load_world(const std::string& map_path, unsigned seed, std::string* world_name) {
  OccupancyGrid<3> world;
  if (map_path.empty()) {
    sim::Room3dOptions ro;
    ro.seed = seed;
    world = sim::generate_room3d(ro).occupancy;
    *world_name = "generated room";
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
    *world_name = std::filesystem::path(map_path).filename().string();
  }
  return world;
}

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

}  // namespace lidar3d
