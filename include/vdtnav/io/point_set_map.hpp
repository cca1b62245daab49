#pragma once
/// \file
/// \brief Occupancy maps from point sets (surveyed walls, point clouds, CSV files).

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/map/grid.hpp"

namespace vdtnav {

/// \brief Rasterises points into an axis-aligned occupancy grid.
///
/// The grid covers the points' bounding box expanded by `margin` on every side; its origin (the
/// lower corner of cell 0, SPEC) is snapped down to a multiple of `resolution`, so maps made from
/// different point sets at one resolution share cell boundaries. Every cell containing a point is
/// occupied (1), the rest free (0). Points with a NaN or infinite coordinate are dropped.
/// \param points     the points, world frame, metres.
/// \param resolution cell size (finite, > 0).
/// \param margin     free border around the bounding box (finite, >= 0), metres.
/// \param dropped    if not null, receives the number of non-finite points dropped.
/// \throws ConfigError when no finite point is left, resolution or margin is out of its domain,
///         or the grid would have 2^31 cells or more.
template <int Dim>
[[nodiscard]] OccupancyGrid<Dim> occupancy_from_points(
    const std::vector<Eigen::Matrix<double, Dim, 1>>& points, double resolution, double margin,
    std::size_t* dropped = nullptr);

/// \brief Reads a point set from a CSV file, one point "x,y" (Dim 2) or "x,y,z" (Dim 3) a line.
///
/// Blank lines and everything after '#' are ignored; the first remaining line is skipped as a
/// header when none of its fields is a number (e.g. "x,y,z"). Fields may have surrounding
/// spaces; "nan" and "inf" are numbers (occupancy_from_points() drops such points).
/// \throws IoError when the file cannot be read.
/// \throws FormatError `file:line: expected Dim comma-separated numbers ...` on a malformed line.
template <int Dim>
[[nodiscard]] std::vector<Eigen::Matrix<double, Dim, 1>> read_point_set_csv(
    const std::string& path);

}  // namespace vdtnav
