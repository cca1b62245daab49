// The VDT sensor model: scan conversion, derivatives against finite differences (2D and 3D), the
// disparity covariance against Monte Carlo, and the gate.
#include "vdtnav/sensor/vdt_sensor_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <type_traits>
#include <vector>

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

TEST(ScanPoints, EvenlySpacedBeamsPointAlongTheirAnglesToRoundOff) {
  // 1081 beams over 270 degrees (the tables of scan_points split the angle as 32 h + l): every
  // direction within a few ulp of (cos, sin) of the beam's own angle, explicit angles alike.
  LaserScan scan;
  scan.angle_min = -0.75 * M_PI;
  scan.angle_increment = 1.5 * M_PI / 1080;
  scan.mount = Pose2(0.1, 0.05, -0.4);
  scan.ranges.assign(1081, 3.0);
  const ScanPoints pts = scan_points(scan);
  ASSERT_EQ(pts.size(), 1081u);
  LaserScan explicit_angles = scan;
  for (std::size_t i = 0; i < scan.ranges.size(); ++i)
    explicit_angles.angles.push_back(scan.angle(i));
  const ScanPoints ref = scan_points(explicit_angles);
  double worst = 0.0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const double a = scan.mount[2] + scan.angle(i);
    worst = std::max(worst, (pts.directions[i] - Eigen::Vector2d(std::cos(a), std::sin(a))).norm());
    worst = std::max(worst, (pts.points[i] - ref.points[i]).norm() / 3.0);
  }
  EXPECT_LT(worst, 2e-15);
}

class SensorModelTest : public ::testing::Test {
 protected:
  OccupancyGrid<2> occ_ = room();
  VdtMap2 map_ = VdtMap2::build(occ_);
};

// ---------------------------------------------------------------- derivatives, 2D and 3D

/// A 3 m x 2.5 m x 2 m room (0.05 m cells) with a box and a shelf in it.
OccupancyGrid<3> room3() {
  OccupancyGrid<3> occ(Eigen::Vector3i(64, 54, 44),
                       GridFrame<3>(0.05, Eigen::Vector3d(-0.1, -0.1, -0.1)), 0);
  for (int k = 0; k < 44; ++k)
    for (int j = 0; j < 54; ++j)
      for (int i = 0; i < 64; ++i) {
        const bool wall = i == 1 || i == 62 || j == 1 || j == 52 || k == 1 || k == 42;
        const bool box = i >= 30 && i <= 40 && j >= 20 && j <= 28 && k <= 16;
        const bool shelf = i >= 8 && i <= 20 && j >= 40 && k == 26;
        occ(Eigen::Vector3i(i, j, k)) = (wall || box || shelf) ? 1 : 0;
      }
  return occ;
}

/// Per-dimension fixture facts: the map, random poses inside it, and random beam directions.
template <int Dim>
struct DimFixture;

template <>
struct DimFixture<2> {
  static const VdtMap2& map() {
    static const VdtMap2 m = VdtMap2::build(room());
    return m;
  }
  static Pose2 pose(std::mt19937& rng) {
    std::uniform_real_distribution<double> ux(0.0, 4.5), uy(0.3, 3.0), ua(-3.1, 3.1);
    return Pose2(ux(rng), uy(rng), ua(rng));
  }
  static Eigen::Vector2d direction(std::mt19937& rng) {
    const double a = std::uniform_real_distribution<double>(-3.1, 3.1)(rng);
    return {std::cos(a), std::sin(a)};
  }
  static Eigen::Vector2d offset() { return {0.1, 0.05}; }
  /// d f(X (+) delta)/d delta from the gradient at X (+) delta: the chart is additive.
  static Eigen::Vector3d chart_gradient(const Eigen::Vector3d& /*delta*/,
                                        const Eigen::Vector3d& gradient) {
    return gradient;
  }
};

template <>
struct DimFixture<3> {
  static const VdtMap3& map() {
    static const VdtMap3 m = VdtMap3::build(room3());
    return m;
  }
  static Pose3 pose(std::mt19937& rng) {
    std::uniform_real_distribution<double> ux(0.2, 2.8), uy(0.2, 2.3), uz(0.0, 0.5),
        ut(-0.15, 0.15), ua(-3.1, 3.1);
    return pose3_from_xyz_rpy(ux(rng), uy(rng), uz(rng), ut(rng), ut(rng), ua(rng));
  }
  static Eigen::Vector3d direction(std::mt19937& rng) {
    std::normal_distribution<double> n(0.0, 1.0);
    return Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  }
  static Eigen::Vector3d offset() { return {-0.05, 0.0, 0.4}; }
  /// d f(X (+) delta)/d delta from the left-perturbation gradient at Y = X (+) delta:
  /// Exp(phi + e) = Exp(J_l(phi) e) Exp(phi) + O(e^2), so the rotational part is J_l(phi)^T g_theta
  /// with the left Jacobian J_l(phi) = I + (1 - cos a)/a^2 [phi]_x + (a - sin a)/a^3 [phi]_x^2.
  static Vector6d chart_gradient(const Vector6d& delta, const Vector6d& gradient) {
    const Eigen::Vector3d phi = delta.tail<3>();
    const double a = phi.norm();
    Eigen::Matrix3d jl = Eigen::Matrix3d::Identity();
    if (a > 1e-12) {
      const Eigen::Matrix3d k = skew(phi);
      jl += (1 - std::cos(a)) / (a * a) * k + (a - std::sin(a)) / (a * a * a) * k * k;
    }
    Vector6d out;
    out << gradient.head<3>(), jl.transpose() * gradient.tail<3>();
    return out;
  }
};

template <typename T>
class SensorModelDerivatives : public ::testing::Test {
 protected:
  static constexpr int kDim = T::value;
  using F = DimFixture<kDim>;
  using Traits = PoseTraits<kDim>;
  using Pose = typename Traits::Pose;
  using Vector = typename SpaceTraits<kDim>::Vector;
  using Tangent = typename Traits::Tangent;
  struct Beam {
    Pose x;
    Vector p, u;
  };

  /// Beams that end within 0.2 m of an obstacle (where localization uses them), away from the
  /// cut loci, from random poses in the room.
  static std::vector<Beam> beams(int n) {
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> ur(0.5, 3.0);
    std::vector<Beam> out;
    while (static_cast<int>(out.size()) < n) {
      const Pose x = F::pose(rng);
      const Vector u = F::direction(rng);
      const Vector p = ur(rng) * u + F::offset();
      const Vector q = Traits::rotation(x) * p + Traits::translation(x);
      const auto s = F::map().evaluate(q);
      if (!s.inside || s.value.norm() > 0.2 || s.value.norm() < 0.03) continue;
      out.push_back({x, p, u});
    }
    return out;
  }
};

using Dims = ::testing::Types<std::integral_constant<int, 2>, std::integral_constant<int, 3>>;
TYPED_TEST_SUITE(SensorModelDerivatives, Dims);

TYPED_TEST(SensorModelDerivatives, FirstDerivativesMatchFiniteDifferences) {
  using Traits = typename TestFixture::Traits;
  using Tangent = typename TestFixture::Tangent;
  using Vector = typename TestFixture::Vector;
  const VdtSensorModelT<TestFixture::kDim> model(TestFixture::F::map());
  for (const auto& [x, p, u] : TestFixture::beams(200)) {
    const auto b = model.disparity(x, p, u);
    const double h = 1e-4;
    for (int k = 0; k < Traits::kDoF; ++k) {
      const Tangent e = Tangent::Unit(k) * h;
      const Vector fd = (model.disparity(Traits::plus(x, e), p, u).d -
                         model.disparity(Traits::plus(x, -e), p, u).d) /
                        (2 * h);
      ASSERT_LT((b.d_pose.col(k) - fd).norm(), 5e-3 * (1 + b.d_pose.norm())) << "k=" << k;
    }
    const Vector fd_r =
        (model.disparity(x, p + h * u, u).d - model.disparity(x, p - h * u, u).d) / (2 * h);
    ASSERT_LT((b.d_range - fd_r).norm(), 5e-3 * (1 + b.d_range.norm()));
  }
}

TYPED_TEST(SensorModelDerivatives, CurvatureMatchesFiniteDifferences) {
  using Traits = typename TestFixture::Traits;
  using Tangent = typename TestFixture::Tangent;
  using Pose = typename TestFixture::Pose;
  using Vector = typename TestFixture::Vector;
  const VdtSensorModelT<TestFixture::kDim> model(TestFixture::F::map());
  // g(X, r) = d(|d|^2/2)/dX = (dd/dX)^T d. The cross derivative is its Jacobian in r; the Hessian
  // is the Jacobian of the chart gradient d f(X (+) delta)/d delta at delta = 0 (additive in 2D,
  // the left perturbation in 3D).
  const auto g = [&](const Pose& x, const Vector& p, const Vector& u) -> Tangent {
    const auto b = model.disparity(x, p, u);
    return b.d_pose.transpose() * b.d;
  };
  for (const auto& [x, p, u] : TestFixture::beams(200)) {
    BeamCurvatureT<TestFixture::kDim> c;
    (void)model.disparity(x, p, u, &c);
    const auto chart = [&](const Tangent& delta) -> Tangent {
      return TestFixture::F::chart_gradient(delta, g(Traits::plus(x, delta), p, u));
    };
    const double h = 1e-4;
    for (int k = 0; k < Traits::kDoF; ++k) {
      const Tangent e = Tangent::Unit(k) * h;
      const Tangent fd = (chart(e) - chart(-e)) / (2 * h);
      ASSERT_LT((c.hessian.col(k) - fd).norm(), 2e-2 * (1 + c.hessian.norm())) << "k=" << k;
    }
    ASSERT_LT((c.hessian - c.hessian.transpose()).norm(), 1e-12 * (1 + c.hessian.norm()));
    const Tangent fd_r = (g(x, p + h * u, u) - g(x, p - h * u, u)) / (2 * h);
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
