#pragma once
/// \file
/// \brief A seeded, procedurally generated building floor plan: the embedded default map that
/// vdtnav's studies run on when no real data is given (SPEC, Data).
///
/// A rectangular building with outer walls, a main corridor along x, a cross corridor along y,
/// rooms on both sides of the main corridor (each with a door onto it, some with doors to their
/// neighbour), furniture-like clutter in the rooms and pillars along the corridor. The same seed
/// always gives the same plan.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/map/grid.hpp"

namespace vdtnav::sim {

/// \brief Parameters of the generated floor plan.
struct FloorPlanOptions {
  double width = 40.0;           ///< metres along x (the hospital section is 40 m x 18 m)
  double height = 18.0;          ///< metres along y
  double resolution = 0.05;      ///< metres per cell
  double wall_thickness = 0.15;  ///< metres
  double corridor_width = 2.2;   ///< metres
  double min_room_width = 3.5;   ///< metres
  double max_room_width = 7.0;   ///< metres
  double door_width = 1.0;       ///< metres
  int clutter_per_room = 3;      ///< furniture items per room (at most)
  std::uint32_t seed = 1;
};

/// \brief A room of the plan, its door onto the corridor and a free point in its middle.
struct Room {
  Eigen::Vector2d min_corner;
  Eigen::Vector2d max_corner;
  Eigen::Vector2d door;    ///< centre of the door gap in the corridor wall
  Eigen::Vector2d centre;  ///< kept free of clutter
};

/// \brief The generated plan.
struct FloorPlan {
  OccupancyGrid<2> occupancy;  ///< 1 = wall or clutter; origin at (0, 0)
  std::vector<Room> rooms;
  double corridor_y = 0.0;  ///< centreline of the main corridor
  double cross_corridor_x = 0.0;
  /// A closed tour through free space: along the corridor, into and out of several rooms.
  std::vector<Eigen::Vector2d> tour;
};

/// \brief Generates the plan. \throws ConfigError for sizes the layout cannot hold.
[[nodiscard]] FloorPlan generate_floor_plan(const FloorPlanOptions& options = {});

}  // namespace vdtnav::sim
