// The VDT EKF: the information-form update equals the batch formula, the motion models'
// Jacobians match finite differences, and the filter tracks a simulated run.
#include "vdtnav/estimation/vdt_ekf.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Cholesky>

#include "scan_fixture.hpp"

namespace vdtnav {
namespace {

TEST(EkfUpdate, InformationFormEqualsTheBatchFormula) {
  std::mt19937 rng(5);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const int beams = 1 + trial % 7;
    std::vector<Eigen::Vector2d> nu;
    std::vector<Eigen::Matrix<double, 2, 3>> h;
    std::vector<Eigen::Matrix2d> r;
    for (int i = 0; i < beams; ++i) {
      Eigen::Matrix<double, 2, 3> hi;
      for (int k = 0; k < 6; ++k) hi(k / 3, k % 3) = n01(rng);
      Eigen::Matrix2d a;
      a << n01(rng), n01(rng), n01(rng), n01(rng);
      h.push_back(hi);
      r.push_back(0.01 * a * a.transpose() + 1e-3 * Eigen::Matrix2d::Identity());
      nu.emplace_back(0.1 * n01(rng), 0.1 * n01(rng));
    }
    Eigen::Matrix3d a;
    for (int k = 0; k < 9; ++k) a(k / 3, k % 3) = n01(rng);
    const Eigen::Matrix3d p0 = 0.01 * a * a.transpose() + 1e-3 * Eigen::Matrix3d::Identity();
    Pose2 xb(1.0, 2.0, 0.3), xi = xb;
    Eigen::Matrix3d pb = p0, pi = p0;
    ekf_update_batch(nu, h, r, xb, pb);
    ekf_update_information(nu, h, r, xi, pi);
    ASSERT_LT((xb - xi).norm(), 1e-10);
    ASSERT_LT((pb - pi).norm(), 1e-10 * (1 + pb.norm()));
    ASSERT_GT(pi.ldlt().vectorD().minCoeff(), 0.0);  // stays positive definite
  }
}

TEST(EkfPredict, VelocityModelIsThesisEquationsAndItsJacobianIsExact) {
  MotionNoise noise;
  noise.floor_xy_rate = noise.floor_yaw_rate = 0.0;  // (3.8) alone
  OdometryStep odo;
  odo.dt = 0.1;
  odo.v = 0.5;
  odo.w = 0.3;
  const Pose2 x0(1.0, -1.0, 0.7);
  Pose2 x = x0;
  Eigen::Matrix3d p = Eigen::Matrix3d::Zero();
  ekf_predict(MotionModelKind::kVelocity, noise, odo, x, p);
  // (3.7)
  EXPECT_NEAR(x[0], 1.0 + 0.1 * 0.5 * std::cos(0.7), 1e-15);
  EXPECT_NEAR(x[1], -1.0 + 0.1 * 0.5 * std::sin(0.7), 1e-15);
  EXPECT_NEAR(x[2], 0.7 + 0.03, 1e-15);
  // With P = 0 the covariance is Gu Q Gu^T: Monte Carlo over noisy (v, w).
  std::mt19937 rng(1);
  std::normal_distribution<double> nv(0.0, noise.sigma_v), nw(0.0, noise.sigma_w);
  Eigen::Matrix3d mc = Eigen::Matrix3d::Zero();
  const int n = 50000;
  for (int k = 0; k < n; ++k) {
    OdometryStep o = odo;
    o.v += nv(rng);
    o.w += nw(rng);
    Pose2 y = x0;
    Eigen::Matrix3d q = Eigen::Matrix3d::Zero();
    ekf_predict(MotionModelKind::kVelocity, noise, o, y, q);
    const Eigen::Vector3d e = pose_error(y, x);
    mc += e * e.transpose() / n;
  }
  EXPECT_LT((mc - p).norm(), 0.03 * p.norm());
}

TEST(EkfPredict, OdometryIncrementModelComposesAndPropagatesLinearly) {
  OdometryStep odo;
  odo.delta = Pose2(0.1, 0.02, 0.05);
  const Pose2 x0(0.5, 0.5, -2.0);
  Eigen::Matrix3d p0 = Eigen::Matrix3d::Identity() * 1e-4;
  Pose2 x = x0;
  Eigen::Matrix3d p = p0;
  MotionNoise noise;
  ekf_predict(MotionModelKind::kOdometryIncrement, noise, odo, x, p);
  EXPECT_LT((x - compose(x0, odo.delta)).norm(), 1e-15);
  // Finite-difference Jacobian of compose in x: P grows at least by F P0 F^T.
  Eigen::Matrix3d f;
  for (int k = 0; k < 3; ++k) {
    const Pose2 e = Pose2::Unit(k) * 1e-6;
    f.col(k) = pose_error(compose(x0 + e, odo.delta), compose(x0 - e, odo.delta)) / 2e-6;
  }
  const Eigen::Matrix3d lower = f * p0 * f.transpose();
  EXPECT_GT((p - lower).ldlt().vectorD().minCoeff(), 0.0);
}

TEST(VdtEkfLocalizer, TracksAShortRunAndReportsTooFewObservations) {
  VdtEkfOptions o;
  VdtEkfLocalizer ekf(test::world().map, o);
  std::mt19937 rng(8);
  Pose2 truth = test::tour_pose(5);
  ekf.reset(truth + Pose2(0.05, -0.05, 0.02), Eigen::Vector3d(0.004, 0.004, 0.001).asDiagonal());
  OdometryStep odo;
  odo.dt = 0.025;
  odo.v = 0.4;
  odo.w = 0.1;
  LocalizationResult r;
  for (int k = 0; k < 40; ++k) {
    truth = Pose2(truth[0] + odo.dt * odo.v * std::cos(truth[2]),
                  truth[1] + odo.dt * odo.v * std::sin(truth[2]), truth[2] + odo.dt * odo.w);
    r = ekf.update(odo, test::simulate_scan(truth, 0.02, rng, 541));
    ASSERT_EQ(r.status, LocalizationStatus::kConverged);
    ASSERT_GT(r.covariance.ldlt().vectorD().minCoeff(), 0.0);
  }
  const Eigen::Vector3d e = pose_error(r.pose, truth);
  EXPECT_LT(e.head<2>().norm(), 0.02);
  EXPECT_LT(std::abs(e[2]), 0.01);
  const Pose2 before = r.pose;
  const LocalizationResult none = ekf.update(odo, LaserScan{});
  EXPECT_EQ(none.status, LocalizationStatus::kTooFewObservations);
  EXPECT_GT((none.pose - before).norm(), 0.0);  // predicted by odometry only
  EXPECT_GT(none.covariance.trace(), r.covariance.trace());
}

}  // namespace
}  // namespace vdtnav
