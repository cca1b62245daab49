#pragma once
/// \file
/// \brief How far a map's surfaces stray from smooth ones: the per-reading floor a range model
/// needs on a map made by SLAM, measured from the map itself.
///
/// A map's DT at a reading's endpoint is the distance to the nearest surface cell; when the true
/// surface is smooth, the model's error is the offset of that cell from it. On a clean raster of a
/// straight wall the offsets are the quantisation, uniform over a cell (h/sqrt(12) at any angle but
/// the axes'); on a SLAM map a wall is jagged by a cell or more where scans disagreed, and a
/// predicted endpoint slides over that pattern as the pose moves. Measured here as the spread of
/// the surface cells about the plane (line in 2D) fitted through one face of a surface in a small
/// window: the smallest eigenvalue of the window's scatter. Per face: for every surface cell and
/// every face it exposes to free space, the window holds the cells exposing that same face,
/// linked within two cells of each other (a jag of one cell either way leaves a gap of one) and
/// within `radius` of the centre — so a thick wall's two faces, the wall across a corner and the
/// shelf beside a wall are not roughness. sigma is the RMS over all windows (the variance of the
/// offsets a reading meets), not a median: on the fetch-office map a median read 2.2 cm (with an
/// earlier window rule) where a hand-set 2 cm floor had lost the single-beam filter's track
/// (README, "Active localization").

#include "vdtnav/map/grid.hpp"

namespace vdtnav {

struct SurfaceRoughnessOptions {
  /// Window half-width in cells (a window spans 2 * radius + 1 cells along the surface).
  int radius = 4;
  /// Cells a window must hold to be fitted (default: radius + 1, half a straight window).
  int min_cells = -1;
};

struct SurfaceRoughness {
  /// Metres: the RMS over windows of the surface cells' offsets from their fitted plane.
  double sigma = 0.0;
  /// Windows fitted (0: no surface, sigma is 0).
  std::size_t windows = 0;
  /// The floor a range model should use: max(sigma, resolution / sqrt(12)).
  double floor = 0.0;
};

/// \brief The roughness of the occupied cells' surfaces (see the file comment).
/// \param occupied non-zero = occupied.
template <int Dim>
[[nodiscard]] SurfaceRoughness measure_surface_roughness(
    const OccupancyGrid<Dim>& occupied, const SurfaceRoughnessOptions& options = {});

}  // namespace vdtnav
