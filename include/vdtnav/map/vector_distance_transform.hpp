#pragma once
/// \file
/// \brief The exact Euclidean vector distance transform (thesis 2.2) and the UDT and SDT derived
/// from it.
///
/// The core is an exact Euclidean *feature* transform: for every cell, the linear index of the
/// nearest occupied cell (Felzenszwalb & Huttenlocher's separable lower envelope of parabolas,
/// carrying the argmin through each pass). It is exact, runs in O(cells) time, and gives
///   DT_v(p) = p - c(p)          (c(p): centre of the occupied cell nearest to p; SPEC convention)
///   DT_u(p) = |DT_v(p)|
/// Ties (several nearest occupied cells) are broken arbitrarily but deterministically.

#include <cstdint>

#include "vdtnav/map/grid.hpp"

namespace vdtnav {

/// Feature value of cells that have no occupied cell to point to (the map is empty).
inline constexpr std::int32_t kNoFeature = -1;

/// \brief Exact Euclidean feature transform.
/// \param occupied non-zero = occupied.
/// \return for every cell the linear index of its nearest occupied cell (itself when occupied),
///         or kNoFeature everywhere when no cell is occupied.
template <int Dim>
[[nodiscard]] Grid<std::int32_t, Dim> nearest_occupied_cells(const OccupancyGrid<Dim>& occupied);

/// \brief The surface cells of an occupancy grid: occupied cells with at least one free
/// 4-neighbour (6-neighbour in 3D) inside the grid. When no cell qualifies (an all-occupied grid),
/// every occupied cell is returned.
///
/// For every free cell the nearest occupied cell is a surface cell, so a transform of the surface
/// cells equals that of all occupied cells outside obstacles; inside them it keeps pointing to the
/// nearest surface instead of collapsing to zero, which keeps range noise that pushes an endpoint
/// into a thick wall from being clipped.
template <int Dim>
[[nodiscard]] OccupancyGrid<Dim> surface_cells(const OccupancyGrid<Dim>& occupied);

/// \brief DT_v at every cell centre, in the grid's own axes and metres: (i - c(i)) * resolution.
/// Cells without a feature get NaN.
template <int Dim>
[[nodiscard]] Grid<Eigen::Matrix<float, Dim, 1>, Dim> vector_distance_transform(
    const Grid<std::int32_t, Dim>& nearest);

/// \brief UDT at every cell centre in metres (+inf without a feature).
template <int Dim>
[[nodiscard]] Grid<float, Dim> unsigned_distance_transform(const Grid<std::int32_t, Dim>& nearest);

/// \brief SDT at every cell centre in metres.
///
/// Inside/outside rule: occupied cells are inside. Cells are squares (cubes), and the zero level
/// is the boundary between occupied and free cells:
///   free cell:      SDT = +(distance to the nearest occupied cell centre - resolution/2)
///   occupied cell:  SDT = -(distance to the nearest free cell centre - resolution/2)
/// so a free cell next to a wall reads +r/2 and the wall cell -r/2. An empty map reads +inf
/// everywhere, an all-occupied map -inf.
template <int Dim>
[[nodiscard]] Grid<float, Dim> signed_distance_transform(const OccupancyGrid<Dim>& occupied);

}  // namespace vdtnav
