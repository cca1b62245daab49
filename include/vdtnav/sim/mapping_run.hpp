#pragma once
/// \file
/// \brief Simulated map-building runs (thesis 5.3): scans ray cast from the true poses with range
/// noise, the poses a map builder would report (the truth plus pose noise, with its covariance),
/// and the true boundary as the sensor sees it; and Experiment 1's L-shaped room.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/map/grid.hpp"
#include "vdtnav/mapping/map_scan.hpp"
#include "vdtnav/sim/lidar_simulator.hpp"
#include "vdtnav/sim/trajectory.hpp"

namespace vdtnav::sim {

/// \brief Noise of a map-building run (zero-mean Gaussian, standard deviations).
struct MappingNoise {
  double sigma_xy = 0.0;     ///< of each pose estimate's x and y, metres
  double sigma_phi = 0.0;    ///< of each pose estimate's heading, radians
  double sigma_range = 0.0;  ///< of every range, metres

  /// \brief Table 5.1 (Experiment 1): 0.01 m, 0.005 rad, 0.02 m.
  [[nodiscard]] static MappingNoise table_5_1() { return {0.01, 0.005, 0.02}; }
  /// \brief Table 5.2 (Experiment 2): 0.05 m, 0.005 rad, 0.02 m.
  [[nodiscard]] static MappingNoise table_5_2() { return {0.05, 0.005, 0.02}; }
};

/// \brief A simulated map-building run.
struct MappingRun {
  std::vector<Pose2> truth;             ///< true pose of every scan
  std::vector<mapping::MapScan> scans;  ///< estimated poses, their covariance, noisy readings
  /// Where the readings would end without range noise, from the true poses (world frame): the
  /// part of the world's boundary the run observed.
  std::vector<Eigen::Vector2d> true_boundary;
};

/// \brief Scans from `truth` in `world` (thin walls through the occupied cells' centres, where
/// the world's VDT is zero): each beam of `lidar` reads the exact range plus N(0, sigma_range^2)
/// (beams that hit nothing within range are dropped); each scan's pose is reported as the truth
/// plus N(0, diag(sigma_xy^2, sigma_xy^2, sigma_phi^2)), with that covariance (zero sigmas: exact
/// poses). The scans declare noise.sigma_range, or lidar.sigma_range when it is 0 (exact ranges
/// still need a weight). Range and pose noise come from separate streams of `seed`.
/// \throws ConfigError for invalid options or no pose.
[[nodiscard]] MappingRun simulate_mapping_run(const OccupancyGrid<2>& world,
                                              const std::vector<Pose2>& truth,
                                              const LidarOptions& lidar, const MappingNoise& noise,
                                              std::uint32_t seed);

/// \brief A world and the poses a map-building run takes in it.
struct MappingScene {
  std::string name;
  OccupancyGrid<2> world;
  std::vector<Pose2> poses;
  std::vector<Eigen::Vector2d> path;  ///< the route driven (empty: poses placed by hand)
};

/// \brief The drive along scene.path (sim::follow_path at 10 Hz, the path driven once).
[[nodiscard]] std::vector<TimedPose> mapping_drive(const MappingScene& scene);

/// \brief A scene whose scans are the key frames a map builder keeps along `path` in `world`: one
/// scan every 0.5 m or 0.3 rad of mapping_drive().
[[nodiscard]] MappingScene scene_along(std::string name, OccupancyGrid<2> world,
                                       std::vector<Eigen::Vector2d> path);

/// \brief Experiment 2's embedded default (thesis 5.3.2 in a corridor of our own): the main
/// corridor of the generated floor plan (FloorPlanOptions with `seed`), driven end to end.
[[nodiscard]] MappingScene generated_corridor(std::uint32_t seed);

/// \brief Experiment 1 (Fig. 5.1): an L-shaped room, 6 m x 6 m with the 3 m x 3 m corner at
/// (3..6, 3..6) cut away, walls one cell thick at `resolution`, observed from three poses.
[[nodiscard]] MappingScene l_shaped_room(double resolution = 0.01);

}  // namespace vdtnav::sim
