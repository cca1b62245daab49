// The VDT sensor model: scan conversion, derivatives against finite differences, the disparity
// covariance against Monte Carlo, and the gate.
#include "vdtnav/sensor/vdt_sensor_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include <Eigen/LU>

namespace vdtnav {
namespace {

/// A 6 m x 4 m room (0.05 m cells) with a box in it.
OccupancyGrid<2> room() {
  OccupancyGrid<2> occ(Eigen::Vector2i(120, 80), GridFrame<2>(0.05, Eigen::Vector2d(-1.0, -0.5)),
                       0);
  for (int j = 0; j < 80; ++j)
    for (int i = 0; i < 120; ++i) {
      const bool wall = i == 2 || i == 117 || j == 2 || j == 77;
      const bool box = i >= 70 && i <= 80 && j >= 30 && j <= 40;
      occ(Eigen::Vector2i(i, j)) = (wall || box) ? 1 : 0;
    }
  return occ;
}

TEST(ScanPoints, DropsAndCountsInvalidReadingsAndAppliesTheMount) {
  LaserScan scan;
  scan.angle_min = -0.5;
  scan.angle_increment = 0.25;
  scan.range_min = 0.1;
  scan.range_max = 10.0;
  scan.mount = Pose2(0.2, -0.1, 0.3);
  scan.ranges = {1.0, std::nan(""), std::numeric_limits<double>::infinity(), 0.05, 10.0, 2.0};
  const ScanPoints pts = scan_points(scan);
  ASSERT_EQ(pts.size(), 2u);
  EXPECT_EQ(pts.dropped_not_finite, 2u);
  EXPECT_EQ(pts.dropped_out_of_range, 2u);  // 0.05 < range_min, 10.0 >= range_max
  // Beam 0 at angle -0.5 in the sensor frame: robot-frame point = mount (+) (r cos, r sin).
  const Eigen::Vector2d expected =
      transform_point(scan.mount, Eigen::Vector2d(std::cos(-0.5), std::sin(-0.5)));
  EXPECT_LT((pts.points[0] - expected).norm(), 1e-12);
  EXPECT_EQ(pts.beam[1], 5u);
  EXPECT_LT((pts.points[1] -
             transform_point(scan.mount, 2.0 * Eigen::Vector2d(std::cos(0.75), std::sin(0.75))))
                .norm(),
            1e-12);
  EXPECT_NEAR(pts.directions[1].norm(), 1.0, 1e-12);
}

class SensorModelTest : public ::testing::Test {
 protected:
  OccupancyGrid<2> occ_ = room();
  VdtMap2 map_ = VdtMap2::build(occ_);

  /// Beams that end within 0.2 m of an obstacle (where localization uses them), away from the
  /// cut loci, from random poses in the room.
  std::vector<std::pair<Pose2, std::pair<Eigen::Vector2d, Eigen::Vector2d>>> beams(int n) const {
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> ux(0.0, 4.5), uy(0.3, 3.0), ua(-3.1, 3.1), ur(0.5, 3.0);
    std::vector<std::pair<Pose2, std::pair<Eigen::Vector2d, Eigen::Vector2d>>> out;
    while (static_cast<int>(out.size()) < n) {
      const Pose2 x(ux(rng), uy(rng), ua(rng));
      const double a = ua(rng), r = ur(rng);
      const Eigen::Vector2d u(std::cos(a), std::sin(a)), p = r * u + Eigen::Vector2d(0.1, 0.05);
      const Eigen::Vector2d q = transform_point(x, p);
      const auto s = map_.evaluate(q);
      if (!s.inside || s.value.norm() > 0.2 || s.value.norm() < 0.03) continue;
      out.push_back({x, {p, u}});
    }
    return out;
  }
};

TEST_F(SensorModelTest, FirstDerivativesMatchFiniteDifferences) {
  const VdtSensorModel model(map_);
  for (const auto& [x, beam] : beams(200)) {
    const auto& [p, u] = beam;
    const BeamDisparity b = model.disparity(x, p, u);
    const double h = 1e-4;
    for (int k = 0; k < 3; ++k) {
      const Pose2 e = Pose2::Unit(k) * h;
      const Eigen::Vector2d fd =
          (model.disparity(x + e, p, u).d - model.disparity(x - e, p, u).d) / (2 * h);
      ASSERT_LT((b.d_pose.col(k) - fd).norm(), 5e-3 * (1 + b.d_pose.norm())) << "k=" << k;
    }
    const Eigen::Vector2d fd_r =
        (model.disparity(x, p + h * u, u).d - model.disparity(x, p - h * u, u).d) / (2 * h);
    ASSERT_LT((b.d_range - fd_r).norm(), 5e-3 * (1 + b.d_range.norm()));
  }
}

TEST_F(SensorModelTest, CurvatureMatchesFiniteDifferencesOfTheGradient) {
  const VdtSensorModel model(map_);
  // g(X, r) = d(|d|^2/2)/dX = (dd/dX)^T d; the curvature is its Jacobian in X and in r.
  const auto g = [&](const Pose2& x, const Eigen::Vector2d& p,
                     const Eigen::Vector2d& u) -> Eigen::Vector3d {
    const BeamDisparity b = model.disparity(x, p, u);
    return b.d_pose.transpose() * b.d;
  };
  for (const auto& [x, beam] : beams(200)) {
    const auto& [p, u] = beam;
    BeamCurvature c;
    (void)model.disparity(x, p, u, &c);
    const double h = 1e-4;
    for (int k = 0; k < 3; ++k) {
      const Pose2 e = Pose2::Unit(k) * h;
      const Eigen::Vector3d fd = (g(x + e, p, u) - g(x - e, p, u)) / (2 * h);
      ASSERT_LT((c.hessian.col(k) - fd).norm(), 2e-2 * (1 + c.hessian.norm())) << "k=" << k;
    }
    const Eigen::Vector3d fd_r = (g(x, p + h * u, u) - g(x, p - h * u, u)) / (2 * h);
    ASSERT_LT((c.cross - fd_r).norm(), 2e-2 * (1 + c.cross.norm()));
  }
}

TEST_F(SensorModelTest, ExactDisparityCovarianceMatchesMonteCarlo) {
  VdtSensorModelOptions o;
  o.map_sigma = 0.0;
  const VdtSensorModel model(map_, o);
  const double sigma = 0.02;
  std::mt19937 rng(9);
  std::normal_distribution<double> noise(0.0, sigma);
  // The robot faces the left wall (centre line x = -0.875) from x = 1.5; beams at several
  // incidences end in front of, on and behind the wall's centre line.
  const Pose2 x(1.5, 2.0, M_PI);
  const double wall_x = occ_.cell_center(Eigen::Vector2i(2, 0)).x();
  for (double a : {-0.4, -0.1, 0.0, 0.25, 0.45}) {
    for (double offset : {-0.04, 0.0, 0.03}) {
      const Eigen::Vector2d u(std::cos(a),
                              std::sin(a));  // robot frame; world direction (-cos, -sin)
      const double r = (x[0] - wall_x) / std::cos(a) + offset;
      const Eigen::Vector2d p = r * u;
      const BeamDisparity b = model.disparity(x, p, u);
      const int n = 20000;
      Eigen::Vector2d mean = Eigen::Vector2d::Zero();
      Eigen::Matrix2d second = Eigen::Matrix2d::Zero();
      for (int k = 0; k < n; ++k) {
        const Eigen::Vector2d d = model.disparity(x, p + noise(rng) * u, u).d;
        mean += d;
        second += d * d.transpose();
      }
      mean /= n;
      const Eigen::Matrix2d mc = second / n - mean * mean.transpose();
      const Eigen::Matrix2d exact = model.disparity_covariance(b, sigma);
      ASSERT_LT((mc - exact).norm(), 0.05 * exact.norm()) << "a " << a << " offset " << offset;
      // Near a straight wall only the normal component moves: sigma_r cos(a) along x.
      EXPECT_NEAR(std::sqrt(exact(0, 0)), sigma * std::cos(a), 1e-2 * sigma);
      EXPECT_LT(std::abs(exact.determinant()), 1e-14);  // one range error: rank one
    }
  }
}

TEST_F(SensorModelTest, DiagonalOptionDropsTheCorrelation) {
  VdtSensorModelOptions o;
  o.covariance = DisparityCovariance::kDiagonal;
  o.map_sigma = 0.01;
  const VdtSensorModel model(map_, o);
  BeamDisparity b;
  b.d_range = Eigen::Vector2d(0.6, -0.8);
  const Eigen::Matrix2d c = model.disparity_covariance(b, 0.02);
  EXPECT_NEAR(c(0, 1), 0.0, 1e-15);
  EXPECT_NEAR(c(0, 0), 0.36 * 4e-4 + 1e-4, 1e-15);
  EXPECT_NEAR(c(1, 1), 0.64 * 4e-4 + 1e-4, 1e-15);
}

TEST_F(SensorModelTest, GateUsesMagnitudesOfTheSignedComponents) {
  VdtSensorModelOptions o;
  o.gate = 0.12;
  o.residual = ResidualMode::kNearestPoint;  // exact DT_v at cell centres
  const VdtSensorModel components(map_, o);
  o.gate_mode = GateMode::kNorm;
  const VdtSensorModel norm(map_, o);
  const Eigen::Vector2d u(1, 0), origin = Eigen::Vector2d::Zero();
  // Diagonally off the box's lower-left corner cell (70, 30): DT_v = (-0.1, -0.1).
  const Eigen::Vector2d p = occ_.cell_center(Eigen::Vector2i(68, 28));
  const auto bc = components.disparity(Pose2(p.x(), p.y(), 0.0), origin, u);
  const auto bn = norm.disparity(Pose2(p.x(), p.y(), 0.0), origin, u);
  ASSERT_LT((bc.d - Eigen::Vector2d(-0.1, -0.1)).norm(), 1e-9);
  EXPECT_TRUE(bc.inlier);   // |DT_x|, |DT_y| < 0.12
  EXPECT_FALSE(bn.inlier);  // |DT_v| = 0.141 > 0.12
  // Ten cells left of the box: DT_v = (-0.5, 0). The thesis's DT_x < alpha would keep it.
  const Eigen::Vector2d f = occ_.cell_center(Eigen::Vector2i(60, 35));
  const auto bf = components.disparity(Pose2(f.x(), f.y(), 0.0), origin, u);
  ASSERT_LT((bf.d - Eigen::Vector2d(-0.5, 0.0)).norm(), 1e-9);
  EXPECT_FALSE(bf.inlier);
  EXPECT_THROW(VdtSensorModel(map_, VdtSensorModelOptions{GateMode::kNorm, -1.0}), ConfigError);
}

}  // namespace
}  // namespace vdtnav
