#pragma once
/// \file
/// \brief A tour through the free space of a 2D occupancy map for the simulated robot to drive
/// (the route of the simulated Dataset 1, thesis 3.4.1, on any map).

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/map/grid.hpp"

namespace vdtnav::sim {

/// \brief Plans a tour that visits far-apart places of the map's largest free region.
///
/// Traversable cells are the free cells whose UDT (distance to the nearest occupied cell centre)
/// is at least `clearance`; the tour stays in the largest 8-connected region of them. Waypoints
/// are picked by randomised geodesic farthest-point sampling (the first at random, each next one
/// at random among the cells at >= 80 % of the largest geodesic distance to those picked so far),
/// each moved up the UDT (at most 1 m) away from walls, then ordered by nearest neighbour from
/// the first. Consecutive waypoints are joined by A* over the 8-connected traversable cells
/// (no corner cutting), with step costs raised near obstacles so that the route keeps to the
/// middle of corridors and doors; each leg is smoothed by a moving average (where that keeps the
/// clearance).
/// \param map occupancy, non-zero = occupied.
/// \param waypoints number of places to visit (>= 2); fewer are used if the region is too small.
/// \param clearance metres every path point keeps from obstacles (UDT at its cell).
/// \param seed the same seed always gives the same tour.
/// \return a dense open polyline (points one to two cells apart) from the first waypoint to the
///         last.
/// \throws ConfigError if waypoints < 2, clearance is negative, or no two free cells with the
///         clearance are connected.
[[nodiscard]] std::vector<Eigen::Vector2d> plan_tour(const OccupancyGrid<2>& map, int waypoints,
                                                     double clearance, std::uint32_t seed);

}  // namespace vdtnav::sim
