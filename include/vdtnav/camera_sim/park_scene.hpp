#pragma once
/// \file
/// \brief A generated park for the personal mobility device study (thesis 3.4.5, Dataset 5: the
/// paths of Wentworth Park, Sydney): grass crossed by a paved loop and gravel paths meeting at a
/// gravel plaza, benches, bins and people standing on the ground, and lamp posts that serve as
/// the landmarks of the bearing observations. The VDT map is built from the boundaries between
/// the surfaces.

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/map/grid.hpp"

namespace vdtnav::rgbd_ground {

enum class Surface : std::uint8_t { kGrass, kPavement, kGravel };

/// \brief Something standing on the ground: a vertical cylinder (radius > 0) or an axis-aligned
/// box (half_size), `height` metres tall, of one colour (BGR).
struct ParkObstacle {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0.0;
  Eigen::Vector2d half_size = Eigen::Vector2d::Zero();
  double height = 1.0;
  Eigen::Vector3d colour = Eigen::Vector3d(60, 60, 60);
};

/// \brief Options of the generated park (defaults: ~2000 m^2, like Wentworth Park's lawns).
struct ParkSceneOptions {
  std::uint64_t seed = 1;
  double width = 52.0, depth = 40.0;  ///< metres
  double path_width = 2.4;            ///< metres, of the paved loop and the gravel paths
  double plaza_radius = 5.0;          ///< metres
  int people = 8;                     ///< standing on the paths
  int benches = 10;                   ///< beside the paths
};

/// \brief The park.
struct ParkScene {
  ParkSceneOptions options;
  std::vector<Eigen::Vector2d> loop;  ///< centre line of the paved loop (closed polyline)
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> gravel_paths;  ///< centre segments
  Eigen::Vector2d plaza = Eigen::Vector2d::Zero();
  std::vector<ParkObstacle> obstacles;      ///< benches, bins, people and the lamp posts
  std::vector<Eigen::Vector2d> lamp_posts;  ///< the landmarks
  [[nodiscard]] Surface surface_at(const Eigen::Vector2d& p) const;
  /// \brief The boundaries between surfaces as occupied cells of a grid covering the park.
  [[nodiscard]] OccupancyGrid<2> boundary_map(double resolution) const;
};

/// \brief Generates the park (deterministic for a seed).
[[nodiscard]] ParkScene generate_park(const ParkSceneOptions& options = {});

}  // namespace vdtnav::rgbd_ground
