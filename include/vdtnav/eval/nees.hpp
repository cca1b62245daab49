#pragma once
/// \file
/// \brief Consistency of an estimator's covariance: the normalised estimation error squared
/// (NEES), its average over a run (ANEES) and the chi-square acceptance interval of that
/// average (Bar-Shalom, Li, Kirubarajan, "Estimation with Applications to Tracking and
/// Navigation", 2001, sec. 5.4.2).
///
/// For a consistent estimator with d-dimensional Gaussian errors, NEES = e^T P^-1 e ~ chi^2(d),
/// so the mean of N independent NEES is chi^2(N d) / N, with mean d.

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/core/pose3.hpp"

namespace vdtnav::eval {

/// \return the standard normal quantile Phi^-1(p) for p in (0, 1) (-inf at 0, +inf at 1, NaN
/// outside [0, 1]): Acklam's rational approximation refined by one Halley step on erfc, to
/// ~1e-15 relative.
[[nodiscard]] double normal_quantile(double p);

/// \return the chi-square quantile with `dof` degrees of freedom at probability p by the
/// Wilson-Hilferty approximation chi^2_p(k) ~ k (1 - 2/(9k) + z_p sqrt(2/(9k)))^3, z_p =
/// normal_quantile(p), clamped at 0. Relative error at the 2.5 % / 97.5 % points, against the
/// exact distribution (tests/eval/test_nees.cpp): -16 % / -0.3 % for k = 3, -2.5 % / -0.05 % for
/// k = 6, -0.75 % / -0.01 % for k = 10, < 0.1 % for k >= 30, < 1e-5 for k >= 300. Good for the
/// ANEES interval (k = N d), poor in the lower tail of a single small-dof NEES.
/// NaN for p outside [0, 1] or dof <= 0.
[[nodiscard]] double chi2_quantile(double p, double dof);

/// \brief A two-sided acceptance interval.
struct ChiSquareInterval {
  double lower = 0.0;
  double upper = 0.0;

  [[nodiscard]] bool contains(double x) const noexcept { return x >= lower && x <= upper; }
};

/// \return the two-sided `confidence` interval of the mean of n NEES values with `dof` degrees
/// of freedom each: [chi^2_{(1-c)/2}(n d) / n, chi^2_{(1+c)/2}(n d) / n] (Wilson-Hilferty).
/// \throws ConfigError unless n >= 1, dof >= 1 and 0 < confidence < 1.
[[nodiscard]] ChiSquareInterval anees_interval(std::size_t n, int dof, double confidence = 0.95);

/// \return e^T P^-1 e, by a Cholesky factorisation of P; NaN when P is not symmetric positive
/// definite (to working precision) or e or P is not finite.
template <int Dof>
[[nodiscard]] double nees(const Eigen::Matrix<double, Dof, 1>& error,
                          const Eigen::Matrix<double, Dof, Dof>& covariance) {
  if (!error.allFinite() || !covariance.allFinite())
    return std::numeric_limits<double>::quiet_NaN();
  // LLT reads one triangle only: an asymmetric matrix is not a covariance.
  if ((covariance - covariance.transpose()).norm() > 1e-9 * covariance.norm())
    return std::numeric_limits<double>::quiet_NaN();
  const Eigen::LLT<Eigen::Matrix<double, Dof, Dof>> llt(covariance);
  if (llt.info() != Eigen::Success) return std::numeric_limits<double>::quiet_NaN();
  // e^T P^-1 e = |L^-1 e|^2 with P = L L^T.
  return llt.matrixL().solve(error).squaredNorm();
}

/// \return the NEES of a planar pose estimate: e = pose_error(estimate, truth) = (dx, dy,
/// wrap(dyaw)), the parameterisation the 2D localizers' covariances are in.
[[nodiscard]] double nees(const Pose2& estimate, const Pose2& truth,
                          const Eigen::Matrix3d& covariance);

/// \return the NEES of an SE(3) estimate: e = ominus(estimate, truth) = (dt, dtheta), the left
/// (world-frame) perturbation of pose3.hpp that the 6-DOF covariances are expressed in. The
/// components whose rows and columns are zero or NaN (held by the estimator and not estimated:
/// roll and pitch in the 4-DOF mode without an attitude sigma) are left out; `dof`, if given,
/// receives the number kept (the chi-square's dof).
[[nodiscard]] double nees(const Pose3& estimate, const Pose3& truth, const Matrix6d& covariance,
                          int* dof = nullptr);

/// \brief The average NEES of a run and its consistency test.
struct AneesResult {
  std::size_t count = 0;  ///< finite NEES values averaged
  /// NaN/inf values: a covariance that is singular, not positive definite or not finite. The
  /// claim failed for those poses: they are left out of the mean, counted here, and any of them
  /// makes the run inconsistent.
  std::size_t failures = 0;
  double anees = 0.0;          ///< mean of the finite values (0 when count == 0)
  ChiSquareInterval interval;  ///< anees_interval(count, dof, confidence)
  /// true when count > 0, failures == 0 and anees lies in the interval: the covariance is
  /// consistent at the confidence level; below means conservative, above over-confident.
  bool consistent = false;
  /// The per-step 95 % bound: the percentage of the values (finite or not) at or below
  /// chi2_95(dof), 95 % when the covariance is calibrated. The ANEES alone can hide a few huge
  /// outliers in a conservative run or many small misses; non-finite values count as outside.
  /// NaN when there are no values.
  double inside_95_pct = std::numeric_limits<double>::quiet_NaN();
};

/// The chi-square distribution's 95 % points for 1-6 degrees of freedom (table values).
inline constexpr double kChi2P95[6] = {3.841458820694124, 5.991464547107979,  7.814727903251178,
                                       9.487729036781154, 11.070497693516351, 12.591587243743977};

/// \return the chi-square distribution's 95 % point with `dof` degrees of freedom: kChi2P95 for
/// 1-6, Wilson-Hilferty above (within 1.5 % from 10 dof: Chi2Quantile's test).
[[nodiscard]] double chi2_95(int dof);

/// \return what a table prints beside an ANEES of a run of `poses` poses: "" when every pose is
/// in it, else "C of P poses: U <why_excluded>, F no finite NEES" (U = poses the caller left out
/// before computing a NEES, e.g. "not localized" or "without a covariance"; F = r.failures).
[[nodiscard]] std::string left_out_note(const AneesResult& r, std::size_t poses,
                                        const std::string& why_excluded = "without a covariance");

/// \brief ANEES of `nees_values` (each with `dof` degrees of freedom) and its two-sided
/// chi-square test at `confidence`.
/// \throws ConfigError unless dof >= 1 and 0 < confidence < 1.
[[nodiscard]] AneesResult anees(const std::vector<double>& nees_values, int dof,
                                double confidence = 0.95);

}  // namespace vdtnav::eval
