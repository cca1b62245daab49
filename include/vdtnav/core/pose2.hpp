#pragma once
/// \file
/// \brief Planar poses (x, y, yaw) as Eigen::Vector3d, REP-103: yaw counter-clockwise, wrapped to
/// (-pi, pi].

#include <cmath>

#include <Eigen/Core>

namespace vdtnav {

using Pose2 = Eigen::Vector3d;  ///< (x [m], y [m], yaw [rad])

inline constexpr double kPi = 3.14159265358979323846;  ///< pi, as a double

/// \return angle wrapped to (-pi, pi].
[[nodiscard]] inline double wrap_angle(double a) {
  a = std::remainder(a, 2.0 * kPi);  // [-pi, pi]
  return a <= -kPi ? a + 2.0 * kPi : a;
}

/// \return the pose a (+) b: b expressed in a's frame, composed onto a.
[[nodiscard]] inline Pose2 compose(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a[2]), s = std::sin(a[2]);
  return {a[0] + c * b[0] - s * b[1], a[1] + s * b[0] + c * b[1], wrap_angle(a[2] + b[2])};
}

/// \return a^{-1} (+) b: the pose of b in a's frame (an odometry increment from a to b).
[[nodiscard]] inline Pose2 between(const Pose2& a, const Pose2& b) {
  const double c = std::cos(a[2]), s = std::sin(a[2]);
  const double dx = b[0] - a[0], dy = b[1] - a[1];
  return {c * dx + s * dy, -s * dx + c * dy, wrap_angle(b[2] - a[2])};
}

/// \return point p (in the frame of `pose`) in the world frame.
[[nodiscard]] inline Eigen::Vector2d transform_point(const Pose2& pose, const Eigen::Vector2d& p) {
  const double c = std::cos(pose[2]), s = std::sin(pose[2]);
  return {pose[0] + c * p.x() - s * p.y(), pose[1] + s * p.x() + c * p.y()};
}

/// \return the pose error a - b with the angle wrapped.
[[nodiscard]] inline Eigen::Vector3d pose_error(const Pose2& a, const Pose2& b) {
  return {a[0] - b[0], a[1] - b[1], wrap_angle(a[2] - b[2])};
}

}  // namespace vdtnav
