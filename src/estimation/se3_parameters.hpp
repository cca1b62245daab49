#pragma once
/// \file
/// \brief The 7 ambient parameters of an SE(3) pose, x = (q_x, q_y, q_z, q_w, t_x, t_y, t_z): the
/// unit quaternion of R in Eigen's coefficient order, then the translation. The block both
/// solvers of VdtOptimizerT<3> hold a pose in (scan_solve.hpp); Eigen only, so the dense solver
/// builds without Ceres (se3_manifold.hpp adds Ceres's manifolds on the same block).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "vdtnav/core/pose3.hpp"

namespace vdtnav {

/// \brief Writes the 7 ambient parameters (q_x, q_y, q_z, q_w, t) of `pose`.
inline void se3_to_parameters(const Pose3& pose, double* x) {
  Eigen::Quaterniond q(pose.linear());
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();  // one of the two covers, w >= 0
  Eigen::Map<Eigen::Vector4d>{x} = q.coeffs();
  Eigen::Map<Eigen::Vector3d>{x + 4} = pose.translation();
}

/// \return the pose of 7 ambient parameters (the quaternion is normalised).
[[nodiscard]] inline Pose3 se3_from_parameters(const double* x) {
  Pose3 pose = Pose3::Identity();
  pose.linear() = Eigen::Quaterniond(x[3], x[0], x[1], x[2]).normalized().toRotationMatrix();
  pose.translation() = Eigen::Map<const Eigen::Vector3d>(x + 4);
  return pose;
}

}  // namespace vdtnav
