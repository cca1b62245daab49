#pragma once
/// \file
/// \brief Rigid 3D poses in SE(3) (REP-103: x forward, y left, z up; roll, pitch, yaw as the
/// ZYX Tait-Bryan angles R = Rz(yaw) Ry(pitch) Rx(roll)), and the small-perturbation maps the
/// 6-DOF estimators share.
///
/// Perturbations are on the left (world frame), delta = (dt, dtheta):
///   X (+) delta = (Exp(dtheta) R, t + dt)
/// so d(R p + t)/d(dt) = I and d(R p + t)/d(dtheta) = -[R p]_x, the Jacobian the 6-DOF VDT
/// residual uses, and the covariance of a pose is that of (dt, dtheta) in the world frame.

#include <algorithm>
#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vdtnav {

using Pose3 = Eigen::Isometry3d;         ///< rotation R and translation t
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// \return the skew-symmetric matrix [v]_x with [v]_x w = v x w.
[[nodiscard]] inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

/// \return Exp(w): the rotation by |w| about w/|w| (Rodrigues; exact to second order near 0).
[[nodiscard]] inline Eigen::Matrix3d so3_exp(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  if (theta < 1e-8) return Eigen::Matrix3d::Identity() + skew(w);
  return Eigen::AngleAxisd(theta, w / theta).toRotationMatrix();
}

/// \return Log(R) as a rotation vector with |w| in [0, pi].
[[nodiscard]] inline Eigen::Vector3d so3_log(const Eigen::Matrix3d& r) {
  const Eigen::AngleAxisd aa(r);
  return aa.angle() * aa.axis();
}

/// \return the pose with position (x, y, z) and attitude R = Rz(yaw) Ry(pitch) Rx(roll).
[[nodiscard]] inline Pose3 pose3_from_xyz_rpy(double x, double y, double z, double roll,
                                             double pitch, double yaw) {
  Pose3 p = Pose3::Identity();
  p.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  p.translation() = Eigen::Vector3d(x, y, z);
  return p;
}

/// \return (roll, pitch, yaw) of R = Rz(yaw) Ry(pitch) Rx(roll), pitch in [-pi/2, pi/2].
[[nodiscard]] inline Eigen::Vector3d rpy_of(const Eigen::Matrix3d& r) {
  const double pitch = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
  const double roll = std::atan2(r(2, 1), r(2, 2));
  const double yaw = std::atan2(r(1, 0), r(0, 0));
  return {roll, pitch, yaw};
}

/// \return X (+) delta, delta = (dt, dtheta) applied on the left (world frame).
[[nodiscard]] inline Pose3 oplus(const Pose3& x, const Vector6d& delta) {
  Pose3 y = Pose3::Identity();
  y.linear() = so3_exp(delta.tail<3>()) * x.linear();
  y.translation() = x.translation() + delta.head<3>();
  return y;
}

/// \return a (-) b: the left perturbation delta with b (+) delta = a.
[[nodiscard]] inline Vector6d ominus(const Pose3& a, const Pose3& b) {
  Vector6d d;
  d.head<3>() = a.translation() - b.translation();
  d.tail<3>() = so3_log(a.linear() * b.linear().transpose());
  return d;
}

/// \return the rotation angle between the attitudes of a and b, radians in [0, pi].
[[nodiscard]] inline double attitude_error(const Pose3& a, const Pose3& b) {
  return so3_log(a.linear() * b.linear().transpose()).norm();
}

}  // namespace vdtnav
