// The marginal covariance of part of a sparse problem's unknowns (Takahashi's selected inverse
// plus the Woodbury term of the few coupled-to-all unknowns) against the dense inverse of the
// same information matrix.
#include "vdtnav/mapping/marginal_covariance.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Dense>

namespace vdtnav::mapping {
namespace {

/// H = J^T J + lambda I of a random problem shaped like the map's fit: n_a unknowns on a line
/// coupled to their neighbours within `reach` (control points sharing a patch), n_d unknowns
/// coupled to random stretches of the line (scan poses seeing part of the map).
Eigen::SparseMatrix<double> random_information(int n_a, int n_d, int reach, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_int_distribution<int> start(0, n_a - 1);
  std::vector<Eigen::Triplet<double>> t;
  int row = 0;
  for (int r = 0; r < 3 * n_a; ++r, ++row) {  // local residuals
    const int c0 = start(rng);
    for (int c = c0; c < std::min(n_a, c0 + reach); ++c) t.emplace_back(row, c, normal(rng));
  }
  for (int d = 0; d < n_d; ++d) {  // residuals tying one "pose" to a stretch of the line
    const int c0 = start(rng);
    for (int r = 0; r < 8; ++r, ++row) {
      t.emplace_back(row, n_a + d, normal(rng));
      for (int c = c0; c < std::min(n_a, c0 + 12); ++c) {
        if (rng() % 3 == 0) t.emplace_back(row, c, normal(rng));
      }
    }
  }
  Eigen::SparseMatrix<double> j(row, n_a + n_d);
  j.setFromTriplets(t.begin(), t.end());
  Eigen::SparseMatrix<double> h = j.transpose() * j;
  for (int i = 0; i < n_a + n_d; ++i) h.coeffRef(i, i) += 0.1;  // a weak prior on everything
  return h;
}

class MarginalCovarianceTest : public ::testing::TestWithParam<int> {};

TEST_P(MarginalCovarianceTest, EqualsTheDenseInverseOnTheFactorsPattern) {
  const int n_a = 300, n_d = GetParam();
  const Eigen::SparseMatrix<double> h = random_information(n_a, n_d, 4, 7 + n_d);
  const Eigen::MatrixXd dense = Eigen::MatrixXd(h).inverse();
  MarginalCovariance mc;
  ASSERT_TRUE(mc.compute(h, n_a));
  EXPECT_EQ(mc.y().cols(), n_d);
  int checked = 0;
  double worst = 0.0;
  for (int a = 0; a < n_a; ++a) {
    for (int b = 0; b < n_a; ++b) {
      const double c = mc.covariance(a, b);
      if (std::isnan(c)) {
        // Off the pattern: only pairs H does not couple may be missing.
        EXPECT_EQ(h.coeff(a, b), 0.0) << a << ", " << b;
        continue;
      }
      worst = std::max(worst, std::abs(c - dense(a, b)) / std::sqrt(dense(a, a) * dense(b, b)));
      ++checked;
    }
  }
  EXPECT_LT(worst, 1e-9);
  // Every pair H couples is there, and the fill-in beyond.
  const Eigen::SparseMatrix<double> a = h.topLeftCorner(n_a, n_a);
  EXPECT_GE(checked, a.nonZeros());
}

INSTANTIATE_TEST_SUITE_P(WithAndWithoutCoupledUnknowns, MarginalCovarianceTest,
                         ::testing::Values(0, 1, 12));

TEST(MarginalCovariance, RefusesAMatrixThatIsNotPositiveDefinite) {
  Eigen::SparseMatrix<double> h = random_information(50, 3, 3, 3);
  for (int i = 0; i < 53; ++i) h.coeffRef(i, i) -= 100.0;
  MarginalCovariance mc;
  EXPECT_FALSE(mc.compute(h, 50));
  EXPECT_TRUE(std::isnan(mc.z(0, 0)));
}

}  // namespace
}  // namespace vdtnav::mapping
