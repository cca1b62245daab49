#pragma once
// Simulated 3D runs with an IMU for the command-line tests (test_cli_3d: scans as PCD files and
// an IMU CSV; test_cli_bags: the same in a ROS bag): the generated room as the map a user has,
// trajectories with their derivatives, and the IMU a BMI088 would give along them.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <vector>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/core/pose3.hpp"
#include "vdtnav/sensor/imu.hpp"
#include "vdtnav/sim/imu_simulator.hpp"
#include "vdtnav/sim/room3d.hpp"

namespace vdtnav::test {

/// The generated room at 0.1 m, its voxels moved by half a voxel so that their centres sit
/// mid-voxel on the lattice map3d voxelizes on (multiples of the resolution): the map rebuilt
/// from the centres, written to `map_csv` (x,y,z), is the world returned, which scans are cast in.
inline OccupancyGrid<3> write_room_map(const std::filesystem::path& map_csv) {
  sim::Room3dOptions ro;
  ro.resolution = 0.1;
  ro.wall_thickness = 0.2;
  const sim::Room3d room = sim::generate_room3d(ro);
  const Eigen::Vector3i n = room.occupancy.size();
  OccupancyGrid<3> world(
      n, GridFrame<3>(0.1, room.occupancy.frame().origin() - Eigen::Vector3d::Constant(0.05)), 0);
  std::ofstream map(map_csv);
  map << "x,y,z\n";
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i)
        if (room.occupancy(Eigen::Vector3i(i, j, k)) != 0) {
          world(Eigen::Vector3i(i, j, k)) = 1;
          const Eigen::Vector3d c = world.frame().cell_center(Eigen::Vector3i(i, j, k));
          map << c.x() << "," << c.y() << "," << c.z() << "\n";
        }
  return world;
}

/// A slalom from standstill on a circle of 1.5 m about (4, 5) in the room, 1.2 m up, level,
/// facing along it: theta(t) = 0.6 (1 - cos pi t) + 0.15 t^2, the turn rate swinging between
/// -1.4 and 2.6 rad/s.
inline sim::MotionState3 slalom(double t) {
  const double th = 0.6 * (1.0 - std::cos(kPi * t)) + 0.15 * t * t, r = 1.5;
  const double w = 0.6 * kPi * std::sin(kPi * t) + 0.3 * t;     // theta'
  const double dw = 0.6 * kPi * kPi * std::cos(kPi * t) + 0.3;  // theta''
  sim::MotionState3 m;
  m.pose = pose3_from_xyz_rpy(4.0 + r * std::cos(th), 5.0 + r * std::sin(th), 1.2, 0.0, 0.0,
                              th + kPi / 2);
  m.velocity = r * w * Eigen::Vector3d(-std::sin(th), std::cos(th), 0.0);
  m.acceleration = r * dw * Eigen::Vector3d(-std::sin(th), std::cos(th), 0.0) -
                   r * w * w * Eigen::Vector3d(std::cos(th), std::sin(th), 0.0);
  m.body_rates = Eigen::Vector3d(0.0, 0.0, w);
  return m;
}

/// A robot creeping at 0.3 m/s along x on a slope: rolled 2 degrees, pitched -1.5 (constant).
inline sim::MotionState3 creep(double t) {
  sim::MotionState3 m;
  m.pose = pose3_from_xyz_rpy(3.0 + 0.3 * t, 4.0, 1.2, 2.0 * kPi / 180, -1.5 * kPi / 180, 0.2);
  m.velocity = Eigen::Vector3d(0.3, 0.0, 0.0);
  return m;
}

/// The IMU along `trajectory` (its time 0 at stamp t0) over [t0 - 0.5, t0 + 4.1] s at 200 Hz,
/// with the BMI088's noise (the settings' defaults) and biases within the settings' sigmas.
inline std::vector<ImuSample> imu_along(sim::MotionState3 (*trajectory)(double), double t0,
                                        std::mt19937& rng) {
  sim::ImuSimulation is;
  const ImuNoise noise;
  is.gyro_noise_density = noise.gyro_noise_density;
  is.accel_noise_density = noise.accel_noise_density;
  is.gyro_bias = Eigen::Vector3d(0.5e-3, -0.5e-3, 0.8e-3);
  is.accel_bias = Eigen::Vector3d(0.01, -0.015, 0.01);
  return sim::simulate_imu([trajectory, t0](double t) { return trajectory(t - t0); }, t0 - 0.5,
                           t0 + 4.1, is, rng);
}

}  // namespace vdtnav::test
