#pragma once
/// \file
/// \brief The simulated Dataset 4 (thesis 3.4.4.2): a LIDAR-Lite v3-like single-beam laser on a
/// pan-tilt unit, swept while the robot stands still, rolled and pitched as on an uneven floor,
/// ray cast in a 3D occupancy grid.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/pose3.hpp"
#include "vdtnav/map/grid.hpp"
#include "vdtnav/sensor/pan_tilt_unit.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace vdtnav::sim {

/// \brief The pan/tilt angles a sweep visits: a raster, pan outer, tilt inner.
///
/// Pan angle i = pan_min + i (pan_max - pan_min) / pan_steps for i in [0, pan_steps): the span is
/// cut into pan_steps equal sectors, so a full turn visits no angle twice. Tilt angle j =
/// tilt_min + j (tilt_max - tilt_min) / (tilt_steps - 1) for j in [0, tilt_steps): both ends
/// (tilt_min alone when tilt_steps = 1). Positive tilt looks down (pan_tilt_unit.hpp). The
/// default, 100 pans over 360 deg x 57 tilts from 0.5 rad up to 0.8 rad down, gives the 5700
/// readings per location of 3.4.4.2 and sees the floor, the walls and the ceiling. 57 is coprime
/// to the thesis's downsampling factors 2, 5, 10 and 100, so keeping every k-th reading still
/// visits every tilt (with 50 tilts, every 100th reading would look along one cone).
struct PanTiltPattern {
  double pan_min = -3.14159265358979323846;  ///< radians
  double pan_max = 3.14159265358979323846;   ///< radians (excluded)
  int pan_steps = 100;
  double tilt_min = -0.5;  ///< radians (up)
  double tilt_max = 0.8;   ///< radians (down, included)
  int tilt_steps = 57;
  /// Explicit (pan, tilt) pairs; when non-empty, used instead of the raster.
  std::vector<Eigen::Vector2d> angles;

  /// \return the number of readings of a sweep.
  [[nodiscard]] std::size_t size() const;
  /// \return the (pan, tilt) of every reading, in sweep order. \throws ConfigError when invalid.
  [[nodiscard]] std::vector<Eigen::Vector2d> pan_tilt_angles() const;
};

/// \brief The simulated sensor: unit geometry, sweep, range limits and noise.
struct PointLaserSimOptions {
  PanTiltCalibration calibration = PanTiltCalibration::turtlebot_example();
  PanTiltPattern pattern;
  PointLaserSpec spec;  ///< LIDAR-Lite v3: 0.05-40 m, sigma 0.025 m
  /// Add N(0, spec.sigma_range^2) to every range. One standard normal is drawn per reading either
  /// way, so a noisy and a noise-free sweep with the same seed differ by exactly sigma * z.
  bool noisy = true;
  double reading_period = 0.002;  ///< seconds between readings (time stamps; 500 Hz)
  /// Where beams stop: by default the cell-centre surface, where the VDT of the same grid is zero,
  /// so that the map and the simulated world agree (ray_casting.hpp).
  RaySurface surface = RaySurface::kCellCentre;
};

/// \brief One sweep taken with the robot at rest.
struct PointLaserSweep {
  Pose3 truth = Pose3::Identity();       ///< true robot pose in the map frame
  std::vector<PanTiltReading> readings;  ///< in PanTiltPattern order; no return reads +inf
  double sigma_range = 0.0;              ///< the sensor's range sigma (spec.sigma_range)
};

/// \brief Simulates one sweep from `robot_pose` in `map`.
///
/// Reading k = (pan_k, tilt_k) leaves the laser frame pan_tilt_laser_pose(calibration, pan,
/// tilt) composed with robot_pose along its +x, and reads the exact distance to the first occupied
/// cell's surface (cast_ray<3> with options.surface) plus spec.sigma_range * z_k (when noisy),
/// clamped at 0. Beams that hit nothing before spec.range_max, or leave the grid, read +inf.
/// time_k = k * reading_period. Noise comes from std::mt19937_64 seeded with (seed, tag); the same
/// seed gives the same sweep. \throws ConfigError for invalid options or a non-finite pose.
[[nodiscard]] PointLaserSweep simulate_point_laser_sweep(const OccupancyGrid<3>& map,
                                                         const Pose3& robot_pose,
                                                         const PointLaserSimOptions& options,
                                                         std::uint32_t seed);

/// \brief One sweep per pose (the 3 locations of 3.4.4.2); sweep k is simulate_point_laser_sweep
/// with the k-th seed a std::seed_seq built from `seed` generates (independent noise streams).
[[nodiscard]] std::vector<PointLaserSweep> simulate_point_laser_sweeps(
    const OccupancyGrid<3>& map, const std::vector<Pose3>& robot_poses,
    const PointLaserSimOptions& options, std::uint32_t seed);

}  // namespace vdtnav::sim
