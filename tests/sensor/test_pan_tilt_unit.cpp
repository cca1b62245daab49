// Pan-tilt point-laser geometry: the point of a reading against an independently composed
// transform chain and a hand-computed case, the sign conventions, the analytic derivatives against
// central finite differences, and the observation set's drop rules.
#include "vdtnav/sensor/pan_tilt_unit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "vdtnav/sensor/point_laser_observations.hpp"

namespace vdtnav {
namespace {

/// A calibration with a rotated, translated mount and non-zero offsets.
PanTiltCalibration random_calibration(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  PanTiltCalibration c;
  c.mount = pose3_from_xyz_rpy(0.3 * u(rng), 0.3 * u(rng), 0.4 + 0.1 * u(rng), 0.2 * u(rng),
                               0.2 * u(rng), kPi * u(rng));
  c.pan_to_tilt = 0.05 * Eigen::Vector3d(u(rng), u(rng), u(rng));
  c.tilt_to_laser = 0.05 * Eigen::Vector3d(u(rng), u(rng), u(rng));
  return c;
}

/// The frame chain composed explicitly: mount, pan about z, offset, tilt about y, offset, range.
Eigen::Vector3d chain_point(const PanTiltCalibration& c, double pan, double tilt, double r) {
  Eigen::Isometry3d t = c.mount;
  t = t * Eigen::AngleAxisd(pan, Eigen::Vector3d::UnitZ());
  t = t * Eigen::Translation3d(c.pan_to_tilt);
  t = t * Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitY());
  t = t * Eigen::Translation3d(c.tilt_to_laser);
  t = t * Eigen::Translation3d(r, 0.0, 0.0);
  return t * Eigen::Vector3d::Zero();
}

TEST(PanTiltUnit, PointEqualsTheComposedTransformChain) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-kPi, kPi), range(0.05, 40.0);
  for (int k = 0; k < 200; ++k) {
    const PanTiltCalibration c = random_calibration(rng);
    const double pan = angle(rng), tilt = 0.5 * angle(rng), r = range(rng);
    const PanTiltPoint p = pan_tilt_point(c, pan, tilt, r);
    EXPECT_LT((p.point - chain_point(c, pan, tilt, r)).norm(), 1e-12 * (1.0 + r));
    // The laser frame: beam origin plus r along its x axis, and that axis is dp/dr.
    const Pose3 laser = pan_tilt_laser_pose(c, pan, tilt);
    EXPECT_LT((laser * Eigen::Vector3d(r, 0, 0) - p.point).norm(), 1e-12 * (1.0 + r));
    EXPECT_LT((laser.linear().col(0) - p.d_range).norm(), 1e-14);
    EXPECT_NEAR(p.d_range.norm(), 1.0, 1e-14);
  }
}

TEST(PanTiltUnit, HandComputedPan90) {
  // Mount 0.1 m ahead of and 0.3 m above the robot origin, axes aligned with the robot's.
  PanTiltCalibration c;
  c.mount.translation() = Eigen::Vector3d(0.1, 0.0, 0.3);
  c.pan_to_tilt = Eigen::Vector3d(0.0, 0.0, 0.05);
  c.tilt_to_laser = Eigen::Vector3d(0.02, 0.0, 0.01);
  // Pan 90 deg, tilt 0: the panned x axis is the robot's +y, so (o_pt + o_l + r e_x) =
  // (2.02, 0, 0.06) in the panned frame becomes (0, 2.02, 0.06), plus the mount.
  const PanTiltPoint p = pan_tilt_point(c, kPi / 2, 0.0, 2.0);
  EXPECT_NEAR(p.point.x(), 0.1, 1e-15);
  EXPECT_NEAR(p.point.y(), 2.02, 1e-15);
  EXPECT_NEAR(p.point.z(), 0.36, 1e-15);
  EXPECT_LT((p.d_range - Eigen::Vector3d::UnitY()).norm(), 1e-15);
  // Turning about z moves the point along -x at radius 2.02 (tangent), not up or down.
  EXPECT_LT((p.d_pan - Eigen::Vector3d(-2.02, 0.0, 0.0)).norm(), 1e-14);
  // Tilting (about the panned y = robot -x) swings the beam end down: d/dtilt = e_y x (2.02, 0,
  // 0.01) in the tilted frame = (0.01, 0, -2.02), i.e. (0, 0.01, -2.02) after the pan.
  EXPECT_LT((p.d_tilt - Eigen::Vector3d(0.0, 0.01, -2.02)).norm(), 1e-14);
}

TEST(PanTiltUnit, PositivePanTurnsLeftAndPositiveTiltLooksDown) {
  const PanTiltCalibration c;  // identity mount, no offsets
  const double a = 0.3;
  EXPECT_LT(
      (pan_tilt_point(c, a, 0.0, 1.0).d_range - Eigen::Vector3d(std::cos(a), std::sin(a), 0.0))
          .norm(),
      1e-15);
  EXPECT_LT(
      (pan_tilt_point(c, 0.0, a, 1.0).d_range - Eigen::Vector3d(std::cos(a), 0.0, -std::sin(a)))
          .norm(),
      1e-15);
  // Pan is applied first (outer): pan 90 deg then tilt down looks along +y and down.
  const Eigen::Vector3d d = pan_tilt_point(c, kPi / 2, a, 1.0).d_range;
  EXPECT_NEAR(d.x(), 0.0, 1e-15);
  EXPECT_NEAR(d.y(), std::cos(a), 1e-15);
  EXPECT_NEAR(d.z(), -std::sin(a), 1e-15);
}

TEST(PanTiltUnit, DerivativesMatchCentralDifferences) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(-kPi, kPi), range(0.05, 40.0);
  const double h = 1e-6;
  for (int k = 0; k < 200; ++k) {
    const PanTiltCalibration c = random_calibration(rng);
    const double pan = angle(rng), tilt = 0.5 * angle(rng), r = range(rng);
    const PanTiltPoint p = pan_tilt_point(c, pan, tilt, r);
    const auto at = [&](double dp, double dt, double dr) {
      return chain_point(c, pan + dp, tilt + dt, r + dr);
    };
    const Eigen::Vector3d fd_r = (at(0, 0, h) - at(0, 0, -h)) / (2 * h);
    const Eigen::Vector3d fd_pan = (at(h, 0, 0) - at(-h, 0, 0)) / (2 * h);
    const Eigen::Vector3d fd_tilt = (at(0, h, 0) - at(0, -h, 0)) / (2 * h);
    const double tol = 1e-8 * (1.0 + r);
    EXPECT_LT((p.d_range - fd_r).norm(), tol);
    EXPECT_LT((p.d_pan - fd_pan).norm(), tol);
    EXPECT_LT((p.d_tilt - fd_tilt).norm(), tol);
  }
}

TEST(ObservationSet3, DropsAndCountsInvalidReadings) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const PanTiltCalibration c = PanTiltCalibration::turtlebot_example();
  const std::vector<PanTiltReading> readings = {
      {0.1, 0.2, 3.0, 0.0},    // kept (reading 0)
      {0.1, 0.2, kInf, 0.0},   // no return
      {0.1, 0.2, kNaN, 0.0},   // not a number
      {kNaN, 0.2, 3.0, 0.0},   // bad pan
      {0.1, kInf, 3.0, 0.0},   // bad tilt
      {0.1, 0.2, 0.04, 0.0},   // below 0.05 m
      {0.1, 0.2, 0.05, 0.0},   // at range_min: kept (reading 6)
      {0.1, 0.2, 40.0, 0.0},   // at range_max: dropped
      {0.1, 0.2, -1.0, 0.0},   // negative
      {-2.0, -0.3, 39.9, 0.0}  // kept (reading 9)
  };
  const ObservationSet3 obs = point_laser_observations(readings, c);
  EXPECT_EQ(obs.size(), 3u);
  EXPECT_EQ(obs.dropped_not_finite, 4u);
  EXPECT_EQ(obs.dropped_out_of_range, 3u);
  EXPECT_EQ(obs.beam, (std::vector<std::size_t>{0, 6, 9}));
  EXPECT_EQ(obs.sigma_range, 0.025);
  ASSERT_EQ(obs.directions.size(), 3u);
  ASSERT_EQ(obs.ranges.size(), 3u);
  for (std::size_t k = 0; k < obs.size(); ++k) {
    const PanTiltReading& z = readings[obs.beam[k]];
    EXPECT_EQ(obs.ranges[k], z.range);
    EXPECT_LT((obs.points[k] - chain_point(c, z.pan, z.tilt, z.range)).norm(), 1e-12 * z.range);
    EXPECT_LT((obs.directions[k] - pan_tilt_point(c, z).d_range).norm(), 1e-15);
  }
  PointLaserSpec narrow;
  narrow.range_min = 1.0;
  narrow.range_max = 10.0;
  narrow.sigma_range = 0.1;
  const ObservationSet3 n = point_laser_observations(readings, c, narrow);
  EXPECT_EQ(n.beam, (std::vector<std::size_t>{0}));
  EXPECT_EQ(n.dropped_out_of_range, 5u);
  EXPECT_EQ(n.sigma_range, 0.1);
}

}  // namespace
}  // namespace vdtnav
