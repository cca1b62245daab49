#pragma once
// 3D test clouds: a box room (8 m x 6 m x 3 m at 0.05 m, with boxes, a table and pillars) whose
// faces all lie on cell-centre planes, and pan-tilt-like sweeps ray cast in it with
// RaySurface::kCellCentre, so that noise-free points lie on the zero set of the VDT (thesis
// 3.4.4's pan-tilt point laser, simulated).

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "vdtnav/core/pose3.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/sensor/observation_set.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace vdtnav::test {

/// Occupancy of a room with inner faces x = 0, y = 0, z = 0 (floor) and x = lx, y = ly, z = lz,
/// walls `wall` cells thick, plus the given solids (closed boxes in metres, on cell-centre planes).
/// Walls are thick (0.5 m) next to the range noise: inside a solid the VDT points to the nearest
/// surface cell, so half-way through a solid lies a cut locus where it folds, and the
/// interpolating spline bends it over two cells on either side; a noisy endpoint there would be
/// pulled towards the far face.
inline OccupancyGrid<3> box_room(double lx, double ly, double lz, double res,
                                 const std::vector<Eigen::AlignedBox3d>& solids, int wall = 10) {
  const int kWall = wall, kMargin = 1;
  const Eigen::Vector3d extent(lx, ly, lz);
  // Cell centres at integer multiples of res: the inner face layer (index kMargin + kWall - 1)
  // is centred on 0.
  const Eigen::Vector3d origin = Eigen::Vector3d::Constant(-(kMargin + kWall - 0.5) * res);
  Eigen::Vector3i size;
  for (int d = 0; d < 3; ++d)
    size[d] = static_cast<int>(std::lround(extent[d] / res)) + 2 * (kMargin + kWall) - 1;
  OccupancyGrid<3> occ(size, GridFrame<3>(res, origin), 0);
  const double eps = 1e-6;
  for (int k = 0; k < size.z(); ++k)
    for (int j = 0; j < size.y(); ++j)
      for (int i = 0; i < size.x(); ++i) {
        const Eigen::Vector3i c(i, j, k);
        const Eigen::Vector3d p = occ.cell_center(c);
        bool shell = true, wall = false;
        for (int d = 0; d < 3; ++d) {
          shell &= p[d] > -kWall * res + eps && p[d] < extent[d] + kWall * res - eps;
          wall |= p[d] < eps || p[d] > extent[d] - eps;
        }
        bool solid = shell && wall;
        for (const auto& b : solids)
          solid |= (p.array() >= b.min().array() - eps).all() &&
                   (p.array() <= b.max().array() + eps).all();
        occ(c) = solid ? 1 : 0;
      }
  return occ;
}

/// The furniture of the test room.
inline std::vector<Eigen::AlignedBox3d> room_solids() {
  using B = Eigen::AlignedBox3d;
  using V = Eigen::Vector3d;
  return {
      B(V(1.0, 4.5, 0.0), V(2.0, 6.0, 1.8)),     // cabinet against the far wall
      B(V(5.5, 0.0, 0.0), V(6.5, 0.8, 1.0)),     // crate against the near wall
      B(V(6.0, 3.0, 0.0), V(6.3, 3.3, 3.0)),     // pillar
      B(V(3.5, 4.8, 0.0), V(3.7, 5.0, 3.0)),     // pillar
      B(V(4.0, 1.5, 0.65), V(5.0, 2.5, 0.8)),    // table top
      B(V(4.0, 1.5, 0.0), V(4.15, 1.65, 0.65)),  // its legs
      B(V(4.85, 1.5, 0.0), V(5.0, 1.65, 0.65)),
      B(V(4.0, 2.35, 0.0), V(4.15, 2.5, 0.65)),
      B(V(4.85, 2.35, 0.0), V(5.0, 2.5, 0.65)),
      B(V(0.0, 0.0, 2.6), V(8.0, 0.4, 3.0)),  // a soffit along the near wall
  };
}

struct World3 {
  OccupancyGrid<3> occupancy = box_room(8.0, 6.0, 3.0, 0.05, room_solids());
  VdtMap3 map = VdtMap3::build(occupancy);
};

inline const World3& world3() {
  static const World3 w;
  return w;
}

/// A robot standing on an uneven floor (rolled and pitched a few degrees), as in 3.4.4.2.
inline Pose3 cloud_pose(int k) {
  switch (k % 3) {
    case 0:
      return pose3_from_xyz_rpy(3.1, 2.9, 0.03, 0.04, -0.03, 0.35);
    case 1:
      return pose3_from_xyz_rpy(2.3, 1.7, 0.05, -0.05, 0.02, -2.2);
    default:
      return pose3_from_xyz_rpy(6.9, 4.4, 0.02, 0.03, 0.05, 1.9);
  }
}

/// Scenario B of Table 3.4: the guess is off by +0.1 m in x, y, z and +0.05 rad in roll, pitch
/// and yaw.
inline Pose3 scenario_b_guess(const Pose3& truth) {
  const Eigen::Vector3d t = truth.translation() + Eigen::Vector3d::Constant(0.1);
  const Eigen::Vector3d rpy = rpy_of(truth.linear()) + Eigen::Vector3d::Constant(0.05);
  return pose3_from_xyz_rpy(t.x(), t.y(), t.z(), rpy[0], rpy[1], rpy[2]);
}

/// A pan-tilt sweep of `pans` x `tilts` readings (5700 = 95 x 60 by default) from a beam origin
/// 0.4 m above the robot origin: pan over the full circle, tilt from 0.7 rad up to 1.2 rad down
/// (positive tilt looks down, as for the pan-tilt unit). Range noise sigma (0: none).
///
/// Which readings a simulated cloud keeps.
enum class Keep {
  kAll,  ///< every reading that hit something
  /// Readings whose noise-free endpoint the map represents exactly (|DT_v| < 1 um there; about
  /// 80 %): in 3D, kCellCentre stops a ray half a cell past the face it entered, which for grazing
  /// rays is well off the surface (up to 0.27 m here), and next to box edges and concave corners
  /// the rasterised surface departs from the boxes by up to half a cell.
  kExact,
};

/// Noise is added after the selection, so a selected noisy cloud is unbiased.
inline ObservationSet3 simulate_cloud(const Pose3& pose, double sigma, std::mt19937& rng,
                                      Keep keep = Keep::kExact, int pans = 95, int tilts = 60) {
  ObservationSet3 out;
  out.sigma_range = sigma > 0 ? sigma : 0.025;
  std::normal_distribution<double> noise(0.0, sigma > 0 ? sigma : 1.0);
  const Eigen::Vector3d origin(0.0, 0.0, 0.4);
  std::size_t index = 0;
  for (int a = 0; a < pans; ++a) {
    const double pan = -M_PI + 2.0 * M_PI * (a + 0.5) / pans;
    for (int b = 0; b < tilts; ++b, ++index) {
      const double tilt = -0.7 + 1.9 * b / (tilts - 1);
      const Eigen::Vector3d u(std::cos(pan) * std::cos(tilt), std::sin(pan) * std::cos(tilt),
                              -std::sin(tilt));
      double r = sim::cast_ray<3>(world3().occupancy, pose * origin, pose.linear() * u, 40.0,
                                  sim::RaySurface::kCellCentre);
      if (!std::isfinite(r)) {
        ++out.dropped_not_finite;
        continue;
      }
      if (keep == Keep::kExact && world3().map.value(pose * (origin + r * u)).norm() >= 1e-6)
        continue;
      if (sigma > 0) r += noise(rng);
      out.add(origin, u, r, index);
    }
  }
  return out;
}

}  // namespace vdtnav::test
