#pragma once
/// \file
/// \brief Occupancy grid mapping with known poses (Thrun, Burgard, Fox, "Probabilistic
/// Robotics", 2005, Table 9.1): log-odds updates along every beam of 2D laser scans, the free
/// cells found by exact grid traversal (Amanatides & Woo 1987).
///
/// Per beam from the sensor origin o to the endpoint p (world frame):
///  - a return (range_min <= r < range_max): every cell the segment o -> p passes through gets
///    l_free, except the cell of p, which gets l_occ;
///  - no return (finite r >= range_max): the cells of the segment from o along the beam up to
///    min(clearing_length, r) get l_free, and no cell gets l_occ (nothing was seen; Cartographer's
///    `missing_data_ray_length` does the same);
///  - NaN, +-inf and r < range_min: dropped.
/// A ray does not clear the cells its own surface runs through: the surface's line is estimated
/// from the endpoints of the neighbouring beams (2 to 20 cells away), and the cells whose centres
/// lie within half a cell of it keep no miss from this ray. Without this, a ray that meets a wall
/// at a grazing angle crosses the wall's cells for 0.5 res / tan(angle) before it reaches the
/// wall (where the thin-wall world of the simulator and the VDT put it: through the occupied
/// cells' centres), and erases the wall behind the scans that saw it head on (measured on the
/// generated floor plan with noise-free scans: IoU of occupied cells 0.835 without, 0.93 with;
/// see tests/mapping).
/// Within one scan a cell is updated at most once, and a hit wins over a miss (as OctoMap's
/// computeUpdate does): otherwise the many beams that pass next to a wall cell at grazing angles
/// would erase the one that ends in it, and the cells around the sensor would be counted once per
/// beam. Log-odds are clamped to [l_min, l_max] after every update (OctoMap's clamping), so that
/// the map can still change when the world does.

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/map/grid.hpp"
#include "vdtnav/sensor/laser_scan.hpp"

namespace vdtnav::mapping {

/// \brief Parameters of the occupancy mapper (defaults: 5 cm cells, OctoMap's sensor model).
struct OccupancyMapperOptions {
  double resolution = 0.05;  ///< metres per cell
  /// Metres of grid added on every side of the box around the sensor origins and the beam
  /// segments (build_occupancy_map only).
  double margin = 1.0;
  /// Snap the grid origin to a multiple of the resolution, so that maps of the same world at
  /// the same resolution share their cell boundaries (build_occupancy_map only).
  bool align_origin = true;
  double l_occ = 0.85;    ///< log-odds of a hit: log(0.7 / 0.3), OctoMap's prob_hit 0.7
  double l_free = -0.41;  ///< log-odds of a miss: log(0.4 / 0.6), OctoMap's prob_miss 0.4
  double l_min = -2.0;    ///< clamping lower bound: p = 0.12 (OctoMap's clamping_thres_min)
  double l_max = 3.5;     ///< clamping upper bound: p = 0.97 (OctoMap's clamping_thres_max)
  /// Metres along a no-return beam (finite reading >= range_max) that are cleared; 0 disables.
  double clearing_length = 5.0;
  /// Do not clear, along a ray, the cells the surface it hit runs through (see the file comment).
  bool keep_surface_cells = true;
  /// Cells with an occupancy probability >= this are occupied (ROS 100).
  double occupied_threshold = 0.65;
  /// Cells with an occupancy probability <= this are free (ROS 0); between the two, and where no
  /// beam went, unknown (ROS -1). The defaults are map_server's occupied_thresh / free_thresh.
  double free_threshold = 0.196;

  /// \throws ConfigError unless resolution > 0, margin >= 0, l_occ > 0 > l_free,
  /// l_min < 0 < l_max, clearing_length >= 0 and 0 < free_threshold < occupied_threshold < 1,
  /// all finite.
  void validate() const;
};

/// \brief Counts of what the mapper did with the readings it was given.
struct MappingStats {
  std::size_t scans = 0;
  std::size_t hits = 0;                ///< returns: free ray + occupied endpoint
  std::size_t no_returns = 0;          ///< finite readings >= range_max: free ray only
  std::size_t dropped_not_finite = 0;  ///< NaN and +-inf
  std::size_t dropped_too_short = 0;   ///< readings < range_min
  /// Returns whose endpoint lies outside the grid (OccupancyMapper with a fixed grid only): the
  /// part of the ray inside the grid is still cleared.
  std::size_t endpoints_outside = 0;
};

/// \brief Log-odds occupancy mapping into a fixed grid (integrate scans one by one).
class OccupancyMapper {
 public:
  /// \param frame, size the grid to map into (axis aligned or rotated).
  /// \throws ConfigError for invalid options or size.
  OccupancyMapper(const GridFrame<2>& frame, const Eigen::Vector2i& size,
                  const OccupancyMapperOptions& options = {});

  /// \brief Integrates a scan taken with the robot at `pose` (the scan's mount is applied).
  /// Cells outside the grid are ignored.
  /// \throws ConfigError when the pose is not finite.
  void insert(const Pose2& pose, const LaserScan& scan);

  /// \return the log-odds of every cell (0 = never observed, or evidence cancelled out).
  [[nodiscard]] const Grid<float, 2>& log_odds() const noexcept { return log_odds_; }
  /// \return how many scans updated each cell (0 = never observed).
  [[nodiscard]] const Grid<std::uint32_t, 2>& observations() const noexcept {
    return observations_;
  }
  /// \return ROS cell values: 100 where p >= occupied_threshold, 0 where p <= free_threshold,
  /// -1 in between and where no scan reached (ready for save_ros_map).
  [[nodiscard]] Grid<std::int8_t, 2> ros_cells() const;
  /// \return 1 where the cell is occupied (ROS 100), else 0: the input of VdtMap2::build.
  [[nodiscard]] OccupancyGrid<2> occupancy() const;
  [[nodiscard]] const MappingStats& stats() const noexcept { return stats_; }
  [[nodiscard]] const OccupancyMapperOptions& options() const noexcept { return options_; }

 private:
  void update(std::ptrdiff_t linear, float delta);

  OccupancyMapperOptions options_;
  Grid<float, 2> log_odds_;
  Grid<std::uint32_t, 2> observations_;
  MappingStats stats_;
  // Per-scan scratch: the update each touched cell gets (0 = none yet), and the touched cells.
  std::vector<float> pending_;
  std::vector<std::ptrdiff_t> touched_;
};

/// \brief An occupancy map built from a whole run.
struct OccupancyMap {
  Grid<float, 2> log_odds;              ///< see OccupancyMapper::log_odds
  Grid<std::uint32_t, 2> observations;  ///< see OccupancyMapper::observations
  Grid<std::int8_t, 2> cells;           ///< ROS values -1 / 0 / 100 (save_ros_map)
  OccupancyGrid<2> occupancy;           ///< 1 = occupied (VdtMap2::build)
  MappingStats stats;
};

/// \brief The grid (frame and size) that holds every sensor origin of `poses` and every beam
/// segment of `scans` as the mapper integrates it (returns to the endpoint, no-returns up to
/// the clearing length), grown by options.margin on every side; axis aligned, with the origin
/// snapped to a multiple of the resolution when options.align_origin.
/// \throws ConfigError for invalid options, poses and scans of different counts, a non-finite
/// pose, or a grid of more than 2^31 cells.
[[nodiscard]] std::pair<GridFrame<2>, Eigen::Vector2i> map_extent(
    const std::vector<Pose2>& poses, const std::vector<LaserScan>& scans,
    const OccupancyMapperOptions& options = {});

/// \brief Maps a run: scans[k] taken with the robot at poses[k], into the grid of map_extent().
/// \throws ConfigError as map_extent().
[[nodiscard]] OccupancyMap build_occupancy_map(const std::vector<Pose2>& poses,
                                               const std::vector<LaserScan>& scans,
                                               const OccupancyMapperOptions& options = {});

}  // namespace vdtnav::mapping
