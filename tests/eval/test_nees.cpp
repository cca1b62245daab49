// NEES and ANEES: Monte Carlo errors drawn from a covariance give NEES ~ chi^2(d) (3 and 6 DOF),
// the ANEES interval covers the ANEES of consistent runs at its confidence and rejects
// over-confident and conservative covariances; the quantiles are checked against the exact
// chi-square distribution (series of the regularised incomplete gamma function, bisection).
#include "vdtnav/eval/nees.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <type_traits>

#include "vdtnav/core/error.hpp"

namespace vdtnav::eval {
namespace {

/// Exact chi^2(k) CDF: P(k/2, x/2) by its power series (converges for every x).
double chi2_cdf(double x, double k) {
  if (x <= 0.0) return 0.0;
  const double a = 0.5 * k, y = 0.5 * x;
  double term = 1.0, sum = 1.0;
  for (int n = 1; n < 100000 && term > 1e-17 * sum; ++n) {
    term *= y / (a + n);
    sum += term;
  }
  return std::exp(a * std::log(y) - y - std::lgamma(a + 1.0) + std::log(sum));
}

/// Exact chi^2(k) quantile by bisection on the CDF.
double chi2_quantile_exact(double p, double k) {
  double lo = 0.0, hi = k + 20.0 * std::sqrt(2.0 * k) + 50.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (chi2_cdf(mid, k) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

TEST(NormalQuantile, InvertsTheNormalCdfToDoublePrecision) {
  for (double p : {1e-12, 1e-6, 1e-3, 0.02, 0.02425, 0.1, 0.3, 0.5, 0.7, 0.9, 0.975, 0.999}) {
    const double x = normal_quantile(p);
    EXPECT_NEAR(normal_cdf(x), p, 1e-13 * p) << p;
    // The upper tail, against the complement (1 - pu is exact for pu >= 0.5).
    const double pu = 1.0 - p, xu = normal_quantile(pu);
    EXPECT_NEAR(0.5 * std::erfc(xu / std::sqrt(2.0)), 1.0 - pu, 1e-13 * (1.0 - pu)) << pu;
  }
  EXPECT_NEAR(normal_quantile(0.975), 1.959963984540054, 1e-14);
  EXPECT_EQ(normal_quantile(0.5), 0.0);
  EXPECT_TRUE(std::isinf(normal_quantile(0.0)) && normal_quantile(0.0) < 0);
  EXPECT_TRUE(std::isinf(normal_quantile(1.0)) && normal_quantile(1.0) > 0);
  EXPECT_TRUE(std::isnan(normal_quantile(1.5)));
}

TEST(Chi2Quantile, WilsonHilfertyAgainstTheExactDistribution) {
  EXPECT_NEAR(chi2_quantile_exact(0.975, 3), 9.348404, 1e-5);  // table values
  EXPECT_NEAR(chi2_quantile_exact(0.025, 3), 0.215795, 1e-5);
  struct Case {
    double dof, tolerance;  // relative, at the 2.5 % and 97.5 % points
  };
  for (const Case c : {Case{3, 0.20}, Case{6, 0.04}, Case{10, 0.015}, Case{30, 0.003},
                       Case{300, 2e-4}, Case{3000, 2e-5}}) {
    for (double p : {0.025, 0.975}) {
      const double exact = chi2_quantile_exact(p, c.dof);
      const double wh = chi2_quantile(p, c.dof);
      std::cout << "chi2 dof " << c.dof << " p " << p << ": exact " << exact << ", Wilson-Hilferty "
                << wh << " (" << 100.0 * (wh / exact - 1.0) << " %)\n";
      EXPECT_NEAR(wh / exact, 1.0, c.tolerance) << "dof " << c.dof << " p " << p;
    }
  }
  EXPECT_TRUE(std::isnan(chi2_quantile(0.5, 0.0)));
  EXPECT_EQ(chi2_quantile(0.0, 3.0), 0.0);
}

TEST(Anees, ThePerStepBoundCountsTheValuesWithinTheChiSquare95PercentPoint) {
  for (int dof = 1; dof <= 12; ++dof) {
    EXPECT_NEAR(chi2_95(dof) / chi2_quantile_exact(0.95, dof), 1.0, dof <= 6 ? 1e-9 : 0.015)
        << "dof " << dof;
  }
  // Crafted: one value in, one just past 7.8147 (3 dof), one far out, one NaN: 25 %.
  EXPECT_DOUBLE_EQ(anees({1.0, 7.82, 100.0, std::nan("")}, 3).inside_95_pct, 25.0);
  EXPECT_DOUBLE_EQ(anees({12.5}, 6).inside_95_pct, 100.0);
  EXPECT_DOUBLE_EQ(anees({12.6}, 6).inside_95_pct, 0.0);
  EXPECT_TRUE(std::isnan(anees({}, 3).inside_95_pct));
  // Monte Carlo: squared norms of N(0, I_3) draws (calibrated NEES) fall within the bound 95 %
  // of the time, to the binomial spread (4000 draws: sigma 0.34 %); inflated by 2, ~74 %.
  std::mt19937 rng(11);
  std::normal_distribution<double> n01(0.0, 1.0);
  std::vector<double> calibrated, over_confident;
  for (int k = 0; k < 4000; ++k) {
    const double v = Eigen::Vector3d(n01(rng), n01(rng), n01(rng)).squaredNorm();
    calibrated.push_back(v);
    over_confident.push_back(2.0 * v);
  }
  EXPECT_NEAR(anees(calibrated, 3).inside_95_pct, 95.0, 1.4);
  EXPECT_LT(anees(over_confident, 3).inside_95_pct, 80.0);
}

/// A random symmetric positive definite matrix with condition number up to ~100.
template <int D>
Eigen::Matrix<double, D, D> random_covariance(std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> log_sv(-2.0, 0.0);
  Eigen::Matrix<double, D, D> g;
  for (int i = 0; i < g.size(); ++i) g.data()[i] = normal(rng);
  const Eigen::HouseholderQR<Eigen::Matrix<double, D, D>> qr(g);
  const Eigen::Matrix<double, D, D> q = qr.householderQ();
  Eigen::Matrix<double, D, 1> sv;
  for (int i = 0; i < D; ++i) sv[i] = std::pow(10.0, log_sv(rng));
  return q * sv.asDiagonal() * q.transpose();
}

template <typename T>
class NeesTest : public ::testing::Test {};
using Dofs = ::testing::Types<std::integral_constant<int, 3>, std::integral_constant<int, 6>>;
TYPED_TEST_SUITE(NeesTest, Dofs);

TYPED_TEST(NeesTest, MonteCarloNeesIsChiSquare) {
  constexpr int kD = TypeParam::value;
  std::mt19937_64 rng(21);
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Matrix<double, kD, kD> p = random_covariance<kD>(rng);
  const Eigen::Matrix<double, kD, kD> l = p.llt().matrixL();
  const int n = 20000;
  std::vector<double> values(n);
  for (int i = 0; i < n; ++i) {
    Eigen::Matrix<double, kD, 1> z;
    for (int k = 0; k < kD; ++k) z[k] = normal(rng);
    values[i] = nees<kD>(Eigen::Matrix<double, kD, 1>(l * z), p);
  }
  double mean = 0.0;
  for (double v : values) mean += v / n;
  EXPECT_NEAR(mean, kD, 4.0 * std::sqrt(2.0 * kD / n));  // Var chi^2(d) = 2d
  // The empirical CDF at exact quantiles matches p (binomial standard error sqrt(p(1-p)/n)).
  std::sort(values.begin(), values.end());
  for (double q : {0.025, 0.25, 0.5, 0.75, 0.975}) {
    const double x = chi2_quantile_exact(q, kD);
    const double frac =
        static_cast<double>(std::upper_bound(values.begin(), values.end(), x) - values.begin()) / n;
    EXPECT_NEAR(frac, q, 4.0 * std::sqrt(q * (1 - q) / n)) << "p " << q;
  }
}

TYPED_TEST(NeesTest, AneesIntervalCoversConsistentRunsAndRejectsMiscalibratedOnes) {
  constexpr int kD = TypeParam::value;
  std::mt19937_64 rng(22);
  std::normal_distribution<double> normal(0.0, 1.0);
  const Eigen::Matrix<double, kD, kD> p = random_covariance<kD>(rng);
  const Eigen::Matrix<double, kD, kD> l = p.llt().matrixL();
  auto run = [&](int n, double scale) {
    std::vector<double> v(n);
    for (int i = 0; i < n; ++i) {
      Eigen::Matrix<double, kD, 1> z;
      for (int k = 0; k < kD; ++k) z[k] = normal(rng);
      v[i] =
          nees<kD>(Eigen::Matrix<double, kD, 1>(l * z), Eigen::Matrix<double, kD, kD>(scale * p));
    }
    return anees(v, kD, 0.95);
  };
  // Coverage: the fraction of consistent runs of 50 samples inside the 95 % interval.
  const int runs = 2000;
  int inside = 0;
  for (int r = 0; r < runs; ++r) inside += run(50, 1.0).consistent ? 1 : 0;
  const double coverage = static_cast<double>(inside) / runs;
  std::cout << "ANEES 95 % interval coverage over " << runs << " runs of 50 (" << kD
            << " dof): " << coverage << "\n";
  EXPECT_NEAR(coverage, 0.95, 4.0 * std::sqrt(0.95 * 0.05 / runs));
  // Over-confident (covariance halved: ANEES ~ 2d) and conservative (doubled: ~ d/2).
  const AneesResult over = run(500, 0.5), under = run(500, 2.0);
  EXPECT_FALSE(over.consistent);
  EXPECT_GT(over.anees, over.interval.upper);
  EXPECT_FALSE(under.consistent);
  EXPECT_LT(under.anees, under.interval.lower);
  EXPECT_NEAR(over.anees, 2.0 * kD, 0.15 * kD);
}

TEST(AneesInterval, MatchesTheNormalApproximationForLargeN) {
  // N ANEES ~ chi^2(N d): mean d, variance 2 d / N.
  const ChiSquareInterval i = anees_interval(1000, 3, 0.95);
  EXPECT_NEAR(i.lower, 3.0 - 1.96 * std::sqrt(6.0 / 1000), 0.01);
  EXPECT_NEAR(i.upper, 3.0 + 1.96 * std::sqrt(6.0 / 1000), 0.01);
  EXPECT_NEAR(i.lower, chi2_quantile_exact(0.025, 3000) / 1000, 1e-4);
  EXPECT_NEAR(i.upper, chi2_quantile_exact(0.975, 3000) / 1000, 1e-4);
  EXPECT_THROW((void)anees_interval(0, 3), ConfigError);
  EXPECT_THROW((void)anees_interval(10, 3, 1.0), ConfigError);
}

TEST(Nees, PoseOverloadsUseTheEstimatorsErrorParameterisation) {
  // Pose2: the yaw error is wrapped.
  const Eigen::Matrix3d p2 = Eigen::Vector3d(0.01, 0.04, 0.0025).asDiagonal();
  EXPECT_NEAR(
      nees(Pose2(0.1, -0.2, 3.1), Pose2(0.0, 0.0, -3.1), p2),
      0.1 * 0.1 / 0.01 + 0.2 * 0.2 / 0.04 + std::pow(2 * 3.14159265358979 - 6.2, 2) / 0.0025, 1e-9);
  // Pose3: e = ominus(estimate, truth), so estimate = oplus(truth, delta) gives delta's NEES.
  std::mt19937_64 rng(23);
  const Matrix6d p6 = random_covariance<6>(rng);
  const Pose3 truth = pose3_from_xyz_rpy(1, 2, 3, 0.1, -0.2, 2.5);
  Vector6d delta;
  delta << 0.05, -0.02, 0.01, 0.03, -0.04, 0.02;
  EXPECT_NEAR(nees(oplus(truth, delta), truth, p6), delta.dot(p6.ldlt().solve(delta)), 1e-9);
}

TEST(Nees, AFourDofCovarianceLeavesTheHeldRollAndPitchOut) {
  // A 4-DOF result: zero rows and columns for dtheta_x, dtheta_y; the NEES is that of the other
  // four components, whatever the (held) roll and pitch errors are.
  const Pose3 truth = pose3_from_xyz_rpy(1, 2, 3, 0.1, -0.2, 2.5);
  Vector6d delta;
  delta << 0.02, -0.01, 0.03, 0.004, -0.003, 0.01;
  Matrix6d cov = Matrix6d::Zero();
  Eigen::Matrix4d free;
  free << 4e-4, 1e-4, 0, 2e-5, 1e-4, 9e-4, 0, 0, 0, 0, 1e-3, 0, 2e-5, 0, 0, 1e-4;
  const int idx[4] = {0, 1, 2, 5};
  Eigen::Vector4d e;
  for (int i = 0; i < 4; ++i) {
    e[i] = delta[idx[i]];
    for (int j = 0; j < 4; ++j) cov(idx[i], idx[j]) = free(i, j);
  }
  int dof = 0;
  const double n = nees(oplus(truth, delta), truth, cov, &dof);
  EXPECT_EQ(dof, 4);
  EXPECT_NEAR(n, e.dot(free.inverse() * e), 1e-9 * n);
  EXPECT_TRUE(std::isfinite(n));
  // Not estimated (NaN rows and columns, the 4-DOF mode without an attitude sigma): the same.
  Matrix6d not_estimated = cov;
  for (int k = 3; k <= 4; ++k) {
    not_estimated.row(k).setConstant(std::nan(""));
    not_estimated.col(k).setConstant(std::nan(""));
  }
  int dof_nan = 0;
  EXPECT_EQ(nees(oplus(truth, delta), truth, not_estimated, &dof_nan), n);
  EXPECT_EQ(dof_nan, 4);
  // A full covariance: all six.
  (void)nees(oplus(truth, delta), truth, Matrix6d::Identity(), &dof);
  EXPECT_EQ(dof, 6);
}

TEST(Nees, BadCovariancesGiveNanAndAneesCountsThemAsFailures) {
  const Eigen::Matrix3d singular = Eigen::Vector3d(1.0, 1.0, 0.0).asDiagonal();
  EXPECT_TRUE(std::isnan(nees<3>(Eigen::Vector3d(1, 1, 1), singular)));
  Eigen::Matrix3d asym = Eigen::Matrix3d::Identity();
  asym(0, 1) = 0.5;
  EXPECT_TRUE(std::isnan(nees<3>(Eigen::Vector3d(1, 1, 1), asym)));
  const AneesResult r = anees({3.0, std::nan(""), 2.0, INFINITY}, 3);
  EXPECT_EQ(r.count, 2u);
  EXPECT_EQ(r.failures, 2u);
  EXPECT_DOUBLE_EQ(r.anees, 2.5);
  EXPECT_FALSE(anees({}, 3).consistent);
  // The finite values alone are consistent (mean 3 over 1000 values of chi^2(3)'s mean); one
  // NaN among them (a singular covariance) makes the run inconsistent, and the note says so.
  std::vector<double> ok(1000, 3.0);
  EXPECT_TRUE(anees(ok, 3).consistent);
  EXPECT_EQ(left_out_note(anees(ok, 3), 1000), "");
  EXPECT_EQ(left_out_note(anees(ok, 3), 1004, "not localized"),
            "1000 of 1004 poses: 4 not localized");
  ok.push_back(nees<3>(Eigen::Vector3d(1, 1, 1), singular));
  const AneesResult with_nan = anees(ok, 3);
  EXPECT_EQ(with_nan.count, 1000u);
  EXPECT_EQ(with_nan.failures, 1u);
  EXPECT_TRUE(with_nan.interval.contains(with_nan.anees));
  EXPECT_FALSE(with_nan.consistent);
  EXPECT_EQ(left_out_note(with_nan, 1003),
            "1000 of 1003 poses: 2 without a covariance, 1 no finite NEES");
}

}  // namespace
}  // namespace vdtnav::eval
