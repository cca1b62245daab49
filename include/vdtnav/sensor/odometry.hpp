#pragma once
/// \file
/// \brief What odometry (and an IMU) report between two scans: the motion readings every
/// localizer's prediction takes, and what the simulators and log readers produce.

#include <limits>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/core/pose3.hpp"

namespace vdtnav {

/// \brief What odometry reports between two scans.
struct OdometryStep {
  double dt = 0.0;              ///< seconds since the previous scan
  double v = 0.0;               ///< measured linear velocity, m/s (velocity model)
  double w = 0.0;               ///< measured angular velocity, rad/s
  Pose2 delta = Pose2::Zero();  ///< measured increment in the previous robot frame
};

/// \brief What odometry and an IMU report between two 3D scans.
struct OdometryStep3 {
  double dt = 0.0;                  ///< seconds since the previous scan
  Pose3 delta = Pose3::Identity();  ///< measured increment in the previous robot frame
  /// The IMU's roll and pitch of the robot at this scan (the gravity direction, R = Rz Ry Rx as
  /// pose3_from_xyz_rpy), radians; NaN: no IMU, the prediction's own attitude is used.
  double roll = std::numeric_limits<double>::quiet_NaN();
  double pitch = std::numeric_limits<double>::quiet_NaN();
  /// Their standard deviation (radians), e.g. from gravity (sensor/imu.hpp,
  /// attitude_from_gravity); NaN: the localizer's own (VdtLocalizer3Options::sigma_imu_attitude).
  double attitude_sigma = std::numeric_limits<double>::quiet_NaN();
  /// The increment's own covariance, of (dt, dtheta) with delta_true = oplus(delta, e) (the left
  /// perturbation in the previous robot frame): an IMU's preintegration (sensor/imu.hpp,
  /// imu_relative_pose). has_covariance false: the localizer's odometry noise model.
  Matrix6d covariance = Matrix6d::Zero();
  bool has_covariance = false;

  [[nodiscard]] bool has_attitude() const noexcept { return roll == roll && pitch == pitch; }
};

/// \brief The odometry type of dimension Dim (OdometryStep in 2D, OdometryStep3 in 3D).
template <int Dim>
struct OdometryTraits;
template <>
struct OdometryTraits<2> {
  using Step = OdometryStep;
};
template <>
struct OdometryTraits<3> {
  using Step = OdometryStep3;
};

}  // namespace vdtnav
