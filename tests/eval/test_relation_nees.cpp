// The relation NEES: the Jacobians of x_i⁻¹ ⊕ x_j against central finite differences, the NEES
// against Monte Carlo (poses drawn from known covariances give NEES ~ χ²(3): mean 3, 95 % below
// 7.81, where Jacobians without the lever arm or with its sign flipped fail), and the
// bookkeeping of relation_nees() over a trajectory (skips by reason, mean, median, fraction).
#include "vdtnav/eval/relation_nees.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Cholesky>

#include "vdtnav/core/error.hpp"
#include "vdtnav/eval/nees.hpp"

namespace vdtnav::eval {
namespace {

/// ∂ between(from, to) / ∂(from or to) by central differences (angle differences wrapped).
Eigen::Matrix3d numeric_jacobian(const Pose2& from, const Pose2& to, bool wrt_from) {
  constexpr double h = 1e-6;
  Eigen::Matrix3d j;
  for (int c = 0; c < 3; ++c) {
    Pose2 a_from = from, b_from = from, a_to = to, b_to = to;
    (wrt_from ? a_from : a_to)[c] += h;
    (wrt_from ? b_from : b_to)[c] -= h;
    j.col(c) = pose_error(between(a_from, a_to), between(b_from, b_to)) / (2.0 * h);
  }
  return j;
}

TEST(RelationNees, JacobiansMatchFiniteDifferences) {
  const std::vector<std::pair<Pose2, Pose2>> cases = {
      {Pose2(0.0, 0.0, 0.0), Pose2(1.0, 0.0, 0.0)},
      {Pose2(1.5, -2.0, 0.7), Pose2(-3.0, 4.0, -2.1)},
      {Pose2(-0.3, 0.2, kPi - 0.01), Pose2(5.0, 1.0, -kPi + 0.02)},  // yaw across ±π
      {Pose2(10.0, 7.0, -1.3), Pose2(10.2, 6.9, 2.9)},
  };
  for (const auto& [from, to] : cases) {
    const RelativePoseJacobians j = relative_pose_jacobians(from, to);
    EXPECT_TRUE(j.delta.isApprox(between(from, to)));
    EXPECT_LT((j.d_from - numeric_jacobian(from, to, true)).norm(), 1e-7)
        << "J_i\n"
        << j.d_from << "\nnumeric\n"
        << numeric_jacobian(from, to, true);
    EXPECT_LT((j.d_to - numeric_jacobian(from, to, false)).norm(), 1e-7)
        << "J_j\n"
        << j.d_to << "\nnumeric\n"
        << numeric_jacobian(from, to, false);
  }
}

/// Relation NEES values of poses drawn around (from, to) with covariances (cov_from, cov_to),
/// computed with Σ_rel from `sigma_rel(from_hat, to_hat)`.
template <class SigmaRel>
std::vector<double> monte_carlo(const Pose2& from, const Pose2& to, const Eigen::Matrix3d& cov_from,
                                const Eigen::Matrix3d& cov_to, int n, SigmaRel sigma_rel) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  const Eigen::Matrix3d l_from = cov_from.llt().matrixL(), l_to = cov_to.llt().matrixL();
  const Pose2 truth = between(from, to);
  std::vector<double> out;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d u(g(rng), g(rng), g(rng)), w(g(rng), g(rng), g(rng));
    const Pose2 a = from + l_from * u, b = to + l_to * w;  // pose_error(a, from) ~ N(0, cov_from)
    out.push_back(nees<3>(pose_error(between(a, b), truth), sigma_rel(a, b)));
  }
  return out;
}

double mean_of(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return s / static_cast<double>(v.size());
}

double fraction_below(const std::vector<double>& v, double bound) {
  double n = 0.0;
  for (double x : v) n += x <= bound ? 1.0 : 0.0;
  return n / static_cast<double>(v.size());
}

TEST(RelationNees, MonteCarloNeesIsChiSquare3AndAWrongJacobianFails) {
  // Ends 6 m apart with a yaw σ of 0.05 rad: the lever arm (the third column of J_i) carries
  // 0.3 m of the relative pose's spread, six times the position σ, and the x–yaw and y–yaw
  // correlations make its sign matter.
  const Pose2 from(1.0, 2.0, 0.4), to(6.0, 5.5, 1.1);
  Eigen::Matrix3d cov_from, cov_to;
  cov_from << 0.05 * 0.05, 0.0004, 0.0010, 0.0004, 0.04 * 0.04, -0.0008, 0.0010, -0.0008,
      0.05 * 0.05;
  cov_to << 0.03 * 0.03, -0.0002, 0.0002, -0.0002, 0.06 * 0.06, 0.0005, 0.0002, 0.0005, 0.03 * 0.03;
  constexpr int kN = 4000;
  // N · ANEES ~ χ²(3N): the 99 % interval of the mean (±0.13 at N = 4000).
  const ChiSquareInterval interval = anees_interval(kN, 3, 0.99);

  const std::vector<double> v = monte_carlo(from, to, cov_from, cov_to, kN, [&](auto a, auto b) {
    return relative_pose_covariance(a, b, cov_from, cov_to);
  });
  EXPECT_TRUE(interval.contains(mean_of(v))) << "mean NEES " << mean_of(v) << " outside ["
                                             << interval.lower << ", " << interval.upper << "]";
  // 95 % below the χ²(3) 95 % quantile; binomial σ = 0.0034 at N = 4000.
  EXPECT_NEAR(fraction_below(v, kChi2Dof3P95), 0.95, 0.012);
  // relation_nees() is the same number as the NEES with Σ_rel computed from the estimates.
  {
    const Pose2 a = from + Pose2(0.03, -0.02, 0.01), b = to + Pose2(-0.01, 0.04, -0.02);
    EXPECT_NEAR(relation_nees(a, b, cov_from, cov_to, between(from, to)),
                nees<3>(pose_error(between(a, b), between(from, to)),
                        relative_pose_covariance(a, b, cov_from, cov_to)),
                1e-12);
  }

  // The same test with wrong Jacobians must fail it: without the lever arm, and with the lever
  // arm's sign flipped.
  const auto wrong = [&](double lever_sign) {
    return [&, lever_sign](const Pose2& a, const Pose2& b) {
      RelativePoseJacobians j = relative_pose_jacobians(a, b);
      j.d_from.block<2, 1>(0, 2) *= lever_sign;
      return Eigen::Matrix3d(j.d_from * cov_from * j.d_from.transpose() +
                             j.d_to * cov_to * j.d_to.transpose());
    };
  };
  const double no_lever = mean_of(monte_carlo(from, to, cov_from, cov_to, kN, wrong(0.0)));
  const double flipped = mean_of(monte_carlo(from, to, cov_from, cov_to, kN, wrong(-1.0)));
  EXPECT_FALSE(interval.contains(no_lever)) << no_lever;
  EXPECT_FALSE(interval.contains(flipped)) << flipped;
}

TEST(RelationNees, OverATrajectoryCountsSkipsAndSummarises) {
  Trajectory2 est;
  std::vector<Eigen::Matrix3d> cov;
  for (int k = 0; k < 6; ++k) {
    est.push_back({100.0 + k, Pose2(0.5 * k, 0.1 * k, 0.05 * k)});
    cov.push_back(Eigen::Matrix3d::Identity() * 0.01);
  }
  cov[4] = Eigen::Matrix3d::Constant(std::nan(""));  // sample 4: no covariance
  cov[5] = Eigen::Matrix3d::Zero();                  // sample 5: exact
  // Relation k: from sample 0 to sample k+1 with a known error: Σ_rel = 0.01 (J_i J_iᵀ + I).
  std::vector<Relation> rel;
  std::vector<double> expected;
  for (int k = 1; k <= 3; ++k) {
    const Pose2 truth = between(est[0].pose, est[k].pose) + Pose2(0.02 * k, -0.01, 0.01 * k);
    rel.push_back({est[0].t, est[k].t, truth});
    expected.push_back(relation_nees(est[0].pose, est[k].pose, cov[0], cov[k], truth));
  }
  rel.push_back({est[0].t, 100.5, Pose2::Zero()});  // no sample at 100.5
  rel.push_back({est[1].t, est[4].t, Pose2::Zero()});
  rel.push_back({est[5].t, est[5].t, Pose2::Zero()});  // Σ_rel = 0: singular

  const RelationNeesResult r = relation_nees(est, cov, rel);
  EXPECT_EQ(r.used, 3u);
  EXPECT_EQ(r.skipped_no_stamp, 1u);
  EXPECT_EQ(r.skipped_no_covariance, 1u);
  EXPECT_EQ(r.skipped_singular, 1u);
  ASSERT_EQ(r.values.size(), rel.size());
  for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(r.values[k], expected[k]);
  for (int k = 3; k < 6; ++k) EXPECT_TRUE(std::isnan(r.values[k]));
  std::vector<double> sorted = expected;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_DOUBLE_EQ(r.median, sorted[1]);
  EXPECT_DOUBLE_EQ(r.mean, (expected[0] + expected[1] + expected[2]) / 3.0);
  RelationNeesOptions o;
  o.bound = sorted[1];  // inclusive: the two smallest are inside
  EXPECT_DOUBLE_EQ(relation_nees(est, cov, rel, o).fraction_inside, 2.0 / 3.0);

  cov.pop_back();
  EXPECT_THROW((void)relation_nees(est, cov, rel), ConfigError);
}

}  // namespace
}  // namespace vdtnav::eval
