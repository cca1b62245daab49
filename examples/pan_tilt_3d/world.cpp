// vdtnav_pan_tilt_3d: the world the study runs in, the generated 3D room or an OctoMap, its VDT
// and the robot locations (pan_tilt_study.hpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "pan_tilt_study.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/sim/ray_casting.hpp"
#include "vdtnav/sim/room3d.hpp"
#ifdef VDTNAV_HAVE_OCTOMAP
#include "vdtnav/octomap/octree_map.hpp"
#endif

namespace pan_tilt_study {

/// \return the world height of the beam origin at zero pan and tilt (the "sensor height").
double sensor_z(const Pose3& robot, const PanTiltCalibration& calibration) {
  return (robot * pan_tilt_laser_pose(calibration, 0.0, 0.0)).translation().z();
}

#ifdef VDTNAV_HAVE_OCTOMAP
namespace {

/// Picks `count` robot locations in the free space of an arbitrary 3D map (e.g. an OctoMap of a
/// real building), deterministically from `seed`:
///  - the floor band: the most frequent height of the lowest occupied voxel of a column, +-0.4 m;
///  - a candidate (x, y) is drawn uniformly over the columns whose lowest voxel is in that band
///    (shrunk by 1 m); its floor z_f is the median of those lowest voxels within 0.5 m (>= 5 of
///    them: a real scan's floor is sparse);
///  - free space: |DT_v| > 0.5 m at 0.6, 0.9 and 1.2 m above z_f (a free ball around the robot
///    and its mast) and, at the sensor height, at least 10 of 12 horizontal rays hit the map
///    within 20 m (inside the building, not in the empty margin of the grid);
///  - at least 2 m between locations;
/// and, as sim::uneven_floor_poses does for the generated room, stands the robot there with a
/// uniform yaw, roll and pitch of 1-5 degrees with random signs and its origin 0-5 cm above z_f.
std::vector<Pose3> free_space_locations(const OccupancyGrid<3>& occ, const VdtMap3& vdt, int count,
                                        std::uint32_t seed, std::string* how) {
  const Eigen::Vector3i n = occ.size();
  const double res = occ.resolution();
  std::vector<int> lowest(static_cast<std::size_t>(n.x()) * n.y(), -1);
  std::vector<long> histogram(static_cast<std::size_t>(n.z()), 0);
  for (int j = 0; j < n.y(); ++j)
    for (int i = 0; i < n.x(); ++i)
      for (int k = 0; k < n.z(); ++k)
        if (occ(Eigen::Vector3i(i, j, k))) {
          lowest[static_cast<std::size_t>(j) * n.x() + i] = k;
          ++histogram[static_cast<std::size_t>(k)];
          break;
        }
  const int mode =
      static_cast<int>(std::max_element(histogram.begin(), histogram.end()) - histogram.begin());
  const double floor_mode = occ.cell_center(Eigen::Vector3i(0, 0, mode)).z();
  const auto lowest_z = [&](int i, int j) {
    const int k = lowest[static_cast<std::size_t>(j) * n.x() + i];
    if (k < 0) return std::numeric_limits<double>::quiet_NaN();
    const double z = occ.cell_center(Eigen::Vector3i(i, j, k)).z();
    return std::abs(z - floor_mode) <= 0.4 ? z : std::numeric_limits<double>::quiet_NaN();
  };
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (int j = 0; j < n.y(); ++j)
    for (int i = 0; i < n.x(); ++i)
      if (std::isfinite(lowest_z(i, j))) {
        const Eigen::Vector2d c = occ.cell_center(Eigen::Vector3i(i, j, 0)).head<2>();
        lo = lo.cwiseMin(c);
        hi = hi.cwiseMax(c);
      }
  VDTNAV_CHECK((hi - lo).minCoeff() > 3.0, "pan_tilt_3d: the map has no floor of at least 3 m");
  lo.array() += 1.0;
  hi.array() -= 1.0;

  const auto local_floor = [&](const Eigen::Vector2d& c, double* z_floor) {
    const Eigen::Vector3i a = occ.cell_of(Eigen::Vector3d(c.x() - 0.5, c.y() - 0.5, 0.0));
    const Eigen::Vector3i b = occ.cell_of(Eigen::Vector3d(c.x() + 0.5, c.y() + 0.5, 0.0));
    std::vector<double> zs;
    for (int j = std::max(0, a.y()); j <= std::min(n.y() - 1, b.y()); ++j)
      for (int i = std::max(0, a.x()); i <= std::min(n.x() - 1, b.x()); ++i) {
        const double z = lowest_z(i, j);
        if (std::isfinite(z) &&
            (occ.cell_center(Eigen::Vector3i(i, j, 0)).head<2>() - c).norm() <= 0.5)
          zs.push_back(z);
      }
    if (zs.size() < 5) return false;
    std::nth_element(zs.begin(), zs.begin() + zs.size() / 2, zs.end());
    *z_floor = zs[zs.size() / 2];
    return true;
  };
  const auto is_free = [&](const Eigen::Vector2d& c, double z_floor) {
    for (double h : {0.6, 0.9, 1.2}) {
      bool inside = false;
      const Eigen::Vector3d d = vdt.value(Eigen::Vector3d(c.x(), c.y(), z_floor + h), &inside);
      if (!inside || d.norm() <= 0.5) return false;
    }
    int hits = 0;
    for (int a = 0; a < 12; ++a) {
      const Eigen::Vector3d dir(std::cos(a * kPi / 6), std::sin(a * kPi / 6), 0.0);
      const double r = sim::cast_ray<3>(occ, Eigen::Vector3d(c.x(), c.y(), z_floor + 0.45), dir,
                                        20.0, sim::RaySurface::kCellCentre);
      hits += std::isfinite(r) && r < 20.0 ? 1 : 0;
    }
    return hits >= 10;
  };

  std::mt19937 rng(seed);
  const auto uniform = [&rng](double a, double b) {
    return std::uniform_real_distribution<double>(a, b)(rng);
  };
  const auto signed_tilt = [&] {
    const double m = uniform(1.0 * kPi / 180, 5.0 * kPi / 180);
    return uniform(0.0, 1.0) < 0.5 ? -m : m;
  };
  std::vector<Pose3> poses;
  std::vector<Eigen::Vector2d> places;
  int attempts = 0;
  for (; static_cast<int>(poses.size()) < count; ++attempts) {
    if (attempts >= 20000)
      throw ConfigError("pan_tilt_3d: found only " + std::to_string(poses.size()) + " of " +
                        std::to_string(count) +
                        " free robot locations (|DT_v| > 0.5 m above a floor, 2 m apart)");
    const Eigen::Vector2d c(uniform(lo.x(), hi.x()), uniform(lo.y(), hi.y()));
    if (std::any_of(places.begin(), places.end(),
                    [&](const Eigen::Vector2d& p) { return (p - c).norm() < 2.0; }))
      continue;
    double z_floor = 0.0;
    if (!local_floor(c, &z_floor) || !is_free(c, z_floor)) continue;
    const double yaw = uniform(-kPi, kPi);
    const double roll = signed_tilt(), pitch = signed_tilt();
    const double z = z_floor + uniform(0.0, 0.05);
    places.push_back(c);
    poses.push_back(pose3_from_xyz_rpy(c.x(), c.y(), z, roll, pitch, yaw));
  }
  char line[256];
  std::snprintf(line, sizeof line,
                "chosen automatically (seed %u, %d candidates): floor band %.2f +- 0.4 m, "
                "|DT_v| > 0.5 m from 0.6 to 1.2 m above the local floor, 2 m apart (%.2f m voxels)",
                seed, attempts, floor_mode, res);
  *how = line;
  return poses;
}

}  // namespace
#endif  // VDTNAV_HAVE_OCTOMAP

bool build_world(const std::string& map_path, unsigned seed, double resolution, World& world,
                 std::unique_ptr<VdtMap3>& vdt) {
  if (map_path.empty()) {
    sim::Room3dOptions ro;
    ro.seed = seed;
    if (resolution > 0.0) {
      ro.resolution = resolution;
      ro.wall_thickness = std::max(ro.wall_thickness, 2.0 * resolution);
    }
    std::fprintf(stderr, "[map] generating the 3D room (seed %u, %.3f m voxels)\n", seed,
                 ro.resolution);
    sim::Room3d r = sim::generate_room3d(ro);
    world.name = "generated room";
    sim::UnevenFloorOptions uo;
    uo.seed = seed;
    world.locations = sim::uneven_floor_poses(r, uo);
    world.how_located =
        "sim::uneven_floor_poses (seed " + std::to_string(seed) +
        "): 0.5 m clearance up to 1 m, 2 m apart, roll/pitch 1-5 deg, origin 0-5 cm above the "
        "floor";
    world.occupancy = std::move(r.occupancy);
    std::fprintf(stderr, "[map] building the VDT of %d x %d x %d voxels\n",
                 world.occupancy.size().x(), world.occupancy.size().y(),
                 world.occupancy.size().z());
    vdt = std::make_unique<VdtMap3>(VdtMap3::build(world.occupancy));
  } else {
#ifdef VDTNAV_HAVE_OCTOMAP
    OctreeOccupancyOptions oo;
    oo.resolution = resolution;
    oo.margin = 0.5;  // free border: rays leaving the building end in free space, not the edge
    std::fprintf(stderr, "[map] loading %s\n", map_path.c_str());
    OctreeOccupancy tree = load_octree_occupancy(map_path, oo);
    world.name = std::filesystem::path(map_path).filename().string();
    world.occupancy = std::move(tree.occupancy);
    std::fprintf(stderr, "[map] building the VDT of %d x %d x %d voxels of %.3f m (%zu occupied)\n",
                 world.occupancy.size().x(), world.occupancy.size().y(), world.occupancy.size().z(),
                 world.occupancy.resolution(), tree.num_occupied);
    vdt = std::make_unique<VdtMap3>(VdtMap3::build(world.occupancy));
    world.locations = free_space_locations(world.occupancy, *vdt, 3, seed, &world.how_located);
#else
    std::fprintf(stderr,
                 "error: --map needs the OctoMap front end (vdtnav::octomap), which this build "
                 "does not have; configure with -DVDTNAV_BUILD_FRONTENDS=ON and OctoMap "
                 "installed\n");
    return false;
#endif
  }
  return true;
}

}  // namespace pan_tilt_study
