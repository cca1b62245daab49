#pragma once
// An empty box room for the 3D simulators' tests, built independently of sim::generate_room3d.

#include <algorithm>
#include <cmath>
#include <limits>

#include "vdtnav/map/grid.hpp"

namespace vdtnav::test {

inline constexpr double kBoxRes = 0.05;  ///< metres per cell

/// An empty box room built here, independently of room3d: three layers of cells beyond each of
/// the planes x = 0, x = lx, y = 0, y = ly, z = 0 (floor) and z = h (ceiling), cell centres on
/// multiples of kBoxRes, so the cell-centre surfaces are exactly those planes.
struct BoxRoom {
  double lx, ly, h;
  bool walls_and_ceiling;
  OccupancyGrid<3> grid;

  BoxRoom(double lx_, double ly_, double h_, bool walls_and_ceiling_)
      : lx(lx_), ly(ly_), h(h_), walls_and_ceiling(walls_and_ceiling_) {
    const int nx = static_cast<int>(std::lround(lx / kBoxRes)),
              ny = static_cast<int>(std::lround(ly / kBoxRes)),
              nz = static_cast<int>(std::lround(h / kBoxRes));
    // Cell (i, j, k) has its centre at ((i - 2) kBoxRes, (j - 2) kBoxRes, (k - 2) kBoxRes).
    grid = OccupancyGrid<3>(Eigen::Vector3i(nx + 5, ny + 5, nz + 5),
                            GridFrame<3>(kBoxRes, Eigen::Vector3d::Constant(-2.5 * kBoxRes)), 0);
    for (int k = 0; k < nz + 5; ++k)
      for (int j = 0; j < ny + 5; ++j)
        for (int i = 0; i < nx + 5; ++i) {
          const int ci = i - 2, cj = j - 2, ck = k - 2;
          const bool floor = ck <= 0;
          const bool other = ci <= 0 || ci >= nx || cj <= 0 || cj >= ny || ck >= nz;
          if (floor || (walls_and_ceiling && other)) grid(Eigen::Vector3i(i, j, k)) = 1;
        }
  }

  /// Distance along the unit `dir` from `o` to the first of the room's planes (+inf if none).
  /// `planes_near_hit` counts the planes within `edge` of the hit point.
  [[nodiscard]] double oracle(const Eigen::Vector3d& o, const Eigen::Vector3d& dir, double edge,
                              int* planes_near_hit) const {
    const Eigen::Vector3d lo(0.0, 0.0, 0.0), hi(lx, ly, h);
    double t = std::numeric_limits<double>::infinity();
    for (int a = 0; a < 3; ++a) {
      if (!walls_and_ceiling && a < 2) continue;
      if (dir[a] < 0) t = std::min(t, (lo[a] - o[a]) / dir[a]);
      if (dir[a] > 0 && (walls_and_ceiling || a != 2)) t = std::min(t, (hi[a] - o[a]) / dir[a]);
    }
    if (planes_near_hit != nullptr && std::isfinite(t)) {
      const Eigen::Vector3d p = o + t * dir;
      *planes_near_hit = 0;
      for (int a = 0; a < 3; ++a)
        *planes_near_hit += (std::abs(p[a] - lo[a]) < edge) + (std::abs(p[a] - hi[a]) < edge);
    }
    return t;
  }
};

}  // namespace vdtnav::test
