#pragma once
/// \file
/// \brief The small-problem solver of the optimizer: Levenberg-Marquardt on the fixed-size normal
/// equations of one observation set (3 unknowns in 2D, 6 in 3D, 4 in the 4-DOF mode), with the
/// sensor model's analytic Jacobians accumulated in one pass over the readings. What Ceres does
/// for this problem, without its per-solve and per-iteration machinery (problem construction,
/// program evaluation, Jacobian copies), which dominates for a few unknowns.
///
/// Cost (the one Ceres minimises with the ScanCost block, halved as Ceres reports it):
///   F(X) = 1/2 sum_i w_i^2 rho(|d_i|^2) [+ 1/2 e^T I e]     (rho(s) = s without a robust loss)
/// Gradient and Gauss-Newton matrix, in the pose perturbation of PoseTraits<Dim>:
///   g = sum_i w_i^2 rho'_i J_i^T d_i [+ I e],   H = sum_i w_i^2 rho'_i J_i^T J_i [+ I]
/// (the IRLS weighting; in brackets an optional prior, e = X (-) mean, a PosePrior; the
/// Jacobian of e is taken as the identity: exact in 2D, first order at the mean in 3D).
/// Step: (H + lambda D) delta = -g, D = diag(H) clamped to [1e-6, 1e32] (Ceres's LM), factored by
/// Cholesky and accepted when the cost falls by at least 1e-3 of the model's predicted decrease;
/// lambda = 1 / radius with Ceres's (Nielsen's) radius update. Stops as
/// Ceres does: |F - F_new| <= function_tolerance F, or |delta| <= parameter_tolerance (|x| +
/// parameter_tolerance), or the iteration limit; and, with step_sigma > 0, when the step is far
/// below the pose's own uncertainty (the test of issue 34, in the covariance's scale):
///   delta^T H delta <= step_sigma^2 s^2,   s^2 = 2 F / max(1, m - DoF),   m = Dim x readings,
/// i.e. the step's Mahalanobis length under the Gauss-Newton covariance s^2 H^-1 of (3.4) is at
/// most step_sigma standard deviations; like the parameter tolerance it keeps x. With it comes a
/// line search along the Gauss-Newton direction (below): the steps that each fell short by the
/// same factor, the cost converging linearly over tens of iterations, reach the minimum in a few.

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Cholesky>

#include "vdtnav/core/traits.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/sensor/observation_set.hpp"
#include "vdtnav/sensor/vdt_sensor_model.hpp"

namespace vdtnav::detail {

/// rho'(s) of a robust loss of the given scale (b = scale^2) at the squared disparity s, the IRLS
/// weight: 1 (none), 1 or sqrt(b / s) (Huber), 1 / (1 + s/b) (Cauchy). No logarithm: the weights
/// of the Jacobian passes and of the covariance need only this.
inline double robust_weight(RobustLoss loss, double scale, double s) {
  const double b = scale * scale;
  switch (loss) {
    case RobustLoss::kHuber:
      return s <= b ? 1.0 : std::sqrt(b / s);
    case RobustLoss::kCauchy:
      return 1.0 / (1.0 + s / b);
    case RobustLoss::kNone:
      break;
  }
  return 1.0;
}

/// rho(s) and rho'(s) as Ceres defines them: Huber rho = s (s <= b), 2 sqrt(b s) - b; Cauchy
/// rho = b log(1 + s/b).
struct RobustValue {
  double rho = 0.0, rho1 = 1.0;
};
inline RobustValue robust_value(RobustLoss loss, double scale, double s) {
  const double b = scale * scale;
  const double rho1 = robust_weight(loss, scale, s);
  switch (loss) {
    case RobustLoss::kHuber:
      return {s <= b ? s : 2.0 * std::sqrt(b * s) - b, rho1};
    case RobustLoss::kCauchy:
      return {b * std::log1p(s / b), rho1};
    case RobustLoss::kNone:
      break;
  }
  return {s, rho1};
}

/// The line search's longest step, in Gauss-Newton steps (solve_scan_lm).
inline constexpr double kMaxLineSearchAlpha = 16.0;

/// Limits of one solve.
struct ScanLmSettings {
  int max_iterations = 25;
  double function_tolerance = 1e-6;
  double parameter_tolerance = 1e-6;
  /// Stop when the step is at most this many of the pose's standard deviations (see above);
  /// 0: off (Ceres's tests alone).
  double step_sigma = 0.0;
  /// Components of the perturbation held at zero (the 4-DOF mode's dtheta_x, dtheta_y).
  unsigned held_mask = 0;
};

/// What a solve did (the fields of ceres::Solver::Summary the optimizer reads; the optimizer
/// reports a Ceres solve in the same form).
struct ScanLmSummary {
  int iterations = 0;       ///< evaluations of a step, the start included (Ceres's count)
  double final_cost = 0.0;  ///< F at the returned pose (half the robust VCD)
  bool converged = false;   ///< a tolerance was met (not the iteration limit)
  bool failed = false;      ///< the cost or the normal equations were not finite at the start
};

/// Minimises F over the readings `beams` of `scan` from `pose` (updated in place).
/// \param sqrt_w per-reading weights w_i (empty: all 1), index k of `beams`.
template <int Dim>
ScanLmSummary solve_scan_lm(const VdtSensorModelT<Dim>& model, const ObservationSet<Dim>& scan,
                            const std::vector<int>& beams, const std::vector<double>& sqrt_w,
                            RobustLoss loss, double loss_scale, const ScanLmSettings& settings,
                            typename PoseTraits<Dim>::Pose* pose,
                            const PosePrior<Dim>* prior = nullptr) {
  using Traits = PoseTraits<Dim>;
  using Pose = typename Traits::Pose;
  using Tangent = typename Traits::Tangent;
  using Normal = typename Traits::Covariance;
  constexpr int kDoF = Traits::kDoF;
  const auto weight = [&](std::size_t k) { return sqrt_w.empty() ? 1.0 : sqrt_w[k] * sqrt_w[k]; };
  // Cost and normal equations at X in one batch lookup of the readings (the SIMD kernels: the
  // Jacobian costs little more than the value there, so a trial point gets both, kept when the
  // step is accepted).
  thread_local std::vector<BeamDisparityT<Dim>> disparities;  // scratch: no allocation per solve
  const auto evaluate = [&](const Pose& x, Normal* h, Tangent* g) {
    model.disparities(Traits::rotation(x), Traits::translation(x), scan, &beams, &disparities,
                      DisparityParts::kPose);
    double cost = 0.0;
    h->setZero();
    g->setZero();
    // Unweighted Cauchy: sum_i b log(1 + s_i/b) = b log prod_i (1 + s_i/b), one logarithm per
    // run of factors up to 1e150 instead of one per reading (the log was an eighth of a real-log
    // scan's time). Each factor is >= 1, so the product only grows and cannot underflow.
    const bool cauchy_product = loss == RobustLoss::kCauchy && sqrt_w.empty();
    const double b2 = loss_scale * loss_scale;
    double product = 1.0, log_sum = 0.0;
    for (std::size_t k = 0; k < beams.size(); ++k) {
      const BeamDisparityT<Dim>& b = disparities[k];
      const double s2 = b.d.squaredNorm(), w = weight(k);
      double wr;
      if (cauchy_product) {
        const double f = 1.0 + s2 / b2;
        product *= f;
        if (product > 1e150) {
          log_sum += std::log(product);
          product = 1.0;
        }
        wr = 1.0 / f;  // rho'
      } else {
        const RobustValue rv = robust_value(loss, loss_scale, s2);
        cost += w * rv.rho;
        wr = w * rv.rho1;
      }
      // The lower triangle of the symmetric J^T J only (mirrored once after the pass).
      const auto wj = (wr * b.d_pose).eval();
      for (int c = 0; c < kDoF; ++c) {
        for (int r = c; r < kDoF; ++r) (*h)(r, c) += wj.col(r).dot(b.d_pose.col(c));
      }
      g->noalias() += wj.transpose() * b.d;
    }
    if (cauchy_product) cost += b2 * (log_sum + std::log(product));
    *h = h->template selfadjointView<Eigen::Lower>();
    if (prior != nullptr) {
      const Tangent e = Traits::minus(x, prior->mean);
      cost += e.dot(prior->information * e);  // halved with the rest below
      h->noalias() += prior->information;
      g->noalias() += prior->information * e;
    }
    for (int c = 0; c < kDoF; ++c) {
      if (!(settings.held_mask & (1u << c))) continue;
      h->row(c).setZero();
      h->col(c).setZero();
      (*h)(c, c) = 1.0;
      (*g)[c] = 0.0;
    }
    return 0.5 * cost;
  };
  // |x| of Ceres's parameter tolerance: 2D (x, y, phi); 3D the ambient (unit quaternion, t).
  const auto norm_of = [](const Pose& x) {
    if constexpr (Dim == 2) {
      return x.norm();
    } else {
      return std::sqrt(1.0 + x.translation().squaredNorm());
    }
  };

  ScanLmSummary summary;
  Normal h, h_trial;
  Tangent g, g_trial;
  double cost = evaluate(*pose, &h, &g);
  summary.iterations = 1;
  summary.final_cost = cost;
  if (!std::isfinite(cost) || !h.allFinite() || !g.allFinite()) {
    summary.failed = true;
    return summary;
  }
  // The residual components' degrees of freedom of s^2 (the step test): m - DoF, at least 1.
  const double dof_free =
      std::max(1.0, static_cast<double>(Dim) * static_cast<double>(beams.size()) - kDoF);
  double mu = 1e4;  // Ceres's initial trust-region radius: lambda = 1 / mu
  double nu = 2.0;
  // The step's length along the Gauss-Newton direction (the line search, with step_sigma > 0):
  // the cost's curvature along a step delta is measured by the step itself, from the cost at
  // alpha delta (a quadratic through F(0), its slope g^T delta and F(alpha)):
  //   c = 2 (F(alpha) - F(0) - alpha g^T delta) / alpha^2,   alpha* = -g^T delta / c,
  // and the next step is taken alpha* times as long (clamped to [1, 16]), though no longer than
  // the last accepted step, where the curvature was measured (a longer one could leave the basin
  // the plain steps stay in: two starts then end apart). On the VDT the
  // Gauss-Newton matrix J^T J overstates the curvature of |d|^2 / 2 (the interpolated field's
  // second derivatives, sum_c d_c grad^2 d_c, are negative where the nearest surface point
  // moves with the reading): on the Intel log the cost fell 1.5-1.9 times what the model
  // predicted, step after step, and the steps halved each time. A longer step that does not
  // decrease the cost enough (Armijo: F(alpha) <= F(0) + 1e-4 alpha g^T delta) is dropped for the
  // plain step, and alpha starts over from 1.
  const bool line_search = settings.step_sigma > 0.0;
  double alpha = 1.0;
  double last_m = 1e308;     // the last step in sigmas (the step test); none yet
  double last_length = 0.0;  // the last accepted step's length sqrt(delta^T H delta)
  const auto next_alpha = [](double f0, double f1, double a, double slope) {
    const double c = 2.0 * (f1 - f0 - a * slope) / (a * a);
    return c > 0.0 ? std::clamp(-slope / c, 1.0, kMaxLineSearchAlpha) : kMaxLineSearchAlpha;
  };
  while (summary.iterations < settings.max_iterations + 1) {
    Normal a = h;
    for (int c = 0; c < kDoF; ++c) a(c, c) += std::clamp(h(c, c), 1e-6, 1e32) / mu;
    // Cholesky as Ceres's DENSE_NORMAL_CHOLESKY: a matrix it cannot factor is an invalid step.
    const Eigen::LLT<Normal> llt(a);
    Tangent delta = llt.solve(-g);
    for (int c = 0; c < kDoF; ++c) {
      if (settings.held_mask & (1u << c)) delta[c] = 0.0;
    }
    if (llt.info() != Eigen::Success || !delta.allFinite()) {  // more damping
      ++summary.iterations;
      mu /= nu;
      nu *= 2.0;
      continue;
    }
    // Ceres's order: parameter tolerance on the step (x is kept; checked before the candidate's
    // evaluation, which would not change the outcome), function tolerance on the cost change.
    if (delta.norm() <=
        settings.parameter_tolerance * (norm_of(*pose) + settings.parameter_tolerance)) {
      summary.converged = true;
      break;
    }
    const double quad = delta.dot(h * delta);  // delta^T H delta: the test, the length, the model
    // The step test: the step alpha delta in sigmas, with the curvature H / alpha, and the distance
    // still to go when the steps shrink linearly (rate r = this step / the last, the geometric sum
    // m / (1 - r)): along a weakly constrained direction (a corridor) the steps creep, each a few
    // percent shorter than the last, and their sum, not the step, is what stopping would lose.
    if (settings.step_sigma > 0.0) {
      const double m = std::sqrt(alpha * quad * dof_free / (2.0 * cost));
      const double to_go = m < last_m ? m / (1.0 - m / last_m) : (last_m > 1e300 ? m : 1e300);
      last_m = m;
      if (to_go <= settings.step_sigma) {
        summary.converged = true;
        break;
      }
    }
    const double slope = g.dot(delta);  // < 0: delta descends (H + lambda D is positive definite)
    // No longer than the last accepted step (see above).
    const double length = std::sqrt(quad);
    const double a_step = line_search ? std::min(alpha, last_length / length) : 1.0;
    if (a_step > 1.0) {
      ++summary.iterations;
      const Pose longer = Traits::plus(*pose, (a_step * delta).eval());
      const double f = evaluate(longer, &h_trial, &g_trial);
      if (std::isfinite(f) && f <= cost + 1e-4 * a_step * slope) {
        const bool done = cost - f <= settings.function_tolerance * cost;
        alpha = next_alpha(cost, f, a_step, slope);
        last_length = a_step * length;
        *pose = longer;
        cost = f;
        h = h_trial;
        g = g_trial;
        mu = std::min(3.0 * mu, 1e16);  // as a step the model predicted well
        nu = 2.0;
        if (done) {
          summary.converged = true;
          break;
        }
        continue;
      }
      alpha = 1.0;
      last_m = 1e308;
      if (summary.iterations >= settings.max_iterations + 1) break;
    }
    ++summary.iterations;
    const double model_decrease = -(slope + 0.5 * quad);
    const Pose candidate = Traits::plus(*pose, delta);
    const double new_cost = evaluate(candidate, &h_trial, &g_trial);
    if (std::isfinite(new_cost) &&
        std::abs(cost - new_cost) <= settings.function_tolerance * cost) {
      summary.converged = true;  // Ceres keeps x here, not the candidate
      break;
    }
    // A step the model does not predict to decrease the cost is invalid (Ceres: shrink).
    const double ratio = model_decrease > 0.0 ? (cost - new_cost) / model_decrease : -1.0;
    if (std::isfinite(new_cost) && ratio > 1e-3) {
      if (line_search) alpha = next_alpha(cost, new_cost, 1.0, slope);
      last_length = length;
      *pose = candidate;
      cost = new_cost;
      h = h_trial;
      g = g_trial;
      mu = std::min(mu / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * ratio - 1.0, 3)), 1e16);
      nu = 2.0;
    } else {
      mu /= nu;
      nu *= 2.0;
      last_m = 1e308;    // the next step is another one (more damping)
      if (mu < 1e-32) {  // Ceres's min_trust_region_radius: no step decreases the cost
        summary.converged = true;
        break;
      }
    }
  }
  summary.final_cost = cost;
  return summary;
}

}  // namespace vdtnav::detail
