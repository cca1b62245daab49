// Umeyama alignment: a known random similarity / rigid transform is recovered exactly from
// noise-free points and near-optimally from noisy ones (checked against Eigen::umeyama and by
// perturbing the solution), in 2D, 3D and a run-time dimension; degenerate inputs say so.
#include "vdtnav/eval/umeyama.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <type_traits>

#include <Eigen/Geometry>

#include "vdtnav/core/error.hpp"

namespace vdtnav::eval {
namespace {

constexpr double kPi = 3.14159265358979323846;

template <int Dim>
using Points = Eigen::Matrix<double, Dim, Eigen::Dynamic>;

Eigen::VectorXd random_vector(int dim, std::mt19937_64& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  Eigen::VectorXd v(dim);
  for (int i = 0; i < dim; ++i) v[i] = u(rng);
  return v;
}

/// A uniformly random rotation: the Q of a Gaussian matrix's QR with det fixed to +1.
Eigen::MatrixXd random_rotation(int dim, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd g(dim, dim);
  for (int i = 0; i < g.size(); ++i) g.data()[i] = normal(rng);
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(g);
  Eigen::MatrixXd q = qr.householderQ();
  const Eigen::VectorXd sign = qr.matrixQR().diagonal().array().sign();
  q = q * sign.asDiagonal();
  if (q.determinant() < 0) q.col(0) *= -1.0;
  return q;
}

template <int Dim>
Points<Dim> random_points(int dim, int n, std::mt19937_64& rng, double spread) {
  std::uniform_real_distribution<double> u(-spread, spread);
  Points<Dim> p(dim, n);
  for (int i = 0; i < p.size(); ++i) p.data()[i] = u(rng);
  return p;
}

/// 1/n sum |y - (s R x + t)|^2 for any (R, t, s).
template <int Dim>
double cost(const Points<Dim>& x, const Points<Dim>& y, const Eigen::MatrixXd& r,
            const Eigen::VectorXd& t, double s) {
  Eigen::MatrixXd fitted = s * r * x;
  fitted.colwise() += t;
  return (y - fitted).squaredNorm() / static_cast<double>(x.cols());
}

template <typename T>
class UmeyamaTest : public ::testing::Test {};
using Dims = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(UmeyamaTest, Dims);

TYPED_TEST(UmeyamaTest, RecoversAKnownTransformFromNoiseFreePoints) {
  constexpr int kDim = TypeParam::value;
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    for (bool with_scale : {false, true}) {
      const Eigen::MatrixXd r = random_rotation(kDim, rng);
      const Eigen::VectorXd t = random_vector(kDim, rng, 10.0);
      const double s = with_scale ? 0.2 + 3.0 * std::abs(random_vector(1, rng, 1.0)[0]) : 1.0;
      const Points<kDim> x = random_points<kDim>(kDim, 30, rng, 5.0);
      Points<kDim> y = s * r * x;
      y.colwise() += t;
      const Similarity<kDim> est = umeyama<kDim>(x, y, with_scale);
      ASSERT_TRUE(est.ok());
      EXPECT_LT((est.rotation - r).norm(), 1e-10) << "trial " << trial;
      EXPECT_LT((est.translation - t).norm(), 1e-9) << "trial " << trial;
      EXPECT_NEAR(est.scale, s, 1e-11);
      EXPECT_LT(est.rmse, 1e-9);
      EXPECT_NEAR(est.rotation.determinant(), 1.0, 1e-12);
    }
  }
}

TYPED_TEST(UmeyamaTest, NoisyPointsGiveTheLeastSquaresOptimum) {
  constexpr int kDim = TypeParam::value;
  std::mt19937_64 rng(12);
  std::normal_distribution<double> noise(0.0, 0.05);
  for (bool with_scale : {false, true}) {
    const Eigen::MatrixXd r = random_rotation(kDim, rng);
    const Eigen::VectorXd t = random_vector(kDim, rng, 10.0);
    const double s = with_scale ? 1.7 : 1.0;
    const int n = 400;
    const Points<kDim> x = random_points<kDim>(kDim, n, rng, 5.0);
    Points<kDim> y = s * r * x;
    y.colwise() += t;
    for (int i = 0; i < y.size(); ++i) y.data()[i] += noise(rng);
    const Similarity<kDim> est = umeyama<kDim>(x, y, with_scale);
    ASSERT_TRUE(est.ok());
    // Close to the truth: the noise is small against the 10 m spread.
    EXPECT_LT((est.rotation - r).norm(), 5e-3);
    EXPECT_LT((est.translation - t).norm(), 2e-2);
    EXPECT_NEAR(est.scale, s, 5e-3);
    EXPECT_NEAR(est.rmse, 0.05 * std::sqrt(kDim), 0.01);
    // Independent implementation: Eigen's umeyama (homogeneous (Dim+1)^2 result).
    // (On dynamic-size copies: GCC 12 reports a false stringop-overread in Eigen's fixed 2D one.)
    const Eigen::MatrixXd h = Eigen::umeyama(Eigen::MatrixXd(x), Eigen::MatrixXd(y), with_scale);
    const double eigen_scale = std::pow(h.topLeftCorner(kDim, kDim).determinant(), 1.0 / kDim);
    EXPECT_LT((est.scale * est.rotation - h.topLeftCorner(kDim, kDim)).norm(), 1e-9);
    EXPECT_LT((est.translation - h.topRightCorner(kDim, 1)).norm(), 1e-9);
    EXPECT_NEAR(est.scale, eigen_scale, 1e-9);
    // Optimality: no perturbation of (R, t, s) lowers the cost.
    const double best = cost<kDim>(x, y, est.rotation, est.translation, est.scale);
    EXPECT_NEAR(best, est.rmse * est.rmse, 1e-12);
    for (int k = 0; k < 50; ++k) {
      const Eigen::MatrixXd w = random_vector(kDim * kDim, rng, 1e-3).reshaped(kDim, kDim);
      const Eigen::MatrixXd a = w - w.transpose();
      const Eigen::MatrixXd eye = Eigen::MatrixXd::Identity(kDim, kDim);
      const Eigen::MatrixXd cayley = (eye - a).inverse() * (eye + a);  // a rotation near I
      const Eigen::MatrixXd r2 = cayley * est.rotation;
      const Eigen::VectorXd t2 = est.translation + random_vector(kDim, rng, 1e-3);
      const double s2 = with_scale ? est.scale * (1.0 + 1e-3 * (k % 3 - 1)) : 1.0;
      EXPECT_GE(cost<kDim>(x, y, r2, t2, s2), best - 1e-12);
    }
  }
}

TYPED_TEST(UmeyamaTest, AMirroredTargetStillGivesAProperRotation) {
  constexpr int kDim = TypeParam::value;
  std::mt19937_64 rng(13);
  const Points<kDim> x = random_points<kDim>(kDim, 50, rng, 3.0);
  Points<kDim> y = x;
  y.row(0) *= -1.0;  // a reflection: no rotation fits exactly
  const Similarity<kDim> est = umeyama<kDim>(x, y, true);
  ASSERT_TRUE(est.ok());
  EXPECT_NEAR(est.rotation.determinant(), 1.0, 1e-12);
  EXPECT_GT(est.rmse, 0.1);
  const Eigen::MatrixXd h = Eigen::umeyama(Eigen::MatrixXd(x), Eigen::MatrixXd(y), true);
  EXPECT_LT((est.scale * est.rotation - h.topLeftCorner(kDim, kDim)).norm(), 1e-9);
}

TYPED_TEST(UmeyamaTest, DegenerateInputsSaySo) {
  constexpr int kDim = TypeParam::value;
  const Points<kDim> none(kDim, 0);
  EXPECT_EQ(umeyama<kDim>(none, none, false).status, AlignmentStatus::kTooFewPoints);
  Points<kDim> same(kDim, 5);
  same.colwise() = Eigen::Matrix<double, kDim, 1>::Constant(2.0);
  const Similarity<kDim> d = umeyama<kDim>(same, same, false);
  EXPECT_EQ(d.status, AlignmentStatus::kDegenerate);
  EXPECT_TRUE(d.rotation.isIdentity());
  // Two distinct points fix a 2D rotation, not a 3D one (the axis through them is free).
  Points<kDim> two = Points<kDim>::Zero(kDim, 2);
  two(0, 1) = 1.0;
  Points<kDim> two_rotated = Points<kDim>::Zero(kDim, 2);
  two_rotated(1, 1) = 1.0;
  const Similarity<kDim> t = umeyama<kDim>(two, two_rotated, false);
  if (kDim == 2) {
    ASSERT_TRUE(t.ok());
    EXPECT_NEAR(std::atan2(t.rotation(1, 0), t.rotation(0, 0)), 0.5 * kPi, 1e-12);
  } else {
    EXPECT_EQ(t.status, AlignmentStatus::kDegenerate);
  }
  const Points<kDim> other(kDim, 3);
  EXPECT_THROW((void)umeyama<kDim>(same, other, false), ConfigError);
}

TEST(Umeyama, RunTimeDimension) {
  std::mt19937_64 rng(14);
  const int dim = 5;
  const Eigen::MatrixXd r = random_rotation(dim, rng);
  const Eigen::VectorXd t = random_vector(dim, rng, 1.0);
  const Eigen::MatrixXd x = random_points<Eigen::Dynamic>(dim, 40, rng, 2.0);
  Eigen::MatrixXd y = 0.5 * r * x;
  y.colwise() += t;
  const Similarity<Eigen::Dynamic> est = umeyama<Eigen::Dynamic>(x, y, true);
  ASSERT_TRUE(est.ok());
  EXPECT_LT((est.rotation - r).norm(), 1e-10);
  EXPECT_LT((est.translation - t).norm(), 1e-10);
  EXPECT_NEAR(est.scale, 0.5, 1e-12);
}

TEST(Umeyama, PointListOverload) {
  const std::vector<Eigen::Vector2d> x = {{0, 0}, {1, 0}, {0, 2}};
  std::vector<Eigen::Vector2d> y;
  for (const auto& p : x) y.push_back(Eigen::Rotation2Dd(0.3) * p + Eigen::Vector2d(1, -2));
  const Similarity<2> est = umeyama(x, y, false);
  ASSERT_TRUE(est.ok());
  EXPECT_NEAR(std::atan2(est.rotation(1, 0), est.rotation(0, 0)), 0.3, 1e-12);
  EXPECT_LT((est.apply(x[2]) - y[2]).norm(), 1e-12);
}

}  // namespace
}  // namespace vdtnav::eval
