#pragma once
/// \file
/// \brief Per-dimension facts in one place (like manif's LieGroupProperties).
///
/// SpaceTraits<Dim> holds the fixed-size types of a Dim-dimensional workspace; PoseTraits<Dim>
/// the rigid pose of that workspace, its perturbation (the chart the estimators linearize in) and
/// the transform of a robot-frame point with its first and second derivatives with respect to
/// the pose, which the VDT sensor model and the implicit-function covariance (3.4)-(3.6) need:
///  - Dim 2: X = (x, y, phi) (Pose2), additive perturbation with the angle wrapped, 3 DoF;
///  - Dim 3: X in SE(3) (Pose3), the left perturbation of pose3.hpp, delta = (dt, dtheta) in the
///    world frame, X (+) delta = (Exp(dtheta) R, t + dt), 6 DoF.

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/core/pose3.hpp"

namespace vdtnav {

/// \brief Fixed-size types and counts for a map/workspace of dimension Dim (2 or 3).
template <int Dim>
struct SpaceTraits {
  static_assert(Dim == 2 || Dim == 3, "vdtnav supports 2D and 3D workspaces");
  static constexpr int kDim = Dim;
  using Vector = Eigen::Matrix<double, Dim, 1>;
  using Matrix = Eigen::Matrix<double, Dim, Dim>;
  using Index = Eigen::Matrix<int, Dim, 1>;
};

/// \brief Rigid poses in Dim dimensions: 3 DoF (x, y, yaw) in 2D, 6 DoF (SE(3)) in 3D.
///
/// Every specialisation provides
///  - `kDim`, `kDoF`; `Pose`, `Vector` (a point), `Rotation`, `Tangent` (a perturbation),
///    `Covariance` (kDoF x kDoF), `PointJacobian` (Dim x kDoF);
///  - `identity()`, `rotation(X)`, `translation(X)`, `plus(X, delta)`, `minus(a, b)`
///    (plus(b, minus(a, b)) == a);
///  - `pose_jacobian(J, rp)`: J dq/dX for q = R p + t with rp = R p, J any Dim x Dim matrix
///    (J = I gives dq/dX itself); d(R u)/dX is the same expression with the translation columns
///    zero: `rotation_jacobian(J, ru)`;
///  - `point_hessian(g, rp)`: sum_c g_c d^2 q_c / dX^2, the second derivative of q along g.
template <int Dim>
struct PoseTraits;

template <>
struct PoseTraits<2> {
  static constexpr int kDim = 2;
  static constexpr int kDoF = 3;
  using Pose = Pose2;
  using Vector = Eigen::Vector2d;
  using Rotation = Eigen::Matrix2d;
  using Tangent = Eigen::Vector3d;
  using Covariance = Eigen::Matrix3d;
  using PointJacobian = Eigen::Matrix<double, 2, 3>;

  [[nodiscard]] static Pose identity() { return Pose::Zero(); }
  [[nodiscard]] static Rotation rotation(const Pose& x) {
    return rotation(std::cos(x[2]), std::sin(x[2]));
  }
  /// \return R(phi) from cos(phi), sin(phi).
  [[nodiscard]] static Rotation rotation(double c, double s) {
    Rotation r;
    r << c, -s, s, c;
    return r;
  }
  [[nodiscard]] static Vector translation(const Pose& x) { return x.head<2>(); }
  /// \return (x + dx, y + dy, wrap(phi + dphi)).
  [[nodiscard]] static Pose plus(const Pose& x, const Tangent& delta) {
    return {x[0] + delta[0], x[1] + delta[1], wrap_angle(x[2] + delta[2])};
  }
  /// \return a - b with the angle wrapped.
  [[nodiscard]] static Tangent minus(const Pose& a, const Pose& b) { return pose_error(a, b); }

  /// \return J [I | R' p], R' p = (-(Rp)_y, (Rp)_x): dq/dphi = R'(phi) p.
  [[nodiscard]] static PointJacobian pose_jacobian(const Eigen::Matrix2d& j, const Vector& rp) {
    PointJacobian out;
    out.leftCols<2>() = j;
    out.col(2) = j * Vector(-rp.y(), rp.x());
    return out;
  }
  /// \return J [0 | R' u].
  [[nodiscard]] static PointJacobian rotation_jacobian(const Eigen::Matrix2d& j, const Vector& ru) {
    PointJacobian out;
    out.leftCols<2>().setZero();
    out.col(2) = j * Vector(-ru.y(), ru.x());
    return out;
  }
  /// \return sum_c g_c d^2 q_c/dX^2: only d^2 q/dphi^2 = -R p is non-zero.
  [[nodiscard]] static Covariance point_hessian(const Vector& g, const Vector& rp) {
    Covariance h = Covariance::Zero();
    h(2, 2) = -g.dot(rp);
    return h;
  }
};

template <>
struct PoseTraits<3> {
  static constexpr int kDim = 3;
  static constexpr int kDoF = 6;
  using Pose = Pose3;
  using Vector = Eigen::Vector3d;
  using Rotation = Eigen::Matrix3d;
  using Tangent = Vector6d;
  using Covariance = Matrix6d;
  using PointJacobian = Eigen::Matrix<double, 3, 6>;

  [[nodiscard]] static Pose identity() { return Pose::Identity(); }
  [[nodiscard]] static Rotation rotation(const Pose& x) { return x.linear(); }
  [[nodiscard]] static Vector translation(const Pose& x) { return x.translation(); }
  /// \return X (+) delta (left perturbation, pose3.hpp).
  [[nodiscard]] static Pose plus(const Pose& x, const Tangent& delta) { return oplus(x, delta); }
  /// \return a (-) b (pose3.hpp).
  [[nodiscard]] static Tangent minus(const Pose& a, const Pose& b) { return ominus(a, b); }

  /// \return J [I | -[R p]_x]: d(Exp(theta) R p + t + dt)/d(dt, theta) at 0.
  [[nodiscard]] static PointJacobian pose_jacobian(const Eigen::Matrix3d& j, const Vector& rp) {
    PointJacobian out;
    out.leftCols<3>() = j;
    // column 3 + k of -[v]_x is e_k x v
    out.col(3) = j.col(2) * rp.y() - j.col(1) * rp.z();  // J (e_x x v) = J (0, -v_z, v_y)
    out.col(4) = j.col(0) * rp.z() - j.col(2) * rp.x();  // J (e_y x v) = J (v_z, 0, -v_x)
    out.col(5) = j.col(1) * rp.x() - j.col(0) * rp.y();  // J (e_z x v) = J (-v_y, v_x, 0)
    return out;
  }
  /// \return J [0 | -[R u]_x].
  [[nodiscard]] static PointJacobian rotation_jacobian(const Eigen::Matrix3d& j, const Vector& ru) {
    PointJacobian out = pose_jacobian(j, ru);
    out.leftCols<3>().setZero();
    return out;
  }
  /// \return sum_c g_c d^2 q_c/dtheta_a dtheta_b = (g_a v_b + g_b v_a)/2 - (g . v) delta_ab with
  /// v = R p, from Exp(theta) v = v + theta x v + theta x (theta x v)/2 + O(theta^3); the
  /// translation rows and columns are zero (q is linear in dt).
  [[nodiscard]] static Covariance point_hessian(const Vector& g, const Vector& rp) {
    Covariance h = Covariance::Zero();
    const Eigen::Matrix3d outer = g * rp.transpose();
    h.bottomRightCorner<3, 3>() = 0.5 * (outer + outer.transpose());
    h.bottomRightCorner<3, 3>().diagonal().array() -= g.dot(rp);
    return h;
  }
};

}  // namespace vdtnav
