#pragma once
/// \file
/// \brief A simulated IMU on a smooth 3D trajectory: the ideal readings (gyro = the body angular
/// velocity, accelerometer = the specific force R^T (a_w - g_w), g_w = (0, 0, -gravity)), with
/// optional white noise and a constant bias — what the IMU's preintegration and attitude are
/// tested against (sensor/imu.hpp).

#include <functional>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/pose3.hpp"
#include "vdtnav/sensor/imu.hpp"

namespace vdtnav::sim {

/// \brief A trajectory's state at one time, with its derivatives.
struct MotionState3 {
  Pose3 pose = Pose3::Identity();                          ///< body in the world, z up
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();      ///< m/s, world frame
  Eigen::Vector3d acceleration = Eigen::Vector3d::Zero();  ///< m/s^2, world frame
  Eigen::Vector3d body_rates = Eigen::Vector3d::Zero();    ///< ω, rad/s, body frame
};

/// \brief A circle flown at constant speed, facing along it, while the height and the roll and
/// pitch oscillate (a drone in gusts, or a robot on rough ground): every derivative in closed form.
/// Position (r cos Ωt, r sin Ωt, z0 + A_z sin 2π f_z t), Ω = speed / r; attitude
/// R = Rz(Ωt + π/2) Ry(A_p sin 2π f_p t) Rx(A_r sin 2π f_r t); body rates ω = E(roll, pitch)
/// (roll', pitch', yaw'), E = [1, 0, -sin p; 0, cos r, sin r cos p; 0, -sin r, cos r cos p].
struct WavyCircle {
  double radius = 5.0;            ///< m
  double speed = 1.5;             ///< m/s
  double height = 1.0;            ///< z0, m
  double height_amplitude = 0.2;  ///< A_z, m
  double height_frequency = 0.4;  ///< f_z, Hz
  double roll_amplitude = 0.15;   ///< A_r, rad
  double roll_frequency = 0.7;    ///< f_r, Hz
  double pitch_amplitude = 0.1;   ///< A_p, rad
  double pitch_frequency = 0.45;  ///< f_p, Hz

  /// \return the state at time t (seconds).
  [[nodiscard]] MotionState3 at(double t) const;
};

/// \brief The simulated sensor.
struct ImuSimulation {
  double rate_hz = 200.0;                                ///< samples per second
  double gyro_noise_density = 0.0;                       ///< rad/s/√Hz; 0: noise-free
  double accel_noise_density = 0.0;                      ///< m/s^2/√Hz; 0: noise-free
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();   ///< rad/s, added to every reading
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();  ///< m/s^2, added to every reading
  double gravity = 9.80665;                              ///< m/s^2
};

/// \brief The readings at t_start + k / rate_hz, k = 0, 1, ... up to t_end (included when on the
/// grid): ω + gyro_bias + n_g, R^T (a - g_w) + accel_bias + n_a, with n white, σ = density
/// sqrt(rate_hz) per axis (the discrete noise of a sensor averaging over its period), drawn from
/// `rng` (not used when both densities are 0).
/// \throws ConfigError unless t_start <= t_end, rate_hz > 0 and the densities are >= 0.
[[nodiscard]] std::vector<ImuSample> simulate_imu(
    const std::function<MotionState3(double)>& trajectory, double t_start, double t_end,
    const ImuSimulation& options, std::mt19937& rng);

}  // namespace vdtnav::sim
