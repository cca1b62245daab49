#pragma once
/// \file
/// \brief Pose estimation by non-linear least squares on the VDT (thesis 3.2, Algorithm 1), with
/// the pose covariance from the implicit function theorem (3.4)-(3.6) as corrected in SPEC, for
/// 3-DOF planar poses (VdtOptimizer) and 6-DOF SE(3) poses (VdtOptimizer3, thesis 3.4.4) from one
/// estimator template VdtOptimizerT<Dim>.
///
/// The estimate minimises d_VCD = sum_i |d_i|^2 (2.17) over the gated beams (3.3). At the minimum
/// the gradient g(X, r) = sum_i J_i^T d_i vanishes, so dX/dr = -H^{-1} dg/dr with H the *full*
/// Hessian of d_VCD/2 (Gauss-Newton term plus the curvature of the interpolated VDT) and
/// dg/dr_i the cross derivative (SPEC: the Hessian and cross derivative of the scalar cost, not of
/// the vector d_VDT). Then
///   cov(X) = H^{-1} [ sum_i sigma_r^2 b_i b_i^T + sum_i J_i^T sigma_map^2 J_i ] H^{-1}   (3.4)
/// where b_i = d^2(d_VCD/2)/dX dr_i and the second term is the map-noise floor.
///
/// In 3D the pose is one Ceres parameter block of 7 numbers (quaternion, translation) on the
/// manifold Se3LeftManifold (left perturbation, se3_manifold.hpp); X, H and cov are in its tangent
/// (dt, dtheta), world frame. The 4-DOF mode (VdtOptimizerOptions::four_dof) uses Se3YawManifold:
/// x, y, z and yaw about the world z axis are estimated, roll and pitch stay exactly those of the
/// guess (e.g. from an IMU), and the covariance is the 4 x 4 block of (dt, dtheta_z) embedded in
/// the 6 x 6 matrix with zero rows and columns for dtheta_x, dtheta_y.

#include <memory>
#include <string>
#include <vector>

#include "vdtnav/core/traits.hpp"
#include "vdtnav/estimation/guess_search.hpp"
#include "vdtnav/estimation/local_scan_map.hpp"
#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/sensor/vdt_sensor_model.hpp"

namespace vdtnav {

/// \brief Which solver minimises the cost of one observation set.
enum class ScanSolver {
  kCeres,  ///< Ceres Solver, one dense residual block, trust region `trust_region`
  /// Levenberg-Marquardt on the fixed-size normal equations, the Jacobians accumulated in one
  /// pass over the readings (scan_lm.hpp): Ceres's LM steps and stopping rules without its
  /// general machinery, 1.5-2.5x faster per solve for 3 to 6 unknowns, the same optimum and
  /// covariance (tested). The default.
  kDense,
};
/// \brief Ceres trust-region strategy (ScanSolver::kCeres; the dense solver is LM).
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
  ScanSolver solver = ScanSolver::kDense;
  TrustRegion trust_region = TrustRegion::kLevenbergMarquardt;
  RobustLoss loss = RobustLoss::kNone;
  double loss_scale = 0.05;  ///< metres: where the robust loss departs from quadratic
  CovarianceMethod covariance = CovarianceMethod::kImplicitFunction;
  int max_iterations = 25;
  /// Ceres's function tolerance (solver ceres only): a solve stops when a step changes the cost by
  /// less than this fraction of it. The dense solver stops by its convergence test (step_sigma).
  double function_tolerance = 1e-6;
  /// The convergence test of the dense solver (scan_lm.hpp (C)): a solve is converged, and stops,
  /// when its Newton step is at most this many of the pose's standard deviations, measured under
  /// sigma^2 H^-1 with sigma the a priori disparity noise (map floor and reading noise). The
  /// status converged means this test held; 0.01 leaves an error of a hundredth of the reported
  /// uncertainty.
  double step_sigma = 0.01;
  /// The dense solver's steps on Newton's curvature of the robust VCD, the robust loss's
  /// second-order term and the field's curvature (scan_lm.hpp (K)); false: the IRLS matrix alone
  /// (what Ceres uses; linear convergence where readings sit near the loss scale or walls are
  /// thick, so more iterations reach the same test).
  bool newton = true;
  /// The lowest floor of the step's curvature relative to the IRLS matrix (scan_lm.hpp (K)),
  /// which follows the measured curvature down from 1/4 while the steps fall short (gain ratio
  /// above 1.25); 1/4: a fixed floor. < 0: 1/4 in 2D, 1/64 in 3D — a real 3D scan half explained
  /// under the Cauchy loss is 0.002-0.2 times as curved as the IRLS matrix in every direction
  /// (Riverside: 34 iterations a scan at 1/4, 11 at 1/64); on the Intel log the lower floor
  /// moved the relations 0.0291 m / 0.437 deg -> 0.0306 / 0.496 (issue 57's note).
  double newton_floor = -1.0;
  int gate_rounds = 3;   ///< re-gate at the solution and solve again while the inliers change
  int min_inliers = 10;  ///< fewer usable beams: kTooFewObservations
  /// Coarse-to-fine levels used when the guess is poor (median disparity > coarse_threshold): the
  /// map is also built at resolution x 2^k, k = levels .. 1, and solved there first with a wide
  /// gate and a Cauchy loss (IRLS: 3 passes per level in 2D, 1 in 3D), which widens the basin of
  /// convergence past thin structures. < 0: the dimension's default, 2 in 2D, 3 in 3D (0.1, 0.2
  /// and 0.4 m for a 0.05 m map, about 1/7 of its memory: the 0.4 m level doubles the share of
  /// sparse clouds that reach the basin from Table 3.4's scenario B).
  int pyramid_levels = -1;
  /// Median disparity at the guess, metres, above which the coarse-to-fine alignment runs.
  /// < 0: the dimension's default, 0.1 m in 2D; 0 in 3D, where it always runs: from Table 3.4's
  /// scenarios A and B (median disparity 4-9 cm) the fine level alone can stop in a local minimum
  /// (2-6 cm, 7-50 mrad off on the test clouds) and the coarse passes cost about what they save.
  double coarse_threshold = -1.0;
  /// Scale the covariance by the a posteriori variance factor s^2 = sum_i d_i^T R_i^-1 d_i /
  /// (Dim n - DoF) when it exceeds 1 (R_i: disparity covariance with the map floor): the residuals
  /// themselves say when the map is rougher than the floor assumes.
  bool variance_factor = false;
  /// 3D only (ignored in 2D): the 4-DOF mode, x, y, z and yaw estimated, roll and pitch held at
  /// those of the guess (from an IMU), as DLL does.
  bool four_dof = false;
  /// The localizers (2D vdt-opt and the sequential 3D one): fuse the prediction (the last
  /// estimate composed with the odometry step, with its propagated covariance) as a prior term of
  /// the cost, a maximum a posteriori solve, and report the posterior covariance. Directions the
  /// scan does not constrain (one straight wall, one marking line) then stay at the prediction
  /// instead of sliding wherever the iterations stop. Off: each scan on its own (maximum
  /// likelihood, the thesis's vdt-opt).
  bool odometry_prior = false;
  /// 2D localizer only: when the solution from the odometry guess explains the scan poorly, also
  /// solve from the best pose of a window search around the guess and keep the better; refuse a
  /// solution that leaves the scan unexplained (the guess is kept, status kRefused).
  GuessSearchOptions search;
  /// 2D localizer only: when the map does not explain a scan, match it against the recent scans
  /// instead of keeping the bare odometry guess (see local_scan_map.hpp).
  LocalScanMapOptions bridge;
};

/// \brief vdt-opt's defaults: what the localizers' constructors, LocalizerSettings{},
/// `vdtnav localize` / `localize3d`, the Python module and the ROS node run without a settings
/// file. The map is one drawn from real scans (the maps users have): a Cauchy loss (scale
/// 0.05 m) against what the map lacks or misplaces, up to 50 iterations (the IRLS passes need more
/// than the 25 of an exact map), the map errors shared by the readings of each square (2D: 2 m,
/// walls) or cube (3D: 1 m) with the map builder's pose error at half a cell
/// (VdtSensorModelOptions::map_correlation_length, map_pose_sigma); in 2D the window search on
/// every scan explained below 95 %; in 3D the covariance scaled by the a posteriori variance
/// factor. VdtOptimizerOptions{} itself is the thesis's solver on an exact map (the generated
/// studies' exact_map_settings()). Measured: docs/localization-2d.md (Intel) and
/// docs/localization-3d.md (the real car pair).
/// \param dimension 2 (LiDAR scans on a 2D map) or 3 (clouds on a 3D map).
[[nodiscard]] VdtOptimizerOptions vdt_opt_defaults(int dimension);

/// \brief A Gaussian prior on the pose: the cost gains 1/2 e^T information e, e = X (-) mean in the
/// perturbation of PoseTraits<Dim> (2D: additive with the angle wrapped).
template <int Dim>
struct PosePrior {
  typename PoseTraits<Dim>::Pose mean = PoseTraits<Dim>::identity();
  typename PoseTraits<Dim>::Covariance information = PoseTraits<Dim>::Covariance::Zero();
};

/// \brief Algorithm 1's OPTIMIZE: one observation set against the map from an initial guess
/// (aliases VdtOptimizer for 2D, VdtOptimizer3 for 3D).
template <int Dim>
class VdtOptimizerT {
 public:
  using Traits = PoseTraits<Dim>;
  using Pose = typename Traits::Pose;
  using Covariance = typename Traits::Covariance;
  using Map = VdtMap<Dim>;
  using Field = VdtField<Dim>;
  using Observations = ObservationSet<Dim>;
  using SensorModel = VdtSensorModelT<Dim>;
  using Result = LocalizationResultT<Dim>;

  /// \brief An optimizer on a VDT map: the dense VdtMap, or a SparseVdtMap3 (a building-sized
  /// map), which has no coarse levels (pyramid_levels is taken as 0: the guess must be within the
  /// fine level's basin, or use solve_multi_start). The map must outlive the optimizer.
  /// \throws ConfigError for invalid options.
  VdtOptimizerT(const Field& map, const VdtOptimizerOptions& options = {});
  /// \brief An optimizer on `other`'s map with other options (the 4-DOF mode next to the 6-DOF
  /// one, another loss, ...), sharing its coarse levels when the pyramid_levels agree: a
  /// map's pyramid is built once however many optimizers use it.
  /// \throws ConfigError for invalid options.
  VdtOptimizerT(const VdtOptimizerT& other, const VdtOptimizerOptions& options);

  /// \brief Minimises d_VCD from `guess`; fills the covariance when the estimate is a minimum
  /// (positive definite Hessian), with status kNotConverged if Ceres hit its iteration limit.
  [[nodiscard]] Result solve(const Observations& observations, const Pose& guess) const;

  /// \brief As solve(observations, guess) with a prior term in every solve (a maximum a
  /// posteriori estimate). The solvers minimise the plain VCD, so the prior joins it as
  /// s^2/2 e^T I e, s^2 the a priori variance of a disparity component (map floor + reading
  /// noise); the covariance is the posterior's, A^-1 (M + s^4 I) A^-1 with A = H + s^2 I. The
  /// same prior in 2D and 3D (e = X (-) mean in the pose traits' perturbation); in the 4-DOF mode
  /// its held rows and columns do nothing (the step keeps them).
  [[nodiscard]] Result solve(const Observations& observations, const Pose& guess,
                             const PosePrior<Dim>& prior) const;

  /// \brief The pose covariance at `pose` over the readings flagged in `inliers` (in the 4-DOF
  /// mode with zero rows and columns for dtheta_x, dtheta_y).
  /// \return false when the Hessian is not positive definite (not a minimum).
  [[nodiscard]] bool covariance(const Observations& observations, const Pose& pose,
                                const std::vector<char>& inliers, Covariance* cov) const;

  [[nodiscard]] const SensorModel& sensor_model() const noexcept { return model_; }
  [[nodiscard]] const VdtOptimizerOptions& options() const noexcept { return options_; }
  /// \return whether pose component k of the tangent is estimated (false: held, 4-DOF mode).
  [[nodiscard]] bool is_free(int k) const noexcept;

 private:
  /// solve() with an optional prior, its information already in VCD units (times prior_s2).
  [[nodiscard]] Result solve_with(const Observations& observations, const Pose& guess,
                                  const PosePrior<Dim>* prior, double prior_s2) const;
  /// covariance() with the readings visited in `order` (see src/estimation/lookup_order.cpp),
  /// with the prior's information in VCD units (times prior_s2) when there is one.
  [[nodiscard]] bool covariance(const Observations& observations, const Pose& pose,
                                const std::vector<char>& inliers, const std::vector<int>& order,
                                const Covariance* prior_information, double prior_s2,
                                Covariance* cov) const;

  void validate_and_default();
  /// The coarse levels, resolution x 2^k for k = levels .. 1 (coarsest first).
  [[nodiscard]] static std::shared_ptr<const std::vector<std::unique_ptr<Map>>> build_pyramid(
      const Field& map, int levels);
  void make_coarse_models();

  SensorModel model_;
  VdtOptimizerOptions options_;
  std::shared_ptr<const std::vector<std::unique_ptr<Map>>> coarse_maps_;  // coarsest first, shared
  std::vector<SensorModel> coarse_models_;
};

extern template class VdtOptimizerT<2>;
extern template class VdtOptimizerT<3>;

using VdtOptimizer = VdtOptimizerT<2>;
using VdtOptimizer3 = VdtOptimizerT<3>;

/// \brief Algorithm 1 as a localizer: the next guess is the last estimate composed with the
/// odometry increment (UPDATEGUESS), then OPTIMIZE. Name "vdt-opt".
class VdtOptimizationLocalizer final : public Localizer2D {
 public:
  VdtOptimizationLocalizer(const VdtMap2& map,
                           const VdtOptimizerOptions& options = vdt_opt_defaults(2),
                           std::string name = "vdt-opt");
  void reset(const Pose2& pose, const Eigen::Matrix3d& covariance) override;
  using Localizer2D::update;
  [[nodiscard]] LocalizationResult update(const OdometryStep& odometry,
                                          const ScanPoints& observations) override;
  [[nodiscard]] std::string name() const override { return name_; }

 private:
  VdtOptimizer optimizer_;
  Pose2 pose_ = Pose2::Zero();
  /// The uncertainty of the next guess: the last accepted estimate's covariance, propagated
  /// with the odometry noise of options().search while updates are refused; it sizes the
  /// window search (guess_search.hpp).
  Eigen::Matrix3d uncertainty_ = Eigen::Matrix3d::Zero();
  LocalScanMap local_;   ///< the recent scans, for the gaps of the map
  bool in_gap_ = false;  ///< the last update was refused (the map did not explain its scan)
  std::string name_;
};

}  // namespace vdtnav
