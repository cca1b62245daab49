#include "vdtnav/estimation/vdt_optimizer.hpp"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Cholesky>

#include "vdtnav/core/error.hpp"

namespace vdtnav {
namespace {

/// All inlier beams of a scan as one residual block (2 residuals per beam, pose x, y, phi).
class ScanCost final : public ceres::CostFunction {
 public:
  /// \param sqrt_weights per-beam IRLS weights sqrt(w_i) (empty: all 1).
  ScanCost(const VdtSensorModel& model, const ScanPoints& scan, std::vector<int> beams,
           std::vector<double> sqrt_weights = {})
      : model_(model), scan_(scan), beams_(std::move(beams)), sqrt_w_(std::move(sqrt_weights)) {
    set_num_residuals(2 * static_cast<int>(beams_.size()));
    mutable_parameter_block_sizes()->push_back(3);
  }
  bool Evaluate(double const* const* params, double* residuals, double** jacobians) const override {
    const Pose2 pose(params[0][0], params[0][1], params[0][2]);
    const double c = std::cos(pose[2]), s = std::sin(pose[2]);
    const bool want_jacobian = jacobians != nullptr && jacobians[0] != nullptr;
    for (std::size_t k = 0; k < beams_.size(); ++k) {
      const int i = beams_[k];
      const double w = sqrt_w_.empty() ? 1.0 : sqrt_w_[k];
      if (!want_jacobian) {  // trial steps: the value-only lookup is about half the work
        const Eigen::Vector2d d = model_.disparity_value(pose, c, s, scan_.points[i], nullptr);
        residuals[2 * k] = w * d.x();
        residuals[2 * k + 1] = w * d.y();
        continue;
      }
      const BeamDisparity b = model_.disparity(pose, c, s, scan_.points[i], scan_.directions[i]);
      residuals[2 * k] = w * b.d.x();
      residuals[2 * k + 1] = w * b.d.y();
      double* j = jacobians[0] + 6 * k;  // row-major 2x3
      for (int col = 0; col < 3; ++col) {
        j[col] = w * b.d_pose(0, col);
        j[3 + col] = w * b.d_pose(1, col);
      }
    }
    return true;
  }

 private:
  const VdtSensorModel& model_;
  const ScanPoints& scan_;
  std::vector<int> beams_;
  std::vector<double> sqrt_w_;
};

/// One beam as a residual block, for robust losses (which apply per block).
class BeamCost final : public ceres::SizedCostFunction<2, 3> {
 public:
  BeamCost(const VdtSensorModel& model, const Eigen::Vector2d& p, const Eigen::Vector2d& u)
      : model_(model), p_(p), u_(u) {}
  bool Evaluate(double const* const* params, double* residuals, double** jacobians) const override {
    const BeamDisparity b =
        model_.disparity(Pose2(params[0][0], params[0][1], params[0][2]), p_, u_);
    residuals[0] = b.d.x();
    residuals[1] = b.d.y();
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      for (int c = 0; c < 3; ++c) {
        jacobians[0][c] = b.d_pose(0, c);
        jacobians[0][3 + c] = b.d_pose(1, c);
      }
    }
    return true;
  }

 private:
  const VdtSensorModel& model_;
  Eigen::Vector2d p_, u_;
};

ceres::LossFunction* make_loss(RobustLoss loss, double scale) {
  switch (loss) {
    case RobustLoss::kHuber:
      return new ceres::HuberLoss(scale);
    case RobustLoss::kCauchy:
      return new ceres::CauchyLoss(scale);
    case RobustLoss::kNone:
      return nullptr;
  }
  return nullptr;
}

/// IRLS weight rho'(s) of a beam with squared disparity s (1 without a robust loss).
double loss_weight(RobustLoss loss, double scale, double s) {
  const double b = scale * scale;
  switch (loss) {
    case RobustLoss::kHuber:
      return s <= b ? 1.0 : std::sqrt(b / s);
    case RobustLoss::kCauchy:
      return 1.0 / (1.0 + s / b);
    case RobustLoss::kNone:
      return 1.0;
  }
  return 1.0;
}

}  // namespace

VdtOptimizer::VdtOptimizer(const VdtMap2& map, const VdtOptimizerOptions& options)
    : model_(map, options.sensor), options_(options) {
  VDTNAV_CHECK(options.max_iterations >= 1, "optimizer: max_iterations must be >= 1");
  VDTNAV_CHECK(options.gate_rounds >= 1, "optimizer: gate_rounds must be >= 1");
  VDTNAV_CHECK(options.min_inliers >= 3, "optimizer: min_inliers must be >= 3 (3 unknowns)");
  VDTNAV_CHECK(options.loss_scale > 0.0, "optimizer: loss_scale must be > 0");
  VDTNAV_CHECK(options.pyramid_levels >= 0, "optimizer: pyramid_levels must be >= 0");
  // Occupancy of the map: the cells that are their own nearest feature.
  const auto& nearest = map.nearest_cells();
  for (int level = options.pyramid_levels; level >= 1; --level) {
    const int f = 1 << level;
    const Eigen::Vector2i size = ((nearest.size().array() + f - 1) / f).max(2);
    OccupancyGrid<2> coarse(
        size, GridFrame<2>(map.resolution() * f, map.frame().origin(), map.frame().yaw()), 0);
    for (std::size_t c = 0; c < nearest.num_cells(); ++c) {
      if (nearest[c] == static_cast<std::int32_t>(c))
        coarse(nearest.index_of(static_cast<std::ptrdiff_t>(c)) / f) = 1;
    }
    coarse_maps_.push_back(std::make_unique<VdtMap2>(VdtMap2::build(coarse)));
    VdtSensorModelOptions so = options.sensor;
    so.gate = std::max(options.sensor.gate, 4.0 * map.resolution() * f);
    coarse_models_.emplace_back(*coarse_maps_.back(), so);
  }
}

namespace {

/// The Ceres settings of every solve here: 3 unknowns, one dense block, one thread, silent. The
/// map stores float coefficients, so costs are known to ~1e-7 relative: ask no more.
ceres::Solver::Options solver_options(TrustRegion trust_region, int max_iterations) {
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
  so.jacobi_scaling = false;
  so.trust_region_strategy_type =
      trust_region == TrustRegion::kDogleg ? ceres::DOGLEG : ceres::LEVENBERG_MARQUARDT;
  so.max_num_iterations = max_iterations;
  so.function_tolerance = 1e-6;
  so.gradient_tolerance = 1e-10;
  so.parameter_tolerance = 1e-6;  // relative: ~10 micrometres at 10 m from the origin
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  return so;
}

/// One Ceres solve of the beams in `beams` from x (updated in place).
ceres::Solver::Summary run_solver(const VdtSensorModel& model, const ScanPoints& scan,
                                  const std::vector<int>& beams, RobustLoss loss, double loss_scale,
                                  TrustRegion trust_region, int max_iterations, double* x) {
  ceres::Problem::Options po;
  po.disable_all_safety_checks = true;
  ceres::Problem problem(po);
  if (loss == RobustLoss::kNone) {
    problem.AddResidualBlock(new ScanCost(model, scan, beams), nullptr, x);
  } else {
    for (int i : beams) {
      problem.AddResidualBlock(new BeamCost(model, scan.points[i], scan.directions[i]),
                               make_loss(loss, loss_scale), x);
    }
  }
  const ceres::Solver::Options so = solver_options(trust_region, max_iterations);
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  return summary;
}

/// Iteratively reweighted least squares with a Cauchy loss of the given scale on one residual
/// block (fast: Ceres's per-block overhead is paid once, not per beam): each pass fixes the
/// weights w_i = 1 / (1 + |d_i|^2 / scale^2) at the current estimate and solves.
void solve_cauchy_irls(const VdtSensorModel& model, const ScanPoints& scan,
                       const std::vector<int>& beams, double scale, TrustRegion trust_region,
                       int max_iterations, int passes, double* x) {
  std::vector<double> sqrt_w(beams.size());
  for (int pass = 0; pass < passes; ++pass) {
    const Pose2 at(x[0], x[1], x[2]);
    for (std::size_t k = 0; k < beams.size(); ++k) {
      const int i = beams[k];
      const double s2 = model.disparity(at, scan.points[i], scan.directions[i]).d.squaredNorm();
      sqrt_w[k] = std::sqrt(loss_weight(RobustLoss::kCauchy, scale, s2));
    }
    ceres::Problem::Options po;
    po.disable_all_safety_checks = true;
    ceres::Problem problem(po);
    problem.AddResidualBlock(new ScanCost(model, scan, beams, sqrt_w), nullptr, x);
    const ceres::Solver::Options so = solver_options(trust_region, max_iterations);
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
  }
}

}  // namespace

LocalizationResult VdtOptimizer::solve(const ScanPoints& scan, const Pose2& guess) const {
  LocalizationResult result;
  result.pose = guess;
  result.dropped = static_cast<int>(scan.dropped_not_finite + scan.dropped_out_of_range);
  double x[3] = {guess[0], guess[1], guess[2]};
  const double alpha = options_.sensor.gate;

  // Coarse alignment, only when the guess is poor (median disparity > 10 cm, e.g. after a kidnap
  // or a bad odometry step): a wide gate and a Cauchy loss first pull the scan into the basin of
  // the right walls without letting far, wrongly associated beams dominate.
  {
    std::vector<double> norms;
    std::vector<int> wide;
    for (std::size_t i = 0; i < scan.size(); ++i) {
      const BeamDisparity b = model_.disparity(guess, scan.points[i], scan.directions[i]);
      if (!b.inside) continue;
      norms.push_back(b.d.norm());
      if (b.d.norm() < std::max(1.0, 2.0 * alpha)) wide.push_back(static_cast<int>(i));
    }
    if (norms.size() >= static_cast<std::size_t>(options_.min_inliers)) {
      std::nth_element(norms.begin(), norms.begin() + norms.size() / 2, norms.end());
      if (norms[norms.size() / 2] > 0.1) {
        for (const VdtSensorModel& coarse : coarse_models_) {
          std::vector<int> beams;
          const Pose2 at(x[0], x[1], x[2]);
          for (std::size_t i = 0; i < scan.size(); ++i) {
            if (coarse.disparity(at, scan.points[i], scan.directions[i]).inlier)
              beams.push_back(static_cast<int>(i));
          }
          if (beams.size() < static_cast<std::size_t>(options_.min_inliers)) continue;
          solve_cauchy_irls(coarse, scan, beams, coarse.options().gate / 4, options_.trust_region,
                            options_.max_iterations, 3, x);
        }
        solve_cauchy_irls(model_, scan, wide, 0.1, options_.trust_region, options_.max_iterations,
                          3, x);
      }
    }
  }

  std::vector<char> inlier(scan.size(), 0);
  bool converged = false;
  for (int round = 0; round < options_.gate_rounds; ++round) {
    // Gate (3.3) at the current estimate.
    const Pose2 at(x[0], x[1], x[2]);
    std::vector<int> beams;
    int changed = 0;
    const double c = std::cos(at[2]), s = std::sin(at[2]);
    for (std::size_t i = 0; i < scan.size(); ++i) {
      bool in = false;
      (void)model_.disparity_value(at, c, s, scan.points[i], &in);
      changed += (in != (inlier[i] != 0)) ? 1 : 0;
      inlier[i] = in ? 1 : 0;
      if (in) beams.push_back(static_cast<int>(i));
    }
    // Solve again only if the gate changed its mind about more than 1 % of the beams.
    if (round > 0 && changed * 100 <= static_cast<int>(beams.size())) break;
    result.inliers = static_cast<int>(beams.size());
    result.dropped =
        static_cast<int>(scan.size() + scan.dropped_not_finite + scan.dropped_out_of_range) -
        result.inliers;
    if (result.inliers < options_.min_inliers) {
      result.status = LocalizationStatus::kTooFewObservations;
      result.pose = guess;
      return result;
    }
    const ceres::Solver::Summary summary =
        run_solver(model_, scan, beams, options_.loss, options_.loss_scale, options_.trust_region,
                   options_.max_iterations, x);
    result.iterations += static_cast<int>(summary.iterations.size());
    result.final_cost = 2.0 * summary.final_cost;  // Ceres reports sum/2: d_VCD = sum |d|^2
    if (summary.termination_type == ceres::FAILURE || !std::isfinite(summary.final_cost)) {
      result.status = LocalizationStatus::kDiverged;
      result.pose = guess;
      return result;
    }
    converged = summary.termination_type == ceres::CONVERGENCE;
  }
  result.pose = Pose2(x[0], x[1], wrap_angle(x[2]));
  result.status = converged ? LocalizationStatus::kConverged : LocalizationStatus::kNotConverged;
  // The covariance is reported whenever the Hessian at the estimate is positive definite, also
  // when Ceres stopped at its iteration limit (the status says so); otherwise it is not a minimum.
  result.has_covariance = covariance(scan, result.pose, inlier, &result.covariance);
  if (!result.has_covariance) result.status = LocalizationStatus::kNotConverged;
  return result;
}

bool VdtOptimizer::covariance(const ScanPoints& scan, const Pose2& pose,
                              const std::vector<char>& inliers, Eigen::Matrix3d* cov) const {
  const double s2 = scan.sigma_range * scan.sigma_range;
  const double m2 = model_.map_sigma() * model_.map_sigma();
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero(), middle = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!inliers[i]) continue;
    if (options_.covariance == CovarianceMethod::kImplicitFunction) {
      BeamCurvature c;
      const BeamDisparity b = model_.disparity(pose, scan.points[i], scan.directions[i], &c);
      const double w = loss_weight(options_.loss, options_.loss_scale, b.d.squaredNorm());
      h += w * c.hessian;                                        // (3.6), of d_VCD / 2
      middle += (w * w * s2) * c.cross * c.cross.transpose();    // range noise via (3.5)
      middle += (w * w * m2) * b.d_pose.transpose() * b.d_pose;  // map-noise floor
    } else {
      const BeamDisparity b = model_.disparity(pose, scan.points[i], scan.directions[i]);
      const double w = loss_weight(options_.loss, options_.loss_scale, b.d.squaredNorm());
      h += w * b.d_pose.transpose() * b.d_pose;
      middle += (w * w) * b.d_pose.transpose() * model_.disparity_covariance(b, scan.sigma_range) *
                b.d_pose;
    }
  }
  const Eigen::LLT<Eigen::Matrix3d> llt(h);
  if (llt.info() != Eigen::Success) return false;
  const Eigen::Matrix3d h_inv = llt.solve(Eigen::Matrix3d::Identity());
  *cov = h_inv * middle * h_inv;  // (3.4) with J = -H^{-1} d^2(d_VCD/2)/dX dr
  *cov = 0.5 * (*cov + cov->transpose());
  if (options_.variance_factor && m2 > 0.0) {
    // A posteriori variance factor of the weighted residuals (chi^2 / degrees of freedom).
    double chi2 = 0.0;
    int n = 0;
    const double c = std::cos(pose[2]), s = std::sin(pose[2]);
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (!inliers[i]) continue;
      const BeamDisparity b = model_.disparity(pose, c, s, scan.points[i], scan.directions[i]);
      chi2 += b.d.dot(model_.disparity_covariance(b, scan.sigma_range).ldlt().solve(b.d));
      ++n;
    }
    const double factor = n > 2 ? chi2 / (2.0 * n - 3.0) : 1.0;
    if (factor > 1.0) *cov *= factor;
  }
  return cov->allFinite();
}

VdtOptimizationLocalizer::VdtOptimizationLocalizer(const VdtMap2& map,
                                                   const VdtOptimizerOptions& options,
                                                   std::string name)
    : optimizer_(map, options), name_(std::move(name)) {}

void VdtOptimizationLocalizer::reset(const Pose2& pose, const Eigen::Matrix3d& /*covariance*/) {
  pose_ = pose;
}

LocalizationResult VdtOptimizationLocalizer::update(const OdometryStep& odometry,
                                                    const LaserScan& scan) {
  const Pose2 guess = compose(pose_, odometry.delta);  // UPDATEGUESS
  LocalizationResult r = optimizer_.solve(scan_points(scan), guess);
  if (r.status == LocalizationStatus::kConverged || r.status == LocalizationStatus::kNotConverged) {
    pose_ = r.pose;
  } else {
    pose_ = guess;
    r.pose = guess;
  }
  return r;
}

}  // namespace vdtnav
