#pragma once
/// \file
/// \brief The PMD's drive through a ParkScene: laps of the paved loop at 1-2 m/s with a detour
/// over the plaza, frames at a fixed rate, the true poses and the wheel odometry (increments in
/// the previous robot frame with noise proportional to the motion).

#include <cstdint>
#include <vector>

#include "vdtnav/camera_sim/park_scene.hpp"
#include "vdtnav/core/pose2.hpp"
#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/estimation/motion_model.hpp"

namespace vdtnav::rgbd_ground {

/// \brief Options of the drive.
struct ScooterDriveOptions {
  std::uint64_t seed = 1;
  double length = 500.0;                     ///< metres
  double frame_rate = 5.0;                   ///< Hz
  double min_speed = 1.0, max_speed = 2.0;   ///< m/s
  double odometry_sigma_per_m = 0.03;        ///< of the distance, per axis
  double odometry_sigma_yaw_per_rad = 0.03;  ///< of the turn
  double odometry_sigma_yaw_per_m = 0.004;   ///< rad per metre (wheel slip, uneven ground)
};

/// \brief The drive.
struct ScooterDrive {
  std::vector<double> time;
  std::vector<Pose2> truth;
  std::vector<OdometryStep> odometry;  ///< odometry[k]: from frame k-1 to k (odometry[0] empty)
};

[[nodiscard]] ScooterDrive simulate_scooter_drive(const ParkScene& scene,
                                                  const ScooterDriveOptions& options = {});

/// \brief The odometry-increment noise of the drive's odometry (for the filters' prediction).
[[nodiscard]] MotionNoise drive_odometry_noise(const ScooterDriveOptions& options);

}  // namespace vdtnav::rgbd_ground
