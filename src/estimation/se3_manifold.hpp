#pragma once
/// \file
/// \brief Ceres manifolds for SE(3) poses with the left perturbation of pose3.hpp, and the
/// 4-DOF (x, y, z, yaw) sub-manifold that holds roll and pitch (from an IMU), as DLL does.
///
/// Private to vdtnav::estimation (its Ceres solver backend, scan_cost.cpp): Ceres is a private
/// dependency, so no installed header includes it (issue 58).
///
/// Ambient parameters (7): x = (q_x, q_y, q_z, q_w, t_x, t_y, t_z), the unit quaternion of R in
/// Eigen's coefficient order followed by the translation.
///  - Se3LeftManifold, tangent delta = (dt, dtheta) in the world frame (6):
///      Plus(X, delta) = (Exp(dtheta) R, t + dt),   Minus(Y, X) = (t_Y - t_X, Log(R_Y R_X^T)).
///  - Se3YawManifold, tangent delta = (dt, dpsi) (4): the left perturbation with
///    dtheta = (0, 0, dpsi), a rotation about the world z axis, which leaves roll and pitch of
///    R = Rz(yaw) Ry(pitch) Rx(roll) unchanged (Rz(dpsi) R = Rz(yaw + dpsi) Ry Rx).
/// Both are consistent with PoseTraits<3>::plus/minus (oplus/ominus), so a Jacobian computed in
/// the 6-DOF left perturbation D (n x 6) is, in the 4-DOF tangent, its columns (0, 1, 2, 5).
///
/// A cost function on the ambient block may return any ambient Jacobian A with A P = D, P the
/// PlusJacobian: A = D M with M the MinusJacobian (M P = I) is the cheap choice
/// (Se3AmbientJacobian).

#include <ceres/manifold.h>

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "se3_parameters.hpp"
#include "vdtnav/core/pose3.hpp"

namespace vdtnav {

namespace detail {

/// Exp(theta) as a unit quaternion (series near 0).
inline Eigen::Quaterniond quaternion_exp(const Eigen::Vector3d& theta) {
  const double a2 = theta.squaredNorm();
  if (a2 < 1e-12) {
    const Eigen::Vector3d v = 0.5 * (1.0 - a2 / 24.0) * theta;
    return Eigen::Quaterniond(1.0 - a2 / 8.0, v.x(), v.y(), v.z()).normalized();
  }
  const double a = std::sqrt(a2);
  const Eigen::Vector3d v = (std::sin(0.5 * a) / a) * theta;
  return Eigen::Quaterniond(std::cos(0.5 * a), v.x(), v.y(), v.z());
}

/// Log(q) as a rotation vector, |theta| in [0, pi].
inline Eigen::Vector3d quaternion_log(Eigen::Quaterniond q) {
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  const double n = q.vec().norm();
  if (n < 1e-12) return (2.0 / q.w()) * q.vec();
  return (2.0 * std::atan2(n, q.w()) / n) * q.vec();
}

/// The rotational rows of the MinusJacobian at q: dLog(q_y q^*)/dq_y at q_y = q,
/// 2 [w I + [v]_x | -v] (3 x 4, columns q_x, q_y, q_z, q_w).
inline Eigen::Matrix<double, 3, 4> rotation_minus_jacobian(const double* x) {
  const Eigen::Vector3d v(x[0], x[1], x[2]);
  const double w = x[3];
  Eigen::Matrix<double, 3, 4> m;
  m.leftCols<3>() = 2.0 * (w * Eigen::Matrix3d::Identity() + skew(v));
  m.col(3) = -2.0 * v;
  return m;
}

/// The rotational block of the PlusJacobian at q: d(Exp(theta) q)/dtheta at 0,
/// [(w I - [v]_x) / 2 ; -v^T / 2] (4 x 3, rows q_x, q_y, q_z, q_w).
inline Eigen::Matrix<double, 4, 3> rotation_plus_jacobian(const double* x) {
  const Eigen::Vector3d v(x[0], x[1], x[2]);
  const double w = x[3];
  Eigen::Matrix<double, 4, 3> p;
  p.topRows<3>() = 0.5 * (w * Eigen::Matrix3d::Identity() - skew(v));
  p.row(3) = -0.5 * v.transpose();
  return p;
}

}  // namespace detail

/// \brief SE(3) with the left perturbation (dt, dtheta) on the 7 ambient parameters.
class Se3LeftManifold final : public ceres::Manifold {
 public:
  static constexpr int kAmbient = 7;
  static constexpr int kTangent = 6;

  [[nodiscard]] int AmbientSize() const override { return kAmbient; }
  [[nodiscard]] int TangentSize() const override { return kTangent; }

  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    const Eigen::Quaterniond q(x[3], x[0], x[1], x[2]);
    const Eigen::Quaterniond dq =
        detail::quaternion_exp(Eigen::Map<const Eigen::Vector3d>(delta + 3));
    Eigen::Quaterniond out = (dq * q).normalized();
    if (out.w() < 0.0) out.coeffs() = -out.coeffs();
    Eigen::Map<Eigen::Vector4d>{x_plus_delta} = out.coeffs();
    Eigen::Map<Eigen::Vector3d>{x_plus_delta + 4} =
        Eigen::Map<const Eigen::Vector3d>(x + 4) + Eigen::Map<const Eigen::Vector3d>(delta);
    return true;
  }

  /// Row-major 7 x 6.
  bool PlusJacobian(const double* x, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> j(jacobian);
    j.setZero();
    j.topRightCorner<4, 3>() = detail::rotation_plus_jacobian(x);
    j.bottomLeftCorner<3, 3>().setIdentity();
    return true;
  }

  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    const Eigen::Quaterniond qy(y[3], y[0], y[1], y[2]), qx(x[3], x[0], x[1], x[2]);
    Eigen::Map<Eigen::Vector3d>{y_minus_x} =
        Eigen::Map<const Eigen::Vector3d>(y + 4) - Eigen::Map<const Eigen::Vector3d>(x + 4);
    Eigen::Map<Eigen::Vector3d>{y_minus_x + 3} = detail::quaternion_log(qy * qx.conjugate());
    return true;
  }

  /// Row-major 6 x 7.
  bool MinusJacobian(const double* x, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> j(jacobian);
    j.setZero();
    j.topRightCorner<3, 3>().setIdentity();
    j.bottomLeftCorner<3, 4>() = detail::rotation_minus_jacobian(x);
    return true;
  }
};

/// \brief The 4-DOF sub-manifold (dt, dpsi) of Se3LeftManifold: yaw about the world z axis,
/// roll and pitch held.
class Se3YawManifold final : public ceres::Manifold {
 public:
  static constexpr int kAmbient = 7;
  static constexpr int kTangent = 4;

  [[nodiscard]] int AmbientSize() const override { return kAmbient; }
  [[nodiscard]] int TangentSize() const override { return kTangent; }

  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    const double full[6] = {delta[0], delta[1], delta[2], 0.0, 0.0, delta[3]};
    return Se3LeftManifold().Plus(x, full, x_plus_delta);
  }

  /// Row-major 7 x 4: the columns (dt, dtheta_z) of Se3LeftManifold's.
  bool PlusJacobian(const double* x, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 7, 4, Eigen::RowMajor>> j(jacobian);
    j.setZero();
    j.topRightCorner<4, 1>() = detail::rotation_plus_jacobian(x).col(2);
    j.bottomLeftCorner<3, 3>().setIdentity();
    return true;
  }

  /// (dt, the z component of Log(R_Y R_X^T)): exact for Y = Plus(X, delta) with |dpsi| < pi.
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    double full[6];
    Se3LeftManifold().Minus(y, x, full);
    y_minus_x[0] = full[0];
    y_minus_x[1] = full[1];
    y_minus_x[2] = full[2];
    y_minus_x[3] = full[5];
    return true;
  }

  /// Row-major 4 x 7: the rows (dt, dtheta_z) of Se3LeftManifold's.
  bool MinusJacobian(const double* x, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 4, 7, Eigen::RowMajor>> j(jacobian);
    j.setZero();
    j.topRightCorner<3, 3>().setIdentity();
    j.bottomLeftCorner<1, 4>() = detail::rotation_minus_jacobian(x).row(2);
    return true;
  }
};

/// \brief Turns Jacobians in the left perturbation (dt, dtheta) into ambient Jacobians at the
/// parameters x, for a cost function on the 7-parameter block: A = D M with M the MinusJacobian,
/// so that A P = D for P the PlusJacobian (M P = I). With `yaw_only` (Se3YawManifold) the tangent
/// Jacobian is D's columns (dt, dtheta_z) and A = D_(0,1,2,5) M_4.
class Se3AmbientJacobian {
 public:
  Se3AmbientJacobian(const double* x, bool yaw_only)
      : m_(detail::rotation_minus_jacobian(x)), yaw_only_(yaw_only) {}

  /// \brief Writes the Rows x 7 row-major ambient Jacobian of `d_pose` (Rows x 6) to `ambient`.
  template <int Rows>
  void operator()(const Eigen::Matrix<double, Rows, 6>& d_pose, double* ambient) const {
    Eigen::Map<Eigen::Matrix<double, Rows, 7, Eigen::RowMajor>> a(ambient);
    if (yaw_only_) {
      a.template leftCols<4>().noalias() = d_pose.col(5) * m_.row(2);
    } else {
      a.template leftCols<4>().noalias() = d_pose.template rightCols<3>() * m_;
    }
    a.template rightCols<3>() = d_pose.template leftCols<3>();
  }

 private:
  Eigen::Matrix<double, 3, 4> m_;
  bool yaw_only_;
};

}  // namespace vdtnav
