#include "vdtnav/eval/nees.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"

namespace vdtnav::eval {

double normal_quantile(double p) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (std::isnan(p) || p < 0.0 || p > 1.0) return kNaN;
  if (p == 0.0) return -kInf;
  if (p == 1.0) return kInf;
  // Upper half by symmetry: 1 - p is exact there (Sterbenz), and the refinement below then works
  // on the small tail probability instead of on p close to 1.
  if (p > 0.5) return -normal_quantile(1.0 - p);
  // P. J. Acklam's rational approximation (relative error < 1.15e-9).
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,
                                 -2.759285104469687e+02, 1.383577518672690e+02,
                                 -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02,
                                 -1.556989798598866e+02, 6.680131188771972e+01,
                                 -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01,
                                 -2.400758277161838e+00, -2.549732539343734e+00,
                                 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01,
                                 2.445134137142996e+00, 3.754408661907416e+00};
  constexpr double kLow = 0.02425;
  double x;
  if (p < kLow) {
    const double q = std::sqrt(-2.0 * std::log(p));
    x = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  } else {
    const double q = p - 0.5, r = q * q;
    x = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
  }
  // One Halley step on Phi(x) - p = 0, Phi(x) = erfc(-x / sqrt 2) / 2: full double precision.
  constexpr double kSqrt2 = 1.41421356237309504880, kSqrt2Pi = 2.50662827463100050242;
  const double e = 0.5 * std::erfc(-x / kSqrt2) - p;
  const double u = e * kSqrt2Pi * std::exp(0.5 * x * x);
  return x - u / (1.0 + 0.5 * x * u);
}

double chi2_quantile(double p, double dof) {
  if (std::isnan(p) || p < 0.0 || p > 1.0 || !(dof > 0.0))
    return std::numeric_limits<double>::quiet_NaN();
  if (p == 1.0 || std::isinf(dof)) return std::numeric_limits<double>::infinity();
  // Wilson & Hilferty (1931): (X / k)^(1/3) is close to N(1 - 2/(9k), 2/(9k)).
  const double a = 2.0 / (9.0 * dof);
  const double cube_root = 1.0 - a + normal_quantile(p) * std::sqrt(a);
  return cube_root <= 0.0 ? 0.0 : dof * cube_root * cube_root * cube_root;
}

ChiSquareInterval anees_interval(std::size_t n, int dof, double confidence) {
  VDTNAV_CHECK(n >= 1, "anees_interval: need at least one NEES value");
  VDTNAV_CHECK(dof >= 1, "anees_interval: dof must be >= 1");
  VDTNAV_CHECK(confidence > 0.0 && confidence < 1.0,
               "anees_interval: confidence must be in (0, 1)");
  // N * ANEES ~ chi^2(N d) for a consistent estimator (Bar-Shalom et al. (5.4.2-6)).
  const double nd = static_cast<double>(n) * dof;
  const double alpha = 1.0 - confidence;
  return {chi2_quantile(0.5 * alpha, nd) / static_cast<double>(n),
          chi2_quantile(1.0 - 0.5 * alpha, nd) / static_cast<double>(n)};
}

double nees(const Pose2& estimate, const Pose2& truth, const Eigen::Matrix3d& covariance) {
  return nees<3>(pose_error(estimate, truth), covariance);
}

double nees(const Pose3& estimate, const Pose3& truth, const Matrix6d& covariance, int* dof) {
  // Components the estimator held (zero rows and columns, the 4-DOF mode) are left out.
  std::vector<int> free;
  for (int k = 0; k < 6; ++k)
    if (!std::isnan(covariance(k, k)) &&                   // a NaN diagonal: not estimated
        ((covariance.row(k).array().abs() > 0.0).any() ||  // NaN entries compare false
         (covariance.col(k).array().abs() > 0.0).any()))
      free.push_back(k);
  if (dof != nullptr) *dof = static_cast<int>(free.size());
  const Vector6d e = ominus(estimate, truth);
  if (free.size() == 6) return nees<6>(e, covariance);
  if (free.empty()) return std::numeric_limits<double>::quiet_NaN();
  const int n = static_cast<int>(free.size());
  Eigen::VectorXd ef(n);
  Eigen::MatrixXd pf(n, n);
  for (int i = 0; i < n; ++i) {
    ef[i] = e[free[static_cast<std::size_t>(i)]];
    for (int j = 0; j < n; ++j)
      pf(i, j) = covariance(free[static_cast<std::size_t>(i)], free[static_cast<std::size_t>(j)]);
  }
  return nees<Eigen::Dynamic>(ef, pf);
}

double chi2_95(int dof) {
  VDTNAV_CHECK(dof >= 1, "chi2_95: dof must be >= 1");
  return dof <= 6 ? kChi2P95[dof - 1] : chi2_quantile(0.95, dof);
}

AneesResult anees(const std::vector<double>& nees_values, int dof, double confidence) {
  VDTNAV_CHECK(dof >= 1, "anees: dof must be >= 1");
  VDTNAV_CHECK(confidence > 0.0 && confidence < 1.0, "anees: confidence must be in (0, 1)");
  AneesResult r;
  double sum = 0.0;
  const double bound = chi2_95(dof);
  std::size_t inside = 0;  // values within the per-step 95 % bound (non-finite ones are not)
  for (double v : nees_values) {
    if (!std::isfinite(v)) {
      ++r.failures;
      continue;
    }
    sum += v;
    ++r.count;
    inside += v <= bound ? 1 : 0;
  }
  if (!nees_values.empty()) {
    r.inside_95_pct = 100.0 * static_cast<double>(inside) / static_cast<double>(nees_values.size());
  }
  if (r.count == 0) return r;
  r.anees = sum / static_cast<double>(r.count);
  r.interval = anees_interval(r.count, dof, confidence);
  r.consistent = r.failures == 0 && r.interval.contains(r.anees);
  return r;
}

std::string left_out_note(const AneesResult& r, std::size_t poses,
                          const std::string& why_excluded) {
  const std::size_t judged = r.count + r.failures;
  const std::size_t excluded = poses > judged ? poses - judged : 0;
  if (excluded == 0 && r.failures == 0) return "";
  std::string note = std::to_string(r.count) + " of " + std::to_string(poses) + " poses:";
  if (excluded > 0) note += " " + std::to_string(excluded) + " " + why_excluded;
  if (excluded > 0 && r.failures > 0) note += ",";
  if (r.failures > 0) note += " " + std::to_string(r.failures) + " no finite NEES";
  return note;
}

}  // namespace vdtnav::eval
