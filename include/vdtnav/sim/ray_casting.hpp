#pragma once
/// \file
/// \brief Exact ray casting through an occupancy grid (Amanatides & Woo's voxel traversal), in
/// 2D and 3D: the range at which a ray first enters an occupied cell.

#include <cmath>
#include <limits>

#include "vdtnav/map/grid.hpp"

namespace vdtnav::sim {

/// \brief Distance along the unit direction `dir` from `origin` (world frame) to the boundary of
/// the first occupied cell the ray enters, or +inf when none is hit within `max_range` or the
/// ray leaves the grid. A ray starting inside an occupied cell returns 0.
template <int Dim>
[[nodiscard]] double cast_ray(const OccupancyGrid<Dim>& grid,
                              const typename SpaceTraits<Dim>::Vector& origin,
                              const typename SpaceTraits<Dim>::Vector& dir, double max_range) {
  using Vector = typename SpaceTraits<Dim>::Vector;
  using Index = typename SpaceTraits<Dim>::Index;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const auto& frame = grid.frame();
  // Work in grid-local cell units: cell i spans [i, i+1) on each axis.
  const Vector local_dir = frame.axis_aligned() ? dir : Vector(frame.rotation().transpose() * dir);
  const Vector start = frame.continuous_index(origin) + Vector::Constant(0.5);
  const double inv_res = frame.inv_resolution();
  Index cell, step;
  Vector t_max, t_delta;  // in metres along the ray
  for (int d = 0; d < Dim; ++d) {
    cell[d] = static_cast<int>(std::floor(start[d]));
    if (local_dir[d] > 0) {
      step[d] = 1;
      t_delta[d] = 1.0 / (local_dir[d] * inv_res);
      t_max[d] = (cell[d] + 1 - start[d]) * t_delta[d];
    } else if (local_dir[d] < 0) {
      step[d] = -1;
      t_delta[d] = -1.0 / (local_dir[d] * inv_res);
      t_max[d] = (start[d] - cell[d]) * t_delta[d];
    } else {
      step[d] = 0;
      t_delta[d] = kInf;
      t_max[d] = kInf;
    }
  }
  double t = 0.0;
  while (t <= max_range) {
    if (!grid.contains(cell)) return kInf;
    if (grid(cell)) return t;
    int axis = 0;
    for (int d = 1; d < Dim; ++d)
      if (t_max[d] < t_max[axis]) axis = d;
    t = t_max[axis];
    t_max[axis] += t_delta[axis];
    cell[axis] += step[axis];
  }
  return kInf;
}

}  // namespace vdtnav::sim
