// Bearings to known landmarks in the EKF: the observation's Jacobian against finite differences,
// the information-form update against the batch formula K = P H^T S^-1, association among
// landmarks of one class and the gate against false detections, and consistency by Monte Carlo.
#include "vdtnav/estimation/bearing_update.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "vdtnav/core/error.hpp"

namespace vdtnav {
namespace {

const std::vector<Landmark2>& park_landmarks() {
  static const std::vector<Landmark2> kLandmarks{
      {{6.0, 2.0}, 0}, {{-4.0, 5.0}, 0}, {{1.0, -7.0}, 1}, {{9.0, -3.0}, 1}, {{-6.0, -4.0}, 0}};
  return kLandmarks;
}

TEST(BearingUpdate, JacobianMatchesCentralDifferences) {
  const Eigen::Vector2d offset(-0.4, 0.15);  // a rear-mounted detector
  for (const Pose2& x : {Pose2(0.3, -0.2, 0.4), Pose2(-1.0, 2.0, -2.9), Pose2(2.0, 1.0, 3.1)}) {
    for (const Landmark2& l : park_landmarks()) {
      Eigen::RowVector3d h;
      (void)predicted_bearing(x, l.position, offset, &h);
      for (int k = 0; k < 3; ++k) {
        const double e = 1e-6;
        Pose2 a = x, b = x;
        a[k] += e;
        b[k] -= e;
        const double fd = wrap_angle(predicted_bearing(a, l.position, offset, nullptr) -
                                     predicted_bearing(b, l.position, offset, nullptr)) /
                          (2.0 * e);
        EXPECT_NEAR(h[k], fd, 1e-7) << "component " << k;
      }
    }
  }
}

TEST(BearingUpdate, EqualsTheBatchKalmanUpdate) {
  const Pose2 truth(0.5, 0.5, 0.3);
  Pose2 x(0.6, 0.42, 0.33);
  Eigen::Matrix3d p;
  p << 0.04, 0.01, 0.0, 0.01, 0.05, 0.002, 0.0, 0.002, 0.01;
  std::vector<BearingDetection> z;
  const BearingUpdateOptions o;
  for (const Landmark2& l : park_landmarks()) {
    BearingDetection d;
    d.bearing = predicted_bearing(truth, l.position, o.sensor_offset, nullptr);
    d.sigma = 0.03;
    d.label = l.label;
    z.push_back(d);
  }
  // Reference: stacked H, diagonal R, S = H P H^T + R, K = P H^T S^-1, dx = K nu, P+ = P - K S K^T.
  const int n = static_cast<int>(z.size());
  Eigen::MatrixXd h(n, 3);
  Eigen::VectorXd nu(n);
  for (int i = 0; i < n; ++i) {
    Eigen::RowVector3d hi;
    nu[i] = wrap_angle(z[static_cast<std::size_t>(i)].bearing -
                       predicted_bearing(x, park_landmarks()[static_cast<std::size_t>(i)].position,
                                         o.sensor_offset, &hi));
    h.row(i) = hi;
  }
  const Eigen::MatrixXd r = Eigen::VectorXd::Constant(n, 0.03 * 0.03).asDiagonal();
  const Eigen::MatrixXd s = h * p * h.transpose() + r;
  const Eigen::MatrixXd k = p * h.transpose() * s.inverse();
  const Eigen::Vector3d dx = k * nu;
  const Eigen::Matrix3d p_ref = p - k * s * k.transpose();
  const Pose2 x_ref(x[0] + dx[0], x[1] + dx[1], wrap_angle(x[2] + dx[2]));

  const BearingUpdateResult res = ekf_bearing_update(z, park_landmarks(), o, x, p);
  EXPECT_EQ(res.accepted, n);
  EXPECT_EQ(res.rejected, 0);
  for (int i = 0; i < n; ++i) EXPECT_EQ(res.landmark[static_cast<std::size_t>(i)], i);
  EXPECT_LT((x - x_ref).norm(), 1e-12);
  EXPECT_LT((p - p_ref).norm(), 1e-12);
}

TEST(BearingUpdate, AssociatesWithinAClassAndGatesFalseDetections) {
  const Pose2 truth(0.0, 0.0, 0.0);
  const Pose2 x(0.05, -0.03, 0.02);
  const Eigen::Matrix3d p0 = Eigen::Vector3d(0.01, 0.01, 0.001).asDiagonal();
  const BearingUpdateOptions o;
  std::vector<BearingDetection> z;
  // The class-0 landmark at (-4, 5), reported as class 0 (two other class-0 landmarks exist).
  z.push_back(
      {predicted_bearing(truth, park_landmarks()[1].position, o.sensor_offset, nullptr), 0.02, 0});
  // A class-1 landmark reported without a class.
  z.push_back(
      {predicted_bearing(truth, park_landmarks()[3].position, o.sensor_offset, nullptr), 0.02, -1});
  // False positives: a bearing pointing at no landmark, and a class-1 bearing toward a class-0
  // landmark (no class-1 landmark lies in that direction).
  z.push_back({-2.0, 0.02, -1});
  z.push_back(
      {predicted_bearing(truth, park_landmarks()[0].position, o.sensor_offset, nullptr), 0.02, 1});
  Pose2 xu = x;
  Eigen::Matrix3d p = p0;
  const BearingUpdateResult r = ekf_bearing_update(z, park_landmarks(), o, xu, p);
  EXPECT_EQ(r.landmark[0], 1);
  EXPECT_EQ(r.landmark[1], 3);
  EXPECT_EQ(r.landmark[2], -1);
  EXPECT_EQ(r.landmark[3], -1);
  EXPECT_EQ(r.accepted, 2);
  EXPECT_EQ(r.rejected, 2);
  // The two accepted bearings are explained better after the update, and the covariance shrinks.
  for (int k : {0, 1}) {
    const Eigen::Vector2d l = park_landmarks()[static_cast<std::size_t>(r.landmark[k])].position;
    const double before =
        wrap_angle(z[k].bearing - predicted_bearing(x, l, o.sensor_offset, nullptr));
    const double after =
        wrap_angle(z[k].bearing - predicted_bearing(xu, l, o.sensor_offset, nullptr));
    EXPECT_LT(std::abs(after), 0.5 * std::abs(before)) << "detection " << k;
  }
  EXPECT_LT(p.trace(), p0.trace());
  // Bad input.
  z[0].sigma = 0.0;
  EXPECT_THROW((void)ekf_bearing_update(z, park_landmarks(), o, xu, p), ConfigError);
}

TEST(BearingUpdate, ALandmarkIsUsedOncePerFrameByItsNearestDetection) {
  // A true detection of landmark 1 and a false one 0.03 rad beside it (inside the gate): the
  // update must equal the one with the true detection alone, whichever comes first.
  const Pose2 x(0.05, -0.03, 0.02);
  const Eigen::Matrix3d p0 = Eigen::Vector3d(0.01, 0.01, 0.001).asDiagonal();
  const BearingUpdateOptions o;
  const double b =
      predicted_bearing(Pose2::Zero(), park_landmarks()[1].position, o.sensor_offset, nullptr);
  const BearingDetection good{b, 0.02, 0}, beside{b + 0.03, 0.02, 0};
  Pose2 x1 = x;
  Eigen::Matrix3d p1 = p0;
  (void)ekf_bearing_update({good}, park_landmarks(), o, x1, p1);
  for (const auto& z :
       {std::vector<BearingDetection>{good, beside}, std::vector<BearingDetection>{beside, good}}) {
    Pose2 x2 = x;
    Eigen::Matrix3d p2 = p0;
    const BearingUpdateResult r = ekf_bearing_update(z, park_landmarks(), o, x2, p2);
    EXPECT_EQ(r.accepted, 1);
    EXPECT_EQ(r.rejected, 1);
    EXPECT_LT((x2 - x1).norm(), 1e-12);
    EXPECT_LT((p2 - p1).norm(), 1e-15);
  }
}

TEST(BearingUpdate, TheUpdatedCovarianceIsConsistentByMonteCarlo) {
  // Prior and bearings drawn from their distributions: the NEES of the updated estimate has mean
  // 3 (chi-square, 3 dof); over 2000 trials its 99 % interval is [2.86, 3.14] for a linear model,
  // widened here by the bearings' curvature over the prior's spread.
  std::mt19937 rng(5);
  std::normal_distribution<double> n01(0.0, 1.0);
  const Pose2 truth(0.2, -0.4, 0.7);
  const Eigen::Matrix3d p0 = Eigen::Vector3d(0.04, 0.04, 0.004).asDiagonal();
  const Eigen::Matrix3d l0 = p0.llt().matrixL();
  const BearingUpdateOptions o;
  double nees = 0.0;
  const int trials = 2000;
  for (int t = 0; t < trials; ++t) {
    const Eigen::Vector3d e0 = l0 * Eigen::Vector3d(n01(rng), n01(rng), n01(rng));
    Pose2 x(truth[0] + e0[0], truth[1] + e0[1], truth[2] + e0[2]);
    Eigen::Matrix3d p = p0;
    std::vector<BearingDetection> z;
    for (const Landmark2& l : park_landmarks()) {
      z.push_back({predicted_bearing(truth, l.position, o.sensor_offset, nullptr) + 0.02 * n01(rng),
                   0.02, l.label});
    }
    (void)ekf_bearing_update(z, park_landmarks(), o, x, p);
    Eigen::Vector3d e = x - truth;
    e[2] = wrap_angle(e[2]);
    nees += e.dot(p.inverse() * e);
  }
  nees /= trials;
  EXPECT_GT(nees, 2.8);
  EXPECT_LT(nees, 3.3);
}

}  // namespace
}  // namespace vdtnav
