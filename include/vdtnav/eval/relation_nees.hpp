#pragma once
/// \file
/// \brief The NEES of a relation (Kümmerle et al. 2009): does the covariance of two pose estimates
/// cover the error of their relative pose against a manually verified one?
///
/// For estimates x_i, x_j (covariances Σ_i, Σ_j, taken as independent) the relative pose is
///   δ = x_i⁻¹ ⊕ x_j = (R(θ_i)ᵀ (t_j − t_i), θ_j − θ_i)                          (1)
/// and to first order its covariance is
///   Σ_rel = J_i Σ_i J_iᵀ + J_j Σ_j J_jᵀ,  J_i = ∂δ/∂x_i,  J_j = ∂δ/∂x_j           (2)
/// with, in the additive (x, y, yaw) parameterisation of the 2D localizers' covariances
/// (pose_error(estimate, truth) = estimate − truth),
///   J_i = [−c −s  δ_y;  s −c −δ_x;  0 0 −1],   J_j = [c s 0; −s c 0; 0 0 1],     (3)
/// c = cos θ_i, s = sin θ_i. The error of the relation is e = δ ⊖ δ* = pose_error(δ, δ*)  (4)
/// and its NEES = eᵀ Σ_rel⁻¹ e                                                      (5)
/// is χ²(3) for a consistent estimator. The error transform δ*⁻¹ ⊕ δ of the relation metric is
/// Q e with Q = diag(R(θ*)ᵀ, 1) orthogonal, so the NEES is the same in either form.

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/eval/relation_metric.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"

namespace vdtnav::eval {

/// The χ²(3) 95 % quantile: a consistent estimator's relation NEES falls below it 95 % of the time.
inline constexpr double kChi2Dof3P95 = kChi2P95[2];

/// \brief The relative pose δ = x_i⁻¹ ⊕ x_j and its Jacobians (1), (3).
struct RelativePoseJacobians {
  Pose2 delta = Pose2::Zero();                       ///< δ, yaw wrapped
  Eigen::Matrix3d d_from = Eigen::Matrix3d::Zero();  ///< J_i = ∂δ/∂x_i
  Eigen::Matrix3d d_to = Eigen::Matrix3d::Zero();    ///< J_j = ∂δ/∂x_j
};

/// \return δ = between(from, to) with its Jacobians w.r.t. the (x, y, yaw) of `from` and `to`.
[[nodiscard]] RelativePoseJacobians relative_pose_jacobians(const Pose2& from, const Pose2& to);

/// \return Σ_rel = J_i Σ_i J_iᵀ + J_j Σ_j J_jᵀ (2), the covariance of between(from, to) when the
/// two estimates' errors are independent.
[[nodiscard]] Eigen::Matrix3d relative_pose_covariance(const Pose2& from, const Pose2& to,
                                                       const Eigen::Matrix3d& cov_from,
                                                       const Eigen::Matrix3d& cov_to);

/// \return the NEES (5) of the relative pose between(from, to) against the true one: e =
/// pose_error(between(from, to), true_delta), Σ_rel by (2). NaN when Σ_rel is not positive
/// definite or an input is not finite.
[[nodiscard]] double relation_nees(const Pose2& from, const Pose2& to,
                                   const Eigen::Matrix3d& cov_from, const Eigen::Matrix3d& cov_to,
                                   const Pose2& true_delta);

/// \brief How the relation NEES of a trajectory is taken.
struct RelationNeesOptions {
  /// An estimate sample within this many seconds of t1 (t2) is the pose at that end (the closest
  /// one). No interpolation: the covariance belongs to a sample.
  double stamp_tolerance = 1e-6;
  double bound = kChi2Dof3P95;  ///< the fraction of relations with NEES <= bound is reported
};

/// \brief The relation NEES over a set of relations.
struct RelationNeesResult {
  std::size_t used = 0;                   ///< relations with a finite NEES
  std::size_t skipped_no_stamp = 0;       ///< an end is no estimate sample (stamp_tolerance)
  std::size_t skipped_no_covariance = 0;  ///< an end's covariance is missing (not finite)
  std::size_t skipped_singular = 0;       ///< Σ_rel not positive definite
  double mean = 0.0;                      ///< mean NEES (0 when used == 0)
  double median = 0.0;                    ///< median NEES (0 when used == 0)
  double fraction_inside = 0.0;           ///< fraction of the used NEES <= bound
  std::vector<double> values;             ///< one per relation, NaN where skipped, input order

  [[nodiscard]] bool ok() const noexcept { return used > 0; }
};

/// \brief The relation NEES of `estimate` whose sample k has covariance `covariances[k]` (a
/// non-finite matrix where the estimator gave none).
/// \throws ConfigError for an invalid trajectory (check_trajectory), covariances.size() !=
/// estimate.size(), non-finite relations, or a negative/NaN stamp_tolerance or bound.
[[nodiscard]] RelationNeesResult relation_nees(const Trajectory2& estimate,
                                               const std::vector<Eigen::Matrix3d>& covariances,
                                               const std::vector<Relation>& relations,
                                               const RelationNeesOptions& options = {});

}  // namespace vdtnav::eval
