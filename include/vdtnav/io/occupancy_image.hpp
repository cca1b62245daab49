#pragma once
/// \file
/// \brief Floor-plan bitmaps without a YAML (e.g. Player/Stage worlds, whose size in metres is
/// given by the world file) as occupancy grids.

#include <string>

#include <Eigen/Core>

#include "vdtnav/map/grid.hpp"

namespace vdtnav {

/// \brief Loads a PNG/PGM floor plan (dark = occupied) covering `size` metres, resampled to
/// square cells of `resolution`; the image's bottom-left corner is the world origin.
///
/// Pixels need not be square (the Stage hospital section is 1086 x 443 px for 40 m x 18 m). A cell
/// is occupied when any pixel overlapping it has luminance below `dark_threshold` (0..1), so
/// one-pixel walls survive downsampling.
/// \throws IoError if the file cannot be read, FormatError if it is not a decodable image,
///         ConfigError for a non-positive size or resolution.
[[nodiscard]] OccupancyGrid<2> load_occupancy_image(const std::string& path,
                                                    const Eigen::Vector2d& size, double resolution,
                                                    double dark_threshold = 0.5);

}  // namespace vdtnav
