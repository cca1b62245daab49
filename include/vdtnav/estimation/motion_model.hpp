#pragma once
/// \file
/// \brief The prediction step shared by the filters and by the optimization localizer's
/// uncertainty bookkeeping: the velocity motion model (3.7)-(3.10), or an odometry-increment
/// model whose noise grows with the motion (for logs, where only pose increments are known).

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/estimation/localizer.hpp"

namespace vdtnav {

/// \brief The prediction model.
enum class MotionModelKind {
  kVelocity,           ///< (3.7)-(3.10) with measured (v, w) and Q = diag(sigma_v^2, sigma_w^2)
  kOdometryIncrement,  ///< X (+) delta with noise proportional to the motion
};

/// \brief Motion noise.
struct MotionNoise {
  double sigma_v = 0.05;  ///< m/s (Table 3.2 read as a standard deviation)
  double sigma_w = 0.01;  ///< rad/s
  /// Velocity model: isotropic process-noise floor for what the motion model leaves out (slip,
  /// and map error that stays correlated while the robot sees the same walls), m/s and rad/s.
  /// Without it the filter keeps fusing scans across the direction of motion and its covariance
  /// shrinks far below the map-limited error (ANEES in the hundreds on the simulated run).
  double floor_xy_rate = 0.02;
  double floor_yaw_rate = 0.005;
  // Odometry-increment model: sigma_trans = a_tt |t| + a_tr |rot| + floor_t,
  // sigma_rot = a_rr |rot| + a_rt |t| + floor_r (per step).
  double a_tt = 0.05, a_tr = 0.01, a_rr = 0.05, a_rt = 0.02;
  double floor_t = 0.001, floor_r = 0.001;
};

/// \brief One EKF step's prediction (3.7)-(3.10) or odometry-increment prediction; `jacobian`,
/// when given, receives F = dX+/dX (what carries a cross-covariance with X forward).
void ekf_predict(MotionModelKind kind, const MotionNoise& noise, const OdometryStep& odometry,
                 Pose2& x, Eigen::Matrix3d& p, Eigen::Matrix3d* jacobian = nullptr);

}  // namespace vdtnav
