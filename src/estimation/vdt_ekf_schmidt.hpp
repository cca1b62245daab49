#pragma once
// Internal to the VDT EKF (vdt_ekf.cpp, vdt_ekf_schmidt.cpp): the joint iterations of a
// Schmidt-Kalman update over the pose and the errors of the map's squares in view.

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/estimation/vdt_ekf.hpp"

namespace vdtnav::detail {

using Matrix32 = Eigen::Matrix<double, 3, 2>;

/// What the joint iterations of a Schmidt-Kalman update found (VdtEkfOptions::schmidt_map_errors).
struct SchmidtStep {
  Pose2 pose = Pose2::Zero();
  int inliers = 0, iterations = 0;
  Eigen::Matrix3d p = Eigen::Matrix3d::Zero();             ///< Pi_xx (+ the frame's shared errors)
  Eigen::Matrix3d out_of_view = Eigen::Matrix3d::Zero();   ///< (Pi Sigma^-1)_xx
  std::vector<std::pair<std::int64_t, Matrix32>> in_view;  ///< Pi_xk per square in view
};

/// Map errors shared per square (VdtSensorModelOptions::map_correlation_length) persist: the
/// robot sees one square in many scans, so the filter keeps cov(X, e_k) = C_k for every square k
/// it has seen (Schmidt-Kalman). The iterations solve for y = (X, e_k of the squares in view)
/// under the prior
///   Sigma = [P C; C^T sigma_c^2 I]
/// with reading i's disparity d_i(X) - d_point_i e_k (a map drawn off by e_k), by Gauss-Newton
/// on (y - y_pred)^T Sigma^-1 (y - y_pred) + sum r^T R^-1 r. The pose takes the joint optimum,
/// the squares' errors stay unestimated (mean 0, variance sigma_c^2), and P+ = Pi_xx,
/// C_k+ = Pi_xk for the squares in view, C_h+ = (Pi Sigma^-1)_xx C_h for the others (Pi the
/// joint posterior covariance; (I - K H) = Pi Sigma^-1): P is the error against the world, and a
/// square seen again adds no information about the pose beyond what its error allows. Errors
/// every point of the frame shares (theta) are considered as in the update: P+ gains
/// S cov(theta) S^T, S = Pi_x sum_i J_i^T R_i^-1 d_point_i G_i (J_i the reading's Jacobian in y).
SchmidtStep schmidt_iterations(const VdtSensorModel& model, const VdtEkfOptions& options,
                               const Pose2& x_pred, const Eigen::Matrix3d& p,
                               const std::unordered_map<std::int64_t, Matrix32>& cross,
                               const ScanPoints& pts, Pose2 xi);

}  // namespace vdtnav::detail
