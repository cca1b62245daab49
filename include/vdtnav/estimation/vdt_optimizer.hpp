#pragma once
/// \file
/// \brief Pose estimation by non-linear least squares on the VDT (thesis 3.2, Algorithm 1), with
/// the pose covariance from the implicit function theorem (3.4)-(3.6) as corrected in SPEC.
///
/// The estimate minimises d_VCD = sum_i |d_i|^2 (2.17) over the gated beams (3.3). At the minimum
/// the gradient g(X, r) = sum_i J_i^T d_i vanishes, so dX/dr = -H^{-1} dg/dr with H the *full*
/// Hessian of d_VCD/2 (Gauss-Newton term plus the curvature of the interpolated VDT) and
/// dg/dr_i the cross derivative (SPEC: the Hessian and cross derivative of the scalar cost, not of
/// the vector d_VDT). Then
///   cov(X) = H^{-1} [ sum_i sigma_r^2 b_i b_i^T + sum_i J_i^T sigma_map^2 J_i ] H^{-1}   (3.4)
/// where b_i = d^2(d_VCD/2)/dX dr_i and the second term is the map-noise floor.

#include <memory>
#include <string>
#include <vector>

#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/sensor/vdt_sensor_model.hpp"

namespace vdtnav {

/// \brief Ceres trust-region strategy.
enum class TrustRegion { kLevenbergMarquardt, kDogleg };
/// \brief Loss on each beam's squared disparity (besides the hard gate).
enum class RobustLoss { kNone, kHuber, kCauchy };
/// \brief How the pose covariance is computed.
enum class CovarianceMethod {
  kImplicitFunction,  ///< (3.4)-(3.6) corrected: full Hessian and cross derivative
  kGaussNewton,       ///< sandwich (J^T J)^-1 J^T Sigma_d J (J^T J)^-1 with Sigma_d per beam
};

/// \brief Options of the optimization localizer.
struct VdtOptimizerOptions {
  VdtSensorModelOptions sensor;
  TrustRegion trust_region = TrustRegion::kLevenbergMarquardt;
  RobustLoss loss = RobustLoss::kNone;
  double loss_scale = 0.05;  ///< metres: where the robust loss departs from quadratic
  CovarianceMethod covariance = CovarianceMethod::kImplicitFunction;
  int max_iterations = 25;
  int gate_rounds = 3;   ///< re-gate at the solution and solve again while the inliers change
  int min_inliers = 10;  ///< fewer usable beams: kTooFewObservations
  /// Coarse-to-fine levels used when the guess is poor (median disparity > 10 cm): the map is
  /// also built at resolution x 2^k, k = levels .. 1, and solved there first with a wide gate and a
  /// Cauchy loss, which widens the basin of convergence past thin structures.
  int pyramid_levels = 2;
  /// Scale the covariance by the a posteriori variance factor s^2 = sum_i d_i^T R_i^-1 d_i /
  /// (2n - 3) when it exceeds 1 (R_i: disparity covariance with the map floor): the residuals
  /// themselves say when the map is rougher than the floor assumes.
  bool variance_factor = false;
};

/// \brief Algorithm 1's OPTIMIZE: one scan against the map from an initial guess.
class VdtOptimizer {
 public:
  /// \throws ConfigError for invalid options.
  VdtOptimizer(const VdtMap2& map, const VdtOptimizerOptions& options = {});

  /// \brief Minimises d_VCD from `guess`; fills the covariance when the estimate is a minimum
  /// (positive definite Hessian), with status kNotConverged if Ceres hit its iteration limit.
  [[nodiscard]] LocalizationResult solve(const ScanPoints& scan, const Pose2& guess) const;

  /// \brief The pose covariance at `pose` over the beams flagged in `inliers`.
  /// \return false when the Hessian is not positive definite (not a minimum).
  [[nodiscard]] bool covariance(const ScanPoints& scan, const Pose2& pose,
                                const std::vector<char>& inliers, Eigen::Matrix3d* cov) const;

  [[nodiscard]] const VdtSensorModel& sensor_model() const noexcept { return model_; }
  [[nodiscard]] const VdtOptimizerOptions& options() const noexcept { return options_; }

 private:
  VdtSensorModel model_;
  VdtOptimizerOptions options_;
  std::vector<std::unique_ptr<VdtMap2>> coarse_maps_;  // coarsest first
  std::vector<VdtSensorModel> coarse_models_;
};

/// \brief Algorithm 1 as a localizer: the next guess is the last estimate composed with the
/// odometry increment (UPDATEGUESS), then OPTIMIZE. Name "vdt-opt".
class VdtOptimizationLocalizer final : public Localizer2D {
 public:
  VdtOptimizationLocalizer(const VdtMap2& map, const VdtOptimizerOptions& options = {},
                           std::string name = "vdt-opt");
  void reset(const Pose2& pose, const Eigen::Matrix3d& covariance) override;
  [[nodiscard]] LocalizationResult update(const OdometryStep& odometry,
                                          const LaserScan& scan) override;
  [[nodiscard]] std::string name() const override { return name_; }

 private:
  VdtOptimizer optimizer_;
  Pose2 pose_ = Pose2::Zero();
  std::string name_;
};

}  // namespace vdtnav
