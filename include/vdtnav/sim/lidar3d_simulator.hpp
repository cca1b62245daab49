#pragma once
/// \file
/// \brief A simulated multi-ring 3D LiDAR (a Velodyne VLP-16 by default) ray cast in a 3D
/// occupancy map: what the 3D localizers are tested and studied on when no real 3D log is at hand.
///
/// The sensor spins about its z axis: ring k points at elevation e_k (evenly spread over
/// [min_elevation, max_elevation]), firing every azimuth_step over the full turn. A ray from the
/// sensor's origin along u(a, e) = (cos e cos a, cos e sin a, sin e) (sensor frame) stops at the
/// surface of the first occupied voxel it meets (RaySurface::kCellCentre: where the VDT of the same
/// grid is zero); the range gets N(0, sigma_range^2) noise. Rays with no return within range_max
/// give NaN points, as drivers write them into organized clouds. simulate_lidar3d_scan takes the
/// whole turn at one pose; simulate_lidar3d_sweep moves the sensor during it (motion distortion,
/// what deskewing undoes: sensor/sweep_motion.hpp).

#include <cstddef>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/pose3.hpp"
#include "vdtnav/map/grid.hpp"
#include "vdtnav/sensor/observation_set.hpp"
#include "vdtnav/sensor/sweep_motion.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace vdtnav::sim {

/// \brief The sensor's geometry and noise; the defaults are the VLP-16's data sheet.
struct Lidar3dSpec {
  int rings = 16;
  double min_elevation = -15.0 * 3.14159265358979323846 / 180.0;  ///< radians
  double max_elevation = 15.0 * 3.14159265358979323846 / 180.0;   ///< radians
  double azimuth_step = 0.2 * 3.14159265358979323846 / 180.0;     ///< radians (10 Hz: 0.2 deg)
  double rate_hz = 10.0;      ///< turns per second (the scans' spacing in time)
  double sigma_range = 0.03;  ///< metres (+-3 cm typical)
  double range_min = 0.5;     ///< metres: closer returns are dropped by the sensor (NaN)
  double range_max = 100.0;   ///< metres
  RaySurface surface = RaySurface::kCellCentre;

  /// \return rays per ring: one per azimuth_step over 2 pi (1800 for the VLP-16 at 10 Hz).
  [[nodiscard]] int rays_per_ring() const;
};

/// \brief One turn: rings x rays_per_ring points in the sensor frame, ring-major (point
/// k * rays_per_ring + j is ring k, azimuth j * azimuth_step); NaN where nothing returned.
struct Lidar3dScan {
  std::vector<Eigen::Vector3d> points;
  /// Seconds after the stamp at which each point was taken (simulate_lidar3d_sweep); empty: the
  /// turn was taken at one pose.
  std::vector<double> times;
  std::size_t returns = 0;  ///< finite points
};

/// \brief Ray casts one turn from `sensor_in_world` in `map` with `rng`'s range noise.
/// \throws ConfigError for a spec out of its domain.
[[nodiscard]] Lidar3dScan simulate_lidar3d_scan(const OccupancyGrid<3>& map,
                                                const Pose3& sensor_in_world,
                                                const Lidar3dSpec& spec, std::mt19937& rng);

/// \brief One turn from a moving sensor: the rays of azimuth column j fire
/// τ_j = j / (rays_per_ring · rate_hz) seconds after the stamp from
/// sensor_at_stamp · motion.at(τ_j) (sweep_motion.hpp (1)); each point is in the sensor's frame at
/// its own time, as a driver writes it, with `times` set.
/// \throws ConfigError for a spec out of its domain.
[[nodiscard]] Lidar3dScan simulate_lidar3d_sweep(const OccupancyGrid<3>& map,
                                                 const Pose3& sensor_at_stamp,
                                                 const SweepMotion& motion, const Lidar3dSpec& spec,
                                                 std::mt19937& rng);

/// \brief The scan's returns as observations in the sensor's frame (beams from its origin, the
/// spec's range noise), `beam` the ray index; the no-return rays left out. What the tests and
/// benchmarks feed the 3D localizers (with each reading's time when the scan has them); a program
/// reading real clouds goes through
/// observations_from_cloud (vdtnav::pcl) instead.
[[nodiscard]] ObservationSet3 lidar3d_observations(const Lidar3dScan& scan,
                                                   const Lidar3dSpec& spec);

}  // namespace vdtnav::sim
