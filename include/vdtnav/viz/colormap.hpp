#pragma once
/// \file
/// \brief Colormaps, and rendering of scalar and occupancy grids as images (world y up).

#include <cstdint>
#include <utility>

#include "vdtnav/map/grid.hpp"
#include "vdtnav/viz/image.hpp"

namespace vdtnav::viz {

/// \brief The colormaps of vdtnav figures.
enum class Colormap {
  kViridis,       ///< perceptually uniform dark blue -> green -> yellow, for magnitudes
  kBlueWhiteRed,  ///< diverging, white at t = 0.5, for signed fields (use lo = -hi)
  kGray,          ///< black -> white
};

/// \brief Colour of non-finite cells in heatmaps: a neutral gray, which viridis and blue-white-red
/// never produce (pass another `nan_color` to heatmap() with kGray).
inline constexpr Rgb kNanColor{150, 150, 150};

/// \return the colour of `map` at t in [0, 1] (t is clamped; NaN gives kNanColor).
[[nodiscard]] Rgb colormap(Colormap map, double t);

/// \return {min, max} over the finite values of `field`, or {0, 1} if it has none.
[[nodiscard]] std::pair<double, double> finite_range(const Grid<float, 2>& field);

/// \brief One pixel per cell, coloured by `colormap(map, (v - lo) / (hi - lo))`, with grid row
/// y = 0 at the *bottom* of the image (world y up); NaN and infinite cells get `nan_color`.
/// If hi <= lo every finite cell gets the colour at t = 0.5.
[[nodiscard]] RgbImage heatmap(const Grid<float, 2>& field, Colormap map, double lo, double hi,
                               Rgb nan_color = kNanColor);

/// \brief One pixel per cell: occupied (non-zero) black, free white; row y = 0 at the bottom.
[[nodiscard]] RgbImage occupancy_image(const Grid<std::uint8_t, 2>& occupancy);

/// \brief ROS occupancy cells (-1 unknown, 0..100 occupied percent) as map_server draws them:
/// unknown grey (205), then 255 - 2.55 v from free white to occupied black; row y = 0 at the
/// bottom.
[[nodiscard]] RgbImage occupancy_image(const Grid<std::int8_t, 2>& ros_cells);

}  // namespace vdtnav::viz
