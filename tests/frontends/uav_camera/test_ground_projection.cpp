// Ground projection of edge pixels: hand-derived cases, an independent ray-plane intersection
// (Eigen::Hyperplane / ParametrizedLine), every Jacobian against central differences, and the
// per-point covariance against Monte Carlo.
#include "vdtnav/uav_camera/ground_projection.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

namespace vdtnav::uav_camera {
namespace {

constexpr double kDeg = kPi / 180.0;

CameraCalibration wide_lens(bool distorted = true) {
  CameraCalibration c;
  c.width = 640;
  c.height = 480;
  c.camera_matrix << 400.0, 0.0, 321.3, 0.0, 401.5, 238.7, 0.0, 0.0, 1.0;
  if (distorted) c.distortion = {-0.28, 0.09, 0.0012, -0.0007, -0.012};
  return c;
}

/// A rig that is not the default: camera off the body origin and tilted forward 10 deg, laser
/// off the origin and tilted too.
UavRig offset_rig() {
  UavRig rig;
  rig.body_from_camera.linear() =
      Eigen::AngleAxisd(10 * kDeg, Eigen::Vector3d::UnitY()).toRotationMatrix() *
      UavRig::default_body_from_camera().linear();
  rig.body_from_camera.translation() = Eigen::Vector3d(0.12, -0.05, -0.08);
  rig.laser_origin = Eigen::Vector3d(-0.03, 0.04, -0.06);
  rig.laser_direction = Eigen::Vector3d(0.05, -0.03, -1.0).normalized();
  return rig;
}

TEST(GroundProjection, LevelCameraLookingDown) {
  // Default rig, level: camera at (0, 0, h), m = R_bc (x_n, y_n, 1) = (-y_n, -x_n, -1), so the
  // ray reaches z = 0 at s = h: p = (-h y_n, -h x_n). Image up (-y_n) is the front (+x).
  const UavRig rig;
  const AttitudeReading a{0.0, 0.0, 25.0};
  EXPECT_DOUBLE_EQ(altitude(a, rig), 25.0);
  const GroundPoint c = project_to_ground({0.0, 0.0}, a, rig);
  ASSERT_TRUE(c.valid);
  EXPECT_NEAR(c.p.norm(), 0.0, 1e-12);
  const GroundPoint g = project_to_ground({0.2, -0.1}, a, rig);
  ASSERT_TRUE(g.valid);
  EXPECT_NEAR(g.p.x(), 2.5, 1e-12);   // -h y_n
  EXPECT_NEAR(g.p.y(), -5.0, 1e-12);  // -h x_n: image right is the body's right (-y)
  // Through the camera: the principal point is (0, 0) whatever the distortion.
  const PinholeCamera cam(wide_lens());
  const ObservationSet2 obs = ground_observations({{321.3, 238.7}}, cam, rig, a);
  ASSERT_EQ(obs.size(), 1U);
  EXPECT_NEAR(obs.points[0].norm(), 0.0, 1e-9);
}

TEST(GroundProjection, PitchedNoseDownLooksBehind) {
  // REP-103: positive pitch is nose down; the downward camera then looks backward. The laser
  // (along the camera axis) measures r = h / cos(pitch), and the principal ray hits at
  // x = -h tan(pitch) = -r sin(pitch).
  const UavRig rig;
  const double pitch = 12 * kDeg;
  const AttitudeReading a{0.0, pitch, 30.0};
  EXPECT_NEAR(altitude(a, rig), 30.0 * std::cos(pitch), 1e-12);
  const GroundPoint g = project_to_ground({0.0, 0.0}, a, rig);
  ASSERT_TRUE(g.valid);
  EXPECT_NEAR(g.p.x(), -30.0 * std::sin(pitch), 1e-12);
  EXPECT_NEAR(g.p.y(), 0.0, 1e-12);
  // Positive roll (right wing down) makes the camera look left (+y).
  const GroundPoint r = project_to_ground({0.0, 0.0}, {10 * kDeg, 0.0, 30.0}, rig);
  EXPECT_NEAR(r.p.y(), 30.0 * std::sin(10 * kDeg), 1e-12);
}

/// The oracle: place the body so that the laser's end is on the ground, build the camera ray
/// from the pixel with K^-1, intersect it with the plane z = 0 using Eigen's geometry module.
Eigen::Vector2d oracle(const Eigen::Vector2d& pixel, const Eigen::Matrix3d& k,
                       const AttitudeReading& a, const UavRig& rig) {
  const Eigen::Matrix3d r = (Eigen::AngleAxisd(a.pitch, Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(a.roll, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  const Eigen::Hyperplane<double, 3> ground(Eigen::Vector3d::UnitZ(), 0.0);
  // Body at (0, 0, z): the laser line from the body must end on the ground after range r.
  const Eigen::Vector3d laser_end_from_body =
      r * (rig.laser_origin + a.laser_range * rig.laser_direction);
  const Eigen::Vector3d body(0.0, 0.0, -laser_end_from_body.z());
  const Eigen::Vector3d centre = body + r * rig.body_from_camera.translation();
  const Eigen::Vector3d ray =
      r * rig.body_from_camera.linear() * k.inverse() * Eigen::Vector3d(pixel.x(), pixel.y(), 1.0);
  const Eigen::ParametrizedLine<double, 3> line(centre, ray.normalized());
  return line.intersectionPoint(ground).head<2>();
}

TEST(GroundProjection, MatchesAnIndependentRayPlaneIntersection) {
  const CameraCalibration calib = wide_lens(false);
  const PinholeCamera cam(calib);
  for (const UavRig& rig : {UavRig{}, offset_rig()}) {
    for (const AttitudeReading& a :
         {AttitudeReading{0.0, 0.0, 20.0}, AttitudeReading{7 * kDeg, -4 * kDeg, 35.0},
          AttitudeReading{-15 * kDeg, 20 * kDeg, 12.0}}) {
      std::vector<Eigen::Vector2d> px;
      for (int v = 0; v < 480; v += 60) {
        for (int u = 0; u < 640; u += 80) px.emplace_back(u, v);
      }
      const ObservationSet2 obs = ground_observations(px, cam, rig, a);
      ASSERT_EQ(obs.size(), px.size());
      for (std::size_t i = 0; i < obs.size(); ++i) {
        const Eigen::Vector2d want = oracle(px[obs.beam[i]], calib.camera_matrix, a, rig);
        EXPECT_LT((obs.points[i] - want).norm(), 1e-9 * (1.0 + want.norm()))
            << "pixel " << px[obs.beam[i]].transpose() << " roll " << a.roll << " pitch "
            << a.pitch;
      }
    }
  }
}

TEST(GroundProjection, JacobiansMatchCentralDifferences) {
  const UavRig rig = offset_rig();
  const double eps = 1e-6;
  for (const AttitudeReading& a :
       {AttitudeReading{0.0, 0.0, 20.0}, AttitudeReading{9 * kDeg, -6 * kDeg, 40.0},
        AttitudeReading{-25 * kDeg, 30 * kDeg, 8.0}}) {
    for (const Eigen::Vector2d& n :
         {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.5, -0.3), Eigen::Vector2d(-0.4, 0.45)}) {
      const GroundPoint g = project_to_ground(n, a, rig);
      ASSERT_TRUE(g.valid);
      Eigen::Matrix2d fd_n;
      for (int k = 0; k < 2; ++k) {
        Eigen::Vector2d e = Eigen::Vector2d::Zero();
        e[k] = eps;
        fd_n.col(k) =
            (project_to_ground(n + e, a, rig).p - project_to_ground(n - e, a, rig).p) / (2 * eps);
      }
      EXPECT_LT((g.d_normalized - fd_n).norm(), 1e-6 * fd_n.norm());
      Eigen::Matrix<double, 2, 3> fd_a;
      for (int k = 0; k < 3; ++k) {
        AttitudeReading plus = a;
        AttitudeReading minus = a;
        double* pp = k == 0 ? &plus.roll : k == 1 ? &plus.pitch : &plus.laser_range;
        double* pm = k == 0 ? &minus.roll : k == 1 ? &minus.pitch : &minus.laser_range;
        *pp += eps;
        *pm -= eps;
        fd_a.col(k) =
            (project_to_ground(n, plus, rig).p - project_to_ground(n, minus, rig).p) / (2 * eps);
        EXPECT_LT((g.d_attitude.col(k) - fd_a.col(k)).norm(), 1e-6 * (1.0 + fd_a.col(k).norm()))
            << "parameter " << k << " at roll " << a.roll << " pitch " << a.pitch << " n "
            << n.transpose();
      }
    }
  }
}

TEST(GroundProjection, ObservationsCarryTheSharedAttitudeErrors) {
  const PinholeCamera cam(wide_lens());
  const UavRig rig = offset_rig();
  const AttitudeReading a{5 * kDeg, -3 * kDeg, 22.0};
  GroundProjectionNoise noise;
  noise.sigma_roll = 0.01;
  noise.sigma_pitch = 0.02;
  noise.sigma_laser_range = 0.1;
  const std::vector<Eigen::Vector2d> px{{100, 80}, {500, 400}, {320, 240}};
  const ObservationSet2 obs = ground_observations(px, cam, rig, a, noise);
  ASSERT_EQ(obs.size(), 3U);
  ASSERT_EQ(obs.num_shared(), 3);
  EXPECT_EQ(obs.sigma_range, 0.0);
  EXPECT_LT((obs.shared_covariance - Eigen::Vector3d(1e-4, 4e-4, 1e-2).asDiagonal().toDenseMatrix())
                .norm(),
            1e-15);
  const auto n = cam.undistort(px);
  for (std::size_t i = 0; i < 3; ++i) {
    const GroundPoint g = project_to_ground(n[i], a, rig);
    EXPECT_LT((obs.shared_jacobians[i] - g.d_attitude).norm(), 1e-12);
    EXPECT_LT((obs.points[i] - g.p).norm(), 1e-12);
  }
}

TEST(GroundProjection, CorrelatedErrorsCountOncePerSquare) {
  // Level camera at 20 m: pixel (u, v) lies at (-h y_n, -h x_n) on the ground. Three pixels whose
  // ground points share one 1 m square and one alone in another: the shared square's points get
  // 3 sigma_c^2, the lone point 1 sigma_c^2, on top of the covariance without the option.
  const PinholeCamera cam(wide_lens(false));
  const UavRig rig;
  const AttitudeReading a{0.0, 0.0, 20.0};
  const double f = cam.calibration().camera_matrix(0, 0);
  const double cx = cam.calibration().camera_matrix(0, 2);
  const double cy = cam.calibration().camera_matrix(1, 2);
  // Ground (x, y) -> pixel: x_n = -y / h, y_n = -x / h.
  const auto pixel = [&](double x, double y) {
    return Eigen::Vector2d(cx - f * y / 20.0, cy - f * x / 20.0);
  };
  const std::vector<Eigen::Vector2d> px{pixel(0.2, 0.3), pixel(0.7, 0.6), pixel(0.5, 0.9),
                                        pixel(2.5, -1.5)};
  GroundProjectionNoise plain;
  GroundProjectionNoise correlated = plain;
  correlated.sigma_correlated = 0.02;
  correlated.correlation_length = 1.0;
  const ObservationSet2 a0 = ground_observations(px, cam, rig, a, plain);
  const ObservationSet2 a1 = ground_observations(px, cam, rig, a, correlated);
  ASSERT_EQ(a1.size(), 4u);
  const double s2 = 0.02 * 0.02;
  for (std::size_t i = 0; i < 4; ++i) {
    const double n = i < 3 ? 3.0 : 1.0;
    const Eigen::Matrix2d extra = a1.point_covariances[i] - a0.point_covariances[i];
    EXPECT_NEAR(extra(0, 0), n * s2, 1e-12) << i;
    EXPECT_NEAR(extra(1, 1), n * s2, 1e-12) << i;
    EXPECT_NEAR(extra(0, 1), 0.0, 1e-12) << i;
  }
}

TEST(GroundProjection, PointCovarianceMatchesMonteCarlo) {
  const PinholeCamera cam(wide_lens());
  const UavRig rig = offset_rig();
  const AttitudeReading a{8 * kDeg, 6 * kDeg, 30.0};
  GroundProjectionNoise noise;
  noise.sigma_pixel = 0.5;
  const std::vector<Eigen::Vector2d> px{{40, 30}, {320, 240}, {600, 100}, {150, 450}};
  const ObservationSet2 nominal = ground_observations(px, cam, rig, a, noise);
  ASSERT_EQ(nominal.size(), px.size());
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss(0.0, noise.sigma_pixel);
  constexpr int kSamples = 20000;
  for (std::size_t i = 0; i < px.size(); ++i) {
    std::vector<Eigen::Vector2d> noisy(kSamples);
    for (auto& p : noisy) p = px[i] + Eigen::Vector2d(gauss(rng), gauss(rng));
    const ObservationSet2 obs = ground_observations(noisy, cam, rig, a, noise);
    ASSERT_EQ(obs.size(), noisy.size());
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : obs.points) mean += p;
    mean /= kSamples;
    Eigen::Matrix2d s = Eigen::Matrix2d::Zero();
    for (const auto& p : obs.points) s += (p - mean) * (p - mean).transpose();
    s /= kSamples - 1;
    // Whitened by the predicted covariance the sample covariance is the identity (10 %).
    const Eigen::Matrix2d cov = nominal.point_covariances[i];
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
    const Eigen::Matrix2d w = es.operatorInverseSqrt();
    const Eigen::Matrix2d white = w * s * w;
    EXPECT_LT((white - Eigen::Matrix2d::Identity()).cwiseAbs().maxCoeff(), 0.1)
        << "pixel " << px[i].transpose() << "\npredicted\n"
        << cov << "\nsample\n"
        << s;
  }
}

TEST(GroundProjection, UnusableAttitudeGivesAnEmptySetAndAReason) {
  const PinholeCamera cam(wide_lens());
  const UavRig rig;
  const std::vector<Eigen::Vector2d> px{{100, 100}, {200, 200}, {300, 300}};

  const AttitudeReading nan_roll{std::nan(""), 0.0, 20.0};
  EXPECT_EQ(check_attitude(nan_roll, rig), "roll is NaN");
  ObservationSet2 obs = ground_observations(px, cam, rig, nan_roll);
  EXPECT_EQ(obs.size(), 0U);
  EXPECT_EQ(obs.dropped_not_finite, 3U);
  EXPECT_EQ(obs.dropped_out_of_range, 0U);

  const AttitudeReading negative{0.0, 0.0, -1.2};
  EXPECT_EQ(check_attitude(negative, rig), "laser range -1.2 m: expected > 0");
  obs = ground_observations(px, cam, rig, negative);
  EXPECT_EQ(obs.size(), 0U);
  EXPECT_EQ(obs.dropped_out_of_range, 3U);
  EXPECT_EQ(obs.dropped_not_finite, 0U);

  UavRig up = rig;
  up.laser_direction = Eigen::Vector3d::UnitZ();  // pointing at the sky: negative altitude
  EXPECT_EQ(check_attitude({0.0, 0.0, 0.3}, up), "altitude -0.3 m: expected > 0");
  EXPECT_EQ(ground_observations(px, cam, up, {0.0, 0.0, 0.3}).dropped_out_of_range, 3U);

  EXPECT_EQ(check_attitude({0.0, 85 * kDeg, 10.0}, rig), "pitch 85 deg: expected |pitch| < 80 deg");
  EXPECT_EQ(ground_observations(px, cam, rig, {0.0, 85 * kDeg, 10.0}).size(), 0U);
  EXPECT_EQ(check_attitude({0.0, 0.0, 10.0}, rig), "");
}

TEST(GroundProjection, RaysAboveTheHorizonAreDroppedAsOutOfRange) {
  const PinholeCamera cam(wide_lens());
  const UavRig rig;
  // Pitched 60 deg nose up: the top of the image (the front) looks above the horizon.
  const AttitudeReading a{0.0, -60 * kDeg, 20.0};
  const std::vector<Eigen::Vector2d> px{{320, 5}, {320, 470}, {std::nan(""), 3.0}};
  const ObservationSet2 obs = ground_observations(px, cam, rig, a);
  EXPECT_EQ(obs.size(), 1U);
  EXPECT_EQ(obs.beam.at(0), 1U);
  EXPECT_EQ(obs.dropped_out_of_range, 1U);
  EXPECT_EQ(obs.dropped_not_finite, 1U);
}

}  // namespace
}  // namespace vdtnav::uav_camera
