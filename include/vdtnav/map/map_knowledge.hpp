#pragma once
/// \file
/// \brief What a map knows: the cells its builder observed (free or occupied) against the unknown
/// rest (ROS map_server's -1: never seen, or beyond the map).
///
/// A scan that ends where the map knows nothing says nothing about the pose (the map lacks the
/// place); one that ends in known free space, or whose beam crosses a known wall, contradicts it
/// (estimation/scan_agreement.hpp). A VDT map alone cannot tell the two apart: its distance field
/// is defined everywhere.

#include <cstdint>

#include <Eigen/Core>

#include "vdtnav/map/grid.hpp"

namespace vdtnav {

/// \brief Known and unknown cells of a 2D map, looked up at world points on the map's own grid.
class MapKnowledge {
 public:
  /// \brief Every point of the VDT map is known (a floor plan, a map without unknown cells);
  /// what lies outside the VDT map is unknown (see known_inside_map()).
  MapKnowledge() = default;

  /// \brief From ROS cell values (negative: unknown, 0..100: known), on their own grid, which
  /// need not be the VDT map's: points outside it are unknown.
  explicit MapKnowledge(const Grid<std::int8_t, 2>& cells);

  /// \return whether the map knows what is at world point p (outside the grid: no). Without a
  /// grid (the default), true: the caller decides by the VDT map's extent.
  [[nodiscard]] bool known(const Eigen::Vector2d& p) const {
    if (!has_grid_) return true;
    const Eigen::Vector2i c = known_.cell_of(p);
    return known_.contains(c) && known_(c) != 0;
  }

  /// \return false when constructed without cells: every point inside the VDT map is known.
  [[nodiscard]] bool has_unknown() const noexcept { return has_grid_; }

  /// \return the share of the grid's cells that are known (1 without a grid).
  [[nodiscard]] double known_fraction() const noexcept { return known_fraction_; }

 private:
  bool has_grid_ = false;
  Grid<std::uint8_t, 2> known_;  ///< 1 known, 0 unknown
  double known_fraction_ = 1.0;
};

}  // namespace vdtnav
