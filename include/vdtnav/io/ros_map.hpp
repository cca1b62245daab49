#pragma once
/// \file
/// \brief ROS map_server maps (YAML + PGM/PNG image): loading with map_server's semantics, saving
/// like map_saver, and the occupancy grid the distance transforms take.
///
/// Conventions (SPEC): `origin` [x, y, yaw] is the pose of the lower-left corner of cell (0, 0);
/// cell centres lie at origin + R(yaw) (i + 1/2) resolution. Image row 0 is the *top* of the map,
/// so cell (i, j) is pixel (column i, row height - 1 - j).

#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "vdtnav/map/grid.hpp"

namespace vdtnav {

/// \brief How map_server turns a pixel into a cell value (YAML key `mode`).
enum class RosMapMode {
  kTrinary,  ///< occupied 100, free 0, unknown -1 (the default)
  kScale,    ///< like trinary, but values between the thresholds are scaled to 1..99
  kRaw,      ///< the grey value itself (0..100; anything above is unknown)
};

/// Cell value of unknown space in a ROS occupancy grid.
inline constexpr std::int8_t kRosUnknown = -1;
/// Cell value of certainly occupied space.
inline constexpr std::int8_t kRosOccupied = 100;
/// Cell value of certainly free space.
inline constexpr std::int8_t kRosFree = 0;
/// Cells with a value >= this (on the 0..100 scale) count as occupied: 65 is the ROS default
/// `occupied_thresh` 0.65 expressed on that scale (map_saver and Nav2 use the same cut).
inline constexpr std::int8_t kRosOccupiedThreshold = 65;

/// \brief The parameters of a map_server YAML file, as written there.
struct RosMapMetadata {
  std::string image;                                 ///< image path as written in the YAML
  double resolution = 0.05;                          ///< metres per cell (> 0)
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< x, y of the lower-left corner; yaw
  bool negate = false;                               ///< true: white is occupied
  double occupied_thresh = 0.65;  ///< occupancy probability above which a cell is occupied
  double free_thresh = 0.196;     ///< occupancy probability below which a cell is free
  RosMapMode mode = RosMapMode::kTrinary;
};

/// \brief A loaded map_server map.
struct RosMap {
  /// Cell values -1 (unknown) or 0..100, framed by resolution, origin xy and origin yaw.
  Grid<std::int8_t, 2> cells;
  RosMapMetadata metadata;  ///< the parsed YAML
  std::string image_path;   ///< the image file actually read (image resolved against the YAML)
};

/// \brief Loads a ROS map_server map.
///
/// Keys (map_server's): `image` (relative to the YAML's folder, or absolute), `resolution`,
/// `origin` [x, y, yaw], `negate` (0/1 or a boolean), `occupied_thresh`, `free_thresh` (all
/// required) and `mode` (trinary, scale or raw; default trinary). The image (PNG, or binary
/// PGM/PPM with maxval <= 255, which is rescaled to 0..255 as map_server's SDL_image does) is
/// decoded by stb_image. Per pixel, as ROS 1 map_server computes it:
///  - v = mean of the colour channels (grey counts as R = G = B); in trinary mode an alpha
///    channel is averaged in as a fourth channel (map_server keeps that for compatibility);
///    with `negate`, v = 255 - v;
///  - raw: cell = floor(v) when <= 100, else -1 (map_server would wrap such values into
///    negative int8; Nav2 and we report them as unknown);
///  - otherwise p = (255 - v) / 255: p > occupied_thresh -> 100, p < free_thresh -> 0, else
///    -1 in trinary mode or where alpha is 0 (fully transparent), and in scale mode
///    floor(1 + 98 (p - free_thresh) / (occupied_thresh - free_thresh)) in 1..99.
/// \param yaml_path the map's YAML file.
/// \throws IoError when the YAML or the image cannot be read.
/// \throws FormatError (`file:line: what was expected`) for a YAML syntax error, a missing key, a
///         value of the wrong type, resolution not finite and > 0, origin not a sequence of 3
///         finite numbers, a threshold outside [0, 1] or free_thresh >= occupied_thresh, an
///         unknown mode, or an image that cannot be decoded (then `file` is the image).
[[nodiscard]] RosMap load_ros_map(const std::string& yaml_path);

/// \brief Saves cells as PREFIX.yaml + PREFIX.pgm (binary P5) the way map_saver does: trinary
/// mode, occupied_thresh 0.65, free_thresh 0.196; cells >= 65 are written black (0), cells in
/// 0..25 white (254), everything else grey (205). load_ros_map() reads a grid of -1/0/100 cells
/// back identically, frame included (resolution, origin and yaw are written exactly).
/// \throws IoError when a file cannot be written.
void save_ros_map(const std::string& prefix, const Grid<std::int8_t, 2>& cells);

/// \brief The occupancy grid the distance transforms take: 1 where cell >= kRosOccupiedThreshold
/// (65), else 0. Unknown cells (-1) count as *not* occupied, so walls come only from what the map
/// saw; the frame is the map's.
[[nodiscard]] OccupancyGrid<2> occupancy(const RosMap& map);

/// \brief As occupancy(const RosMap&), for a bare grid of ROS cell values.
[[nodiscard]] OccupancyGrid<2> occupancy(const Grid<std::int8_t, 2>& cells);

}  // namespace vdtnav
