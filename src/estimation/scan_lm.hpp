#pragma once
/// \file
/// \brief The small-problem solver of the optimizer: Levenberg-Marquardt on the fixed-size normal
/// equations of one observation set (3 unknowns in 2D, 6 in 3D, 4 in the 4-DOF mode), with the
/// sensor model's analytic Jacobians accumulated in one pass over the readings. What Ceres does
/// for this problem, without its per-solve and per-iteration machinery (problem construction,
/// program evaluation, Jacobian copies), which dominates for a few unknowns.
///
/// Cost (the one Ceres minimises with the ScanCost block, halved as Ceres reports it):
///   F(X) = 1/2 sum_i w_i^2 rho(s_i) [+ 1/2 e^T I e],   s_i = |d_i|^2   (rho(s) = s without a loss)
/// Gradient, in the pose perturbation of PoseTraits<Dim>:
///   g = sum_i w_i^2 rho'_i J_i^T d_i [+ I e]
/// Curvature: Newton's (issue 57). Two terms make it differ from the IRLS matrix
///   H_G = sum_i w_i^2 rho'_i J_i^T J_i [+ I]                                                (G)
/// (what Ceres uses for a loss with rho'' <= 0), and each made every step fall short by about
/// half on the Intel log (gain ratio ~1.5-2 step after step, the cost converging linearly over
/// tens of iterations):
/// - the robust loss's second-order term (Triggs et al., "Bundle adjustment - a modern
///   synthesis", 2000, Sec. 4.3: the Hessian of rho(|d|^2)/2 in d is rho' I + 2 rho'' d d^T),
///     T = sum_i 2 w_i^2 rho''_i (J_i^T d_i)(J_i^T d_i)^T                                    (T)
///   (a Cauchy reading at |d| = scale / 1.7 has half the IRLS curvature), at every evaluation;
/// - the curvature of the field and of the rotation (BeamCurvatureT::hessian, what the
///   covariance (3.6) uses; the interpolated VDT bends where walls are thick or meet),
///     C = sum_i w_i^2 rho'_i (hessian_i - J_i^T J_i),                                       (F)
///   one lookup of the field's second derivatives per reading, outside the batch kernels, so it
///   is measured only where (G) + (T) proved a poor model: after an accepted step whose gain
///   ratio was off 1 by more than a quarter (on a floor plan's exact field never), and kept
///   while the model predicts well.
/// H_N = H_G + T + C is Newton's matrix of F, indefinite away from a minimum. The step's matrix
/// keeps its eigenvalues relative to H_G from below at 1/4 (newton_curvature()),
///     H = L V max(Lambda, 1/4) V^T L^T,   L L^T = H_G,   L^-1 H_N L^-T = V Lambda V^T       (K)
/// positive definite, Newton's own wherever H_N is that curved, at most 4x the IRLS step in any
/// direction: a lower floor (0.1) let steps leave their basin on the Intel log (4 scans lost).
/// The floor follows the cost where the steps prove it flatter (ScanLmSettings::floor_min < 1/4,
/// the 3D default): an accepted step's gain ratio rho = 2 - 1/k (a quadratic whose model is k
/// times as curved along the step) above 1.25 divides the floor by min(k, 4), down to floor_min;
/// a ratio below 3/4 or a rejected step multiplies it by 4, up to 1/4. Measured on a real 3D scan
/// (Riverside, 13k readings, half explained): the cost's curvature by central differences is
/// 0.002-0.2 of H_G in every direction, H_N agrees (-0.05-0.19), and at the fixed floor each step
/// covered a fraction of the way (rho ~1.85 step after step, 34 iterations a scan; 11 now).
/// Near the minimum the floor follows below floor_min (the 2D default 1/4) as far as keeps the
/// step within one sigma of the pose: a step at floor f is at most 1/(4 f) times the step at 1/4
/// in any direction, so after a step that started s sigmas from the minimum (test (C) below) the
/// floor may go down to max(s / 4, 1/64) (kNearFloor): where s < 1 a longer step stays inside
/// the region the covariance already claims. Measured: the MIT corridor's correct scans that
/// met the iteration limit, Newton's step stuck at 0.016 sigma (50 um a step along the
/// corridor, gain ratio ~2 each step), converge (kidnapped study: 98.9 % -> 99.6 % of the correct
/// scans published); a fixed 1/64 in 2D moved the Intel relations 0.0291 m / 0.437 deg ->
/// 0.0306 / 0.496 (long steps far from the minimum leave their basin), this rule to 0.0290 /
/// 0.431.
/// (F) is summed over an even subset of at most kCurvatureReadings readings, scaled to the scan.
/// Step: (H + lambda D) delta = -g, D = diag(H) clamped to [1e-6, 1e32] (Ceres's LM), factored by
/// Cholesky and accepted when the cost falls by at least 1e-3 of the model's predicted decrease;
/// lambda = 1 / radius with Ceres's (Nielsen's) radius update. A rejected step is not retried
/// with the radius halved (from Ceres's start, lambda = 1e-4, it took five rejections before the
/// damping shortened the step at all: 13 % of the Intel solves' steps were such retries), but
/// cut back along itself by a step-length factor s (delta = s delta_LM), to the minimum of the
/// quadratic through the cost along the step, phi(0) = F, phi'(0) = g^T delta,
/// phi(1) = F(X + delta) (Nocedal & Wright, "Numerical Optimization", 2006, eq. 3.57),
///   s <- s clamp(alpha*, 1/10, 1/2),  alpha* = -phi'(0) / (2 (phi(1) - phi(0) - phi'(0)))  (B)
/// and regained by doubling (up to 1) after each step whose gain ratio exceeds 3/4. Measured
/// (BM_VdtOptSolve2D, a 2D scan from 0.3 m / 0.1 rad off): 11.3 -> 8.4 iterations a solve.
///
/// Convergence (issue 57) is a test at the pose, not a property of the stop: the Newton step
/// delta_N = -H^-1 g, measured in the pose's standard deviations under the covariance
/// sigma^2 H^-1 of (3.4) (sigma: the a priori standard deviation of one disparity component,
/// the map's floor with the readings' noise),
///   |delta_N|_sigma^2 = g^T H^-1 g / sigma^2 <= step_sigma^2                                 (C)
/// i.e. the gradient small in the information metric, the remaining step far below one sigma
/// (0.01 by default). A solve stops as soon as (C) holds (converged), or at the iteration limit,
/// or when no step decreases the cost, or at Ceres's parameter tolerance (a step of ~10 um) where
/// the damping is not what made the step that short;
/// whatever stopped it, `converged` says whether (C) holds where it stopped (or Newton's step
/// itself is below the parameter tolerance: the minimum as far as the arithmetic resolves it).

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

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

/// (K)'s floor at the start of a solve (and its highest).
inline constexpr double kNewtonFloor = 0.25;

/// (K)'s lowest floor near the minimum, whatever ScanLmSettings::floor_min (see (K) above).
inline constexpr double kNearFloor = 1.0 / 64.0;

/// (F) is measured on at most this many readings, evenly over the scan (a 2D scan's are all).
inline constexpr std::size_t kCurvatureReadings = 2048;

/// Limits of one solve.
struct ScanLmSettings {
  int max_iterations = 25;
  double parameter_tolerance = 1e-6;
  /// The convergence test (C): the Newton step at most this many of the pose's standard
  /// deviations.
  double step_sigma = 0.01;
  /// sigma of (C), metres: the a priori standard deviation of one disparity component (> 0).
  double sigma = 0.01;
  /// Components of the perturbation held at zero (the 4-DOF mode's dtheta_x, dtheta_y).
  unsigned held_mask = 0;
  /// The step's matrix (K) from Newton's curvature; false: the IRLS matrix (G) alone.
  bool newton = true;
  /// The lowest floor of (K) away from the minimum (kNewtonFloor: fixed there), reached while
  /// steps fall short; within one sigma it may follow lower (kNearFloor, see (K)).
  double floor_min = kNewtonFloor;
};

/// The curvature of the step, (K): Newton's H_N, its eigenvalues relative to the Gauss-Newton
/// matrix H_G (with (T)) clamped from below at kNewtonFloor. With L L^T = H_G and
/// L^-1 H_N L^-T = V diag(lambda) V^T, the step's matrix is L V diag(max(lambda, floor)) V^T L^T:
/// positive definite, at most 1 / floor times as long as the Gauss-Newton step in any direction,
/// and Newton's own wherever it is that curved. H_G itself when it is not positive definite.
template <typename Normal>
Normal newton_curvature(const Normal& h_gauss_newton, const Normal& h_newton,
                        double floor = kNewtonFloor) {
  const Eigen::LLT<Normal> llt(h_gauss_newton);
  if (llt.info() != Eigen::Success || !h_newton.allFinite()) return h_gauss_newton;
  const Normal l = llt.matrixL();
  Normal m = llt.matrixL().solve(h_newton);
  m = llt.matrixL().solve(m.transpose().eval());  // L^-1 H_N L^-T (H_N symmetric)
  const Eigen::SelfAdjointEigenSolver<Normal> eig(0.5 * (m + m.transpose()));
  if (eig.info() != Eigen::Success) return h_gauss_newton;
  const auto lambda = eig.eigenvalues().cwiseMax(floor).eval();
  const Normal lv = l * eig.eigenvectors();
  return lv * lambda.asDiagonal() * lv.transpose();
}

/// What a solve did (the fields of ceres::Solver::Summary the optimizer reads; the optimizer
/// reports a Ceres solve in the same form).
struct ScanLmSummary {
  int iterations = 0;       ///< evaluations of a step, the start included (Ceres's count)
  double final_cost = 0.0;  ///< F at the returned pose (half the robust VCD)
  bool converged = false;   ///< the test (C) holds at the returned pose
  bool failed = false;      ///< the cost or the normal equations were not finite at the start
  /// |delta_N|_sigma of (C) at the returned pose (infinite when H is not positive definite).
  double step_sigmas = 0.0;
};

/// rho''(s) of a robust loss (see (T) above): 0 (none; Huber's core), -rho' / (2 s) (Huber
/// outside it), -rho'^2 / b (Cauchy).
inline double robust_curvature(RobustLoss loss, double scale, double s, double rho1) {
  if (loss == RobustLoss::kNone || s <= 0.0) return 0.0;
  const double b = scale * scale;
  if (loss == RobustLoss::kHuber) return s <= b ? 0.0 : -0.5 * rho1 / s;
  return -rho1 * rho1 / b;
}

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
  // Cost, gradient, (G) and (T) at X in one batch lookup of the readings (the SIMD
  // kernels: the Jacobian costs little more than the value there, so a trial point gets both,
  // kept when the step is accepted).
  thread_local std::vector<BeamDisparityT<Dim>> disparities;  // scratch: no allocation per solve
  const auto evaluate = [&](const Pose& x, Normal* h, Normal* t, Tangent* g) {
    const auto rotation = Traits::rotation(x);
    const auto translation = Traits::translation(x);
    model.disparities(rotation, translation, scan, &beams, &disparities, DisparityParts::kPose);
    double cost = 0.0;
    h->setZero();
    t->setZero();
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
      double rho1;
      if (cauchy_product) {
        const double f = 1.0 + s2 / b2;
        product *= f;
        if (product > 1e150) {
          log_sum += std::log(product);
          product = 1.0;
        }
        rho1 = 1.0 / f;
      } else {
        const RobustValue rv = robust_value(loss, loss_scale, s2);
        cost += w * rv.rho;
        rho1 = rv.rho1;
      }
      const double wr = w * rho1;
      // J^T d, and the lower triangle of the symmetric J^T J (mirrored once after the pass).
      const Tangent jd = b.d_pose.transpose() * b.d;
      const auto wj = (wr * b.d_pose).eval();
      for (int c = 0; c < kDoF; ++c) {
        for (int r = c; r < kDoF; ++r) (*h)(r, c) += wj.col(r).dot(b.d_pose.col(c));
      }
      g->noalias() += wr * jd;
      // (T)'s second-order term 2 rho'' (J^T d)(J^T d)^T (robust_curvature).
      const double c2 = 2.0 * w * robust_curvature(loss, loss_scale, s2, rho1);
      if (c2 != 0.0) {
        for (int c = 0; c < kDoF; ++c) {
          for (int r = c; r < kDoF; ++r) (*t)(r, c) += c2 * jd[r] * jd[c];
        }
      }
    }
    if (cauchy_product) cost += b2 * (log_sum + std::log(product));
    *h = h->template selfadjointView<Eigen::Lower>();
    *t = t->template selfadjointView<Eigen::Lower>();
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
      t->row(c).setZero();
      t->col(c).setZero();
      (*g)[c] = 0.0;
    }
    return 0.5 * cost;
  };
  // (F) at X: the curvature of the field and of the rotation (on a subset: see kCurvatureReadings).
  const auto correction_at = [&](const Pose& x) {
    const auto rotation = Traits::rotation(x);
    const auto translation = Traits::translation(x);
    Normal c = Normal::Zero();
    // An even subset of at most kCurvatureReadings readings, the sum scaled by the stride: (F)
    // corrects the model's curvature, and a sum of thousands of terms is known to a few percent
    // from hundreds of them (a 3D scan's 13k readings cost 7 single lookups each otherwise).
    const std::size_t stride = (beams.size() + kCurvatureReadings - 1) / kCurvatureReadings;
    std::size_t used = 0;
    for (std::size_t k = 0; k < beams.size(); k += std::max<std::size_t>(stride, 1), ++used) {
      BeamCurvatureT<Dim> cv;
      const BeamDisparityT<Dim> b = model.disparity(rotation, translation, scan.points[beams[k]],
                                                    scan.directions[beams[k]], &cv);
      const double wr = weight(k) * robust_weight(loss, loss_scale, b.d.squaredNorm());
      cv.hessian.noalias() -= b.d_pose.transpose() * b.d_pose;
      for (int j = 0; j < kDoF; ++j) {
        for (int r = j; r < kDoF; ++r) c(r, j) += wr * cv.hessian(r, j);
      }
    }
    if (used > 0) c *= static_cast<double>(beams.size()) / static_cast<double>(used);
    c = c.template selfadjointView<Eigen::Lower>();
    for (int j = 0; j < kDoF; ++j) {
      if (!(settings.held_mask & (1u << j))) continue;
      c.row(j).setZero();
      c.col(j).setZero();
    }
    return c;
  };
  // |x| of Ceres's parameter tolerance: 2D (x, y, phi); 3D the ambient (unit quaternion, t).
  const auto norm_of = [](const Pose& x) {
    if constexpr (Dim == 2) {
      return x.norm();
    } else {
      return std::sqrt(1.0 + x.translation().squaredNorm());
    }
  };
  // (C) at the current pose: the Newton step's length in sigmas (infinite if H is not positive
  // definite there).
  const double sigma2 = settings.sigma * settings.sigma;
  const auto newton_sigmas = [&](const Normal& h, const Tangent& g) {
    const Eigen::LLT<Normal> llt(h);
    if (llt.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
    const double q = g.dot(llt.solve(g));
    return std::isfinite(q) ? std::sqrt(std::max(0.0, q) / sigma2)
                            : std::numeric_limits<double>::infinity();
  };

  ScanLmSummary summary;
  // h, t, g: (G), (T) and the gradient at the pose; c: (F), measured only where the model
  // proved poor (see above); hs: the step's matrix (K).
  Normal h, h_trial, t, t_trial, c = Normal::Zero(), hs;
  double floor = kNewtonFloor;  // (K)'s, lowered while the steps fall short (below)
  Tangent g, g_trial;
  const auto step_matrix = [&]() {
    hs = settings.newton ? newton_curvature(h, (h + t + c).eval(), floor) : h;
  };
  double cost = evaluate(*pose, &h, &t, &g);
  summary.iterations = 1;
  summary.final_cost = cost;
  if (!std::isfinite(cost) || !h.allFinite() || !g.allFinite()) {
    summary.failed = true;
    summary.step_sigmas = std::numeric_limits<double>::infinity();
    return summary;
  }
  step_matrix();
  double mu = 1e4;  // Ceres's initial trust-region radius: lambda = 1 / mu
  double nu = 2.0;
  double sigmas = newton_sigmas(hs, g);
  bool at_resolution = false;  // stopped by the parameter tolerance at Newton's step
  double length = 1.0;         // s of (B): the step-length factor after rejected steps
  while (sigmas > settings.step_sigma && summary.iterations < settings.max_iterations + 1) {
    Normal a = hs;
    for (int k = 0; k < kDoF; ++k) a(k, k) += std::clamp(hs(k, k), 1e-6, 1e32) / mu;
    // Cholesky as Ceres's DENSE_NORMAL_CHOLESKY: a matrix it cannot factor is an invalid step.
    const Eigen::LLT<Normal> llt(a);
    Tangent delta = length * llt.solve(-g);
    for (int k = 0; k < kDoF; ++k) {
      if (settings.held_mask & (1u << k)) delta[k] = 0.0;
    }
    if (llt.info() != Eigen::Success || !delta.allFinite()) {  // more damping
      ++summary.iterations;
      mu /= nu;
      nu *= 2.0;
      continue;
    }
    // Ceres's parameter tolerance on the step (x is kept): a step of micrometres. Where that is
    // Newton's own step (the damping negligible) the pose is at the minimum as far as the
    // arithmetic resolves it, though (C) may ask for less on a cloud of thousands of readings.
    // Where the damping alone made it that short (rejected steps shrank the radius), the solve
    // has not stopped at a minimum: the radius grows tenfold and the solve goes on (an
    // iteration, so the limit still ends it), up to Ceres's largest radius.
    const double tiny =
        settings.parameter_tolerance * (norm_of(*pose) + settings.parameter_tolerance);
    if (delta.norm() <= tiny) {
      const Eigen::LLT<Normal> newton(hs);
      at_resolution = newton.info() == Eigen::Success && newton.solve(g).norm() <= 2.0 * tiny;
      // Cut back to micrometres by (B): no step along it decreases the cost.
      if (at_resolution || mu >= 1e16 || length < 1.0) break;
      ++summary.iterations;
      mu = std::min(10.0 * mu, 1e16);
      nu = 2.0;
      continue;
    }
    ++summary.iterations;
    const double model_decrease = -(g.dot(delta) + 0.5 * delta.dot(hs * delta));
    const Pose candidate = Traits::plus(*pose, delta);
    const double new_cost = evaluate(candidate, &h_trial, &t_trial, &g_trial);
    // A step the model does not predict to decrease the cost is invalid (Ceres: shrink).
    const double ratio = model_decrease > 0.0 ? (cost - new_cost) / model_decrease : -1.0;
    if (std::isfinite(new_cost) && ratio > 1e-3 && h_trial.allFinite() && g_trial.allFinite()) {
      *pose = candidate;
      cost = new_cost;
      h = h_trial;
      t = t_trial;
      g = g_trial;
      if (ratio > 0.75) length = std::min(1.0, 2.0 * length);
      if (settings.newton && std::abs(ratio - 1.0) > 0.25) {
        const Normal measured = correction_at(*pose);
        if (measured.allFinite()) c = measured;
        // A gain ratio rho = 2 - 1/k says the model was k times as curved along the step as
        // the cost: where the floor, not Newton's matrix, set the curvature (a cost flatter
        // than 1/4 of the IRLS matrix in every direction: a 3D scan half explained under the
        // Cauchy loss), the floor follows the measured curvature down, by up to 4 a step; a
        // step that overshoots (rho < 3/4) or fails raises it again. Below floor_min only as
        // far as keeps the next step within one sigma (s / 4 after a step from s sigmas).
        if (ratio > 1.25) {
          // `sigmas` is still (C) where this step started (updated below).
          const double lowest =
              std::min(settings.floor_min, std::max(kNearFloor, kNewtonFloor * sigmas));
          floor = std::max(lowest, floor / std::min(4.0, 1.0 / (2.0 - std::min(ratio, 1.75))));
        } else {
          floor = std::min(kNewtonFloor, 4.0 * floor);
        }
      }
      step_matrix();
      sigmas = newton_sigmas(hs, g);
      mu = std::min(mu / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * ratio - 1.0, 3)), 1e16);
      nu = 2.0;
    } else {
      if (std::isfinite(new_cost) && model_decrease > 0.0) {
        // (B): the minimum of the quadratic through phi(0), phi'(0), phi(1) along the step.
        const double slope = g.dot(delta);
        const double bend = new_cost - cost - slope;
        length *= std::clamp(bend > 0.0 ? -slope / (2.0 * bend) : 0.5, 0.1, 0.5);
      } else {  // not finite there, or no predicted decrease: more damping (Ceres)
        mu /= nu;
        nu *= 2.0;
      }
      if (floor < kNewtonFloor) {
        floor = std::min(kNewtonFloor, 4.0 * floor);
        step_matrix();
      }
      if (mu < 1e-32) break;  // Ceres's min_trust_region_radius: no step decreases the cost
    }
  }
  summary.final_cost = cost;
  summary.step_sigmas = sigmas;
  summary.converged = sigmas <= settings.step_sigma || at_resolution;
  return summary;
}

}  // namespace vdtnav::detail
