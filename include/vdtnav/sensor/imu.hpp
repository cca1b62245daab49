#pragma once
/// \file
/// \brief An IMU between two scans: its samples preintegrated into the motion increment and its
/// covariance (Forster, Carlone, Dellaert, Scaramuzza, "On-Manifold Preintegration for Real-Time
/// Visual-Inertial Odometry", IEEE T-RO 33(1), 2017, Sec. V, cited by name: [F: preintegrated
/// measurements], [F: noise propagation], [F: bias update]), the pose predicted
/// from it, and roll and pitch observed from gravity (the 4-DOF mode's held attitude).
///
/// Frames and units. The body frame is the robot's (REP-103: x forward, y left, z up; the IMU is
/// taken to be mounted at the body origin, axes aligned); the world (map) frame has z up and
/// gravity g_w = (0, 0, -gravity). The gyro measures the body angular velocity (rad/s), the
/// accelerometer the specific force f = R^T (a_w - g_w) (m/s^2: +gravity on z at rest, level).
///
/// Preintegration [F: preintegrated measurements]: between t0 and t1, with R(τ) the rotation from
/// the body at τ to the body at t0,
///   ΔR = R_{t0}^T R_{t1},   Δv = ∫ R(τ) f(τ) dτ,   Δp = ∫∫ R(τ) f(τ) dτ²,
/// all in the t0 body frame, gravity NOT removed; the pose and velocity then follow:
///   R1 = R0 ΔR,   v1 = v0 + g_w Δt + R0 Δv,   p1 = p0 + v0 Δt + ½ g_w Δt² + R0 Δp.
/// Integration: the measurements are taken linear in time between samples (the samples at t0 and
/// t1 themselves interpolated between their neighbours), and each interval [a, b], h = b - a, is
/// integrated to second order (global error O(h²), against O(h) for Forster's Euler step,
/// a zero-order hold):
///   R_b = R_a Exp(h (ω_a + ω_b) / 2),   Δv += h (R_a f_a + R_b f_b) / 2,
///   Δp += h Δv_a + h² (R_a f_a / 3 + R_b f_b / 6)
/// (the rotated specific force taken linear over the interval, integrated twice exactly).
///
/// Covariance: of the error e = (δθ, δv, δp) with ΔR_true = Exp(δθ) ΔR, Δv_true = Δv + δv,
/// Δp_true = Δp + δp — the LEFT perturbation in the t0 body frame, the convention of pose3.hpp
/// (Forster's right δφ, ΔR_true = ΔR Exp(δφ), is ΔR^T δθ). It is propagated to first order from
/// each sample's white noise, the discrete σ_d² = density² / Δt_k (Δt_k the sample's period, the
/// mean of its two neighbouring gaps), through the linearised recursion of the scheme above ([F:
/// noise propagation], left-perturbed, with the noise of both ends of each interval), plus the bias
/// left after the known bias is subtracted: a CONSTANT over the window, N(0, σ_b²) per axis,
/// entering through the Jacobian of the increment with respect to the bias [F: bias update]:
///   Σ = Σ_k G_k diag(σ_g,k², σ_a,k²) G_k^T + J_b diag(σ_bg², σ_ba²) J_b^T.
/// Not a random walk: over a scan interval the bias barely moves, but what is left of it after a
/// calibration is common to every sample — as a random walk (variance σ² Δt) it would be far too
/// small. Consecutive increments share it, so a filter chaining them sees correlated errors.

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/pose3.hpp"

namespace vdtnav {

using Matrix9d = Eigen::Matrix<double, 9, 9>;

/// \brief One IMU reading.
struct ImuSample {
  double t = 0.0;                                   ///< seconds
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero();   ///< angular velocity, rad/s, body frame
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();  ///< specific force, m/s^2, body frame
};

/// \brief The IMU's noise and biases. Defaults: a consumer MEMS IMU, the Bosch BMI088 (data sheet
/// BST-BMI088-DS001: gyro noise density 0.014 °/s/√Hz, accelerometer 175 µg/√Hz at ±3 g; gyro
/// zero-rate offset drift 0.015 °/s/K), still and clean: on a vehicle, vibration raises the noise
/// (VIO set-ups commonly inflate the data sheet's densities several times).
struct ImuNoise {
  /// Gyro white noise, rad/s/√Hz (0.014 °/s/√Hz).
  double gyro_noise_density = 0.014 * 3.14159265358979323846 / 180.0;
  /// Accelerometer white noise, m/s^2/√Hz (175 µg/√Hz).
  double accel_noise_density = 175e-6 * 9.80665;
  /// Known gyro bias, rad/s, subtracted from every reading (e.g. the mean at standstill).
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();
  /// Known accelerometer bias, m/s^2, subtracted from every reading.
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();
  /// 1 σ per axis of the gyro bias left after subtraction, rad/s (0.06 °/s: the offset drift
  /// over ±4 K after a standstill calibration).
  double gyro_bias_sigma = 1e-3;
  /// 1 σ per axis of the accelerometer bias left after subtraction, m/s^2 (2 mg).
  double accel_bias_sigma = 0.02;
  /// Magnitude of gravity, m/s^2 (standard gravity).
  double gravity = 9.80665;

  /// \throws ConfigError unless the densities and sigmas are finite and >= 0, the biases finite
  /// and gravity finite and > 0.
  void validate() const;
};

/// \brief The preintegrated IMU between two times [F: preintegrated measurements].
struct ImuIncrement {
  double t0 = 0.0;  ///< seconds
  double t1 = 0.0;  ///< seconds
  double dt = 0.0;  ///< t1 - t0, seconds
  /// ΔR: the rotation from the body frame at t1 to the body frame at t0 (R1 = R0 ΔR).
  Eigen::Matrix3d delta_R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d delta_v = Eigen::Vector3d::Zero();  ///< Δv, m/s, t0 body frame, with gravity
  Eigen::Vector3d delta_p = Eigen::Vector3d::Zero();  ///< Δp, m, t0 body frame, with gravity
  /// Of (δθ, δv, δp) (rad, m/s, m), left perturbation in the t0 body frame: noise and bias.
  Matrix9d covariance = Matrix9d::Zero();
  /// J_b = d(δθ, δv, δp) / d(gyro_bias, accel_bias): the increment with the bias b + δb
  /// subtracted is, to first order, (Exp(J_θ δb) ΔR, Δv + J_v δb, Δp + J_p δb) [F: bias update].
  Eigen::Matrix<double, 9, 6> bias_jacobian = Eigen::Matrix<double, 9, 6>::Zero();
  std::size_t samples_used = 0;  ///< samples with a weight in the integral (both brackets included)
  double max_gap = 0.0;          ///< the longest interval between samples integrated, seconds
};

/// \return true when `samples` cover [t0, t1]: one at or before t0, one at or after t1.
[[nodiscard]] bool imu_covers(const std::vector<ImuSample>& samples, double t0, double t1);

/// \brief Preintegrates the samples covering [t0, t1] (see the file comment).
/// \param samples in strictly increasing time (as load_imu_csv returns them).
/// \throws ConfigError unless t0 < t1 (finite) and noise is valid; when the samples do not cover
/// [t0, t1] (the message gives the samples' span and the times missing: check imu_covers() first
/// on a live stream); when the samples used are not in strictly increasing time.
[[nodiscard]] ImuIncrement integrate_imu(const std::vector<ImuSample>& samples, double t0,
                                         double t1, const ImuNoise& noise);

/// \brief The pose at t1 from the pose and world velocity at t0:
/// R1 = R0 ΔR, v1 = v0 + g_w Δt + R0 Δv, p1 = p0 + v0 Δt + ½ g_w Δt² + R0 Δp,
/// g_w = (0, 0, -gravity) in the world (map) frame, z up.
/// \param velocity_world_t1 if not null, receives v1 (m/s, world frame).
[[nodiscard]] Pose3 predict_with_imu(const Pose3& pose_t0, const Eigen::Vector3d& velocity_world_t0,
                                     const ImuIncrement& inc, double gravity,
                                     Eigen::Vector3d* velocity_world_t1 = nullptr);

/// \brief The motion increment an IMU gives between two scans: what fills OdometryStep3::delta.
struct ImuRelativePose {
  /// D = T0^-1 T1, the pose at t1 in the body frame at t0: R_D = ΔR,
  /// t_D = R0^T (v0 Δt + ½ g_w Δt²) + Δp.
  Pose3 delta = Pose3::Identity();
  /// Of (dt, dθ) with D_true = oplus(D, (dt, dθ)) = (Exp(dθ) R_D, t_D + dt): the left
  /// perturbation of pose3.hpp in the t0 body frame (the frame OdometryStep3::delta is in); for the
  /// world frame, rotate both blocks by R0: pose_t0 * oplus(D, e) = oplus(pose_t0 * D, (R0 dt,
  /// R0 dθ)). Holds the IMU's noise and bias and the velocity's uncertainty, uncorrelated;
  /// R0's own uncertainty is left out (its roll/pitch turns ½ g Δt²: 0.25 mm at 0.1 s and 5 mrad).
  Matrix6d covariance = Matrix6d::Zero();
  Eigen::Vector3d velocity_world_t1 = Eigen::Vector3d::Zero();  ///< v1, m/s, world frame
};

/// \brief The relative pose over an increment and its covariance, from the pose at t0 (for the
/// gravity direction in the body frame) and a world velocity estimate at t0 (e.g. constant
/// velocity from the last two scan poses).
/// \param velocity_covariance of v0, (m/s)^2, world frame.
[[nodiscard]] ImuRelativePose imu_relative_pose(const Pose3& pose_t0,
                                                const Eigen::Vector3d& velocity_world_t0,
                                                const Eigen::Matrix3d& velocity_covariance,
                                                const ImuIncrement& inc, double gravity);

/// \brief Roll and pitch observed from gravity.
struct GravityAttitude {
  double roll = 0.0;         ///< radians, R = Rz(yaw) Ry(pitch) Rx(roll) as pose3_from_xyz_rpy
  double pitch = 0.0;        ///< radians
  double sigma_roll = 0.0;   ///< 1 σ, radians (inflated when accelerating)
  double sigma_pitch = 0.0;  ///< 1 σ, radians (inflated when accelerating)
  /// Of (roll, pitch), rad^2, from the noise and bias (inflated when accelerating).
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  Eigen::Vector3d mean_specific_force = Eigen::Vector3d::Zero();  ///< m/s^2, bias subtracted
  /// | |f̄| - gravity |, m/s^2: what acceleration the norm shows.
  double gravity_deviation = 0.0;
  bool accelerating = false;  ///< gravity_deviation > the threshold
  std::size_t samples_used = 0;
};

/// \brief Roll and pitch from the mean specific force over the samples in [t0, t1]: at rest (or
/// at constant velocity) f = R^T (0, 0, g) = g (-sin p, cos p sin r, cos p cos r), so
///   roll = atan2(f_y, f_z),   pitch = atan2(-f_x, sqrt(f_y² + f_z²)).
/// Their covariance is J Σ_f J^T, Σ_f = (accel_noise_density² / Δt / N + accel_bias_sigma²) I
/// (the white noise averages over the N samples, the bias does not); σ_roll = σ_f / |(f_y, f_z)|,
/// σ_pitch = σ_f / |f|.
/// An acceleration a tilts f by up to |a| / g: the window is flagged `accelerating` when |f̄|
/// differs from gravity by more than `accelerating_threshold` (m/s^2; the default is 5 σ of the
/// norm's error with the default accel_bias_sigma), and then the variance of both angles grows by
/// (a_n / g)², a_n = sqrt(| |f̄|² - g² |): the acceleration across gravity that would give that
/// norm (≈ sqrt(2 g d) for a deviation d: 0.14 rad at the threshold). The norm sees a
/// vertical acceleration fully but a horizontal one only to second order (1 m/s^2 sideways moves
/// |f| by 0.05 m/s^2 and roll by 0.1 rad): take windows where the robot is known to be at rest or
/// cruising.
/// \throws ConfigError unless t0 <= t1 and noise is valid, or when no sample lies in [t0, t1].
[[nodiscard]] GravityAttitude attitude_from_gravity(const std::vector<ImuSample>& samples,
                                                    double t0, double t1, const ImuNoise& noise,
                                                    double accelerating_threshold = 0.1);

}  // namespace vdtnav
