// The Ceres manifolds of the 6-DOF and 4-DOF optimizers: Plus/Minus consistency with pose3.hpp's
// left perturbation, their Jacobians against finite differences, and the 3D sensor model's
// derivatives in the 4-DOF tangent against finite differences along Se3YawManifold::Plus.
#include "se3_manifold.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cloud_fixture.hpp"
#include "vdtnav/sensor/vdt_sensor_model.hpp"

namespace vdtnav {
namespace {

using Ambient = Eigen::Matrix<double, 7, 1>;

Pose3 random_pose(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-3.0, 3.0), a(-1.2, 1.2);
  return pose3_from_xyz_rpy(u(rng), u(rng), u(rng), a(rng), a(rng), 2.5 * a(rng));
}

Ambient params(const Pose3& x) {
  Ambient p;
  se3_to_parameters(x, p.data());
  return p;
}

Pose3 pose(const Ambient& p) { return se3_from_parameters(p.data()); }

TEST(Se3LeftManifold, PlusAndMinusAreTheLeftPerturbationOfPose3) {
  const Se3LeftManifold m;
  std::mt19937 rng(1);
  std::normal_distribution<double> n(0.0, 0.7);
  for (int k = 0; k < 200; ++k) {
    const Pose3 x = random_pose(rng);
    Vector6d delta;
    for (int i = 0; i < 6; ++i) delta[i] = n(rng);
    if (delta.tail<3>().norm() > 3.0) continue;  // Minus returns |dtheta| <= pi
    const Ambient px = params(x);
    Ambient py;
    ASSERT_TRUE(m.Plus(px.data(), delta.data(), py.data()));
    EXPECT_NEAR(py.head<4>().norm(), 1.0, 1e-14);
    const Pose3 expected = oplus(x, delta);
    EXPECT_LT((pose(py).matrix() - expected.matrix()).norm(), 1e-12);
    Vector6d back;
    ASSERT_TRUE(m.Minus(py.data(), px.data(), back.data()));
    EXPECT_LT((back - delta).norm(), 1e-11) << delta.transpose();
    EXPECT_LT((back - ominus(expected, x)).norm(), 1e-11);
    // Plus(x, Minus(y, x)) == y for any two poses.
    const Pose3 y = random_pose(rng);
    Vector6d d;
    ASSERT_TRUE(m.Minus(params(y).data(), px.data(), d.data()));
    Ambient pz;
    ASSERT_TRUE(m.Plus(px.data(), d.data(), pz.data()));
    EXPECT_LT((pose(pz).matrix() - y.matrix()).norm(), 1e-12);
  }
}

/// Central differences of Plus(x, .) at 0 and of Minus(., x) at x, against the analytic
/// Jacobians, and MinusJacobian * PlusJacobian = I.
template <typename Manifold>
void expect_jacobians_match_finite_differences() {
  constexpr int kT = Manifold::kTangent;
  const Manifold m;
  std::mt19937 rng(2);
  const double h = 1e-6;
  for (int k = 0; k < 100; ++k) {
    const Ambient x = params(random_pose(rng));
    Eigen::Matrix<double, 7, kT, Eigen::RowMajor> plus;
    Eigen::Matrix<double, kT, 7, Eigen::RowMajor> minus;
    ASSERT_TRUE(m.PlusJacobian(x.data(), plus.data()));
    ASSERT_TRUE(m.MinusJacobian(x.data(), minus.data()));
    for (int j = 0; j < kT; ++j) {
      Eigen::Matrix<double, kT, 1> e = Eigen::Matrix<double, kT, 1>::Zero();
      e[j] = h;
      Ambient a, b;
      m.Plus(x.data(), e.data(), a.data());
      e[j] = -h;
      m.Plus(x.data(), e.data(), b.data());
      EXPECT_LT(((a - b) / (2 * h) - plus.col(j)).norm(), 1e-8) << "plus column " << j;
    }
    for (int j = 0; j < 7; ++j) {
      Ambient a = x, b = x;
      a[j] += h;
      b[j] -= h;
      Eigen::Matrix<double, kT, 1> da, db;
      m.Minus(a.data(), x.data(), da.data());
      m.Minus(b.data(), x.data(), db.data());
      EXPECT_LT(((da - db) / (2 * h) - minus.col(j)).norm(), 1e-7) << "minus column " << j;
    }
    EXPECT_LT((minus * plus - Eigen::Matrix<double, kT, kT>::Identity()).norm(), 1e-14);
  }
}

TEST(Se3LeftManifold, JacobiansMatchFiniteDifferences) {
  expect_jacobians_match_finite_differences<Se3LeftManifold>();
}
TEST(Se3YawManifold, JacobiansMatchFiniteDifferences) {
  expect_jacobians_match_finite_differences<Se3YawManifold>();
}

TEST(Se3YawManifold, MovesXyzAndYawAndKeepsRollAndPitch) {
  const Se3YawManifold m4;
  const Se3LeftManifold m6;
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 0.8);
  for (int k = 0; k < 200; ++k) {
    const Pose3 x = random_pose(rng);
    const Eigen::Vector4d delta(n(rng), n(rng), n(rng), n(rng));
    Ambient y4, y6;
    ASSERT_TRUE(m4.Plus(params(x).data(), delta.data(), y4.data()));
    Vector6d full;
    full << delta.head<3>(), 0.0, 0.0, delta[3];
    ASSERT_TRUE(m6.Plus(params(x).data(), full.data(), y6.data()));
    EXPECT_LT((y4 - y6).norm(), 1e-15);  // the sub-chart dtheta = (0, 0, dpsi)
    const Eigen::Vector3d before = rpy_of(x.linear()), after = rpy_of(pose(y4).linear());
    EXPECT_NEAR(after[0], before[0], 1e-13);
    EXPECT_NEAR(after[1], before[1], 1e-13);
    EXPECT_NEAR(wrap_angle(after[2] - before[2] - delta[3]), 0.0, 1e-13);
    Eigen::Vector4d back;
    ASSERT_TRUE(m4.Minus(y4.data(), params(x).data(), back.data()));
    EXPECT_LT((back - delta).norm(), 1e-12);
  }
}

TEST(Se3AmbientJacobian, TimesPlusJacobianGivesTheTangentJacobian) {
  std::mt19937 rng(4);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int k = 0; k < 50; ++k) {
    const Ambient x = params(random_pose(rng));
    Eigen::Matrix<double, 3, 6> d;
    for (int i = 0; i < 18; ++i) d(i) = n(rng);
    Eigen::Matrix<double, 3, 7, Eigen::RowMajor> a;
    Eigen::Matrix<double, 7, 6, Eigen::RowMajor> p6;
    Se3LeftManifold().PlusJacobian(x.data(), p6.data());
    Se3AmbientJacobian(x.data(), false)(d, a.data());
    EXPECT_LT((a * p6 - d).norm(), 1e-13);
    Eigen::Matrix<double, 7, 4, Eigen::RowMajor> p4;
    Se3YawManifold().PlusJacobian(x.data(), p4.data());
    Se3AmbientJacobian(x.data(), true)(d, a.data());
    Eigen::Matrix<double, 3, 4> d4;
    d4 << d.leftCols<3>(), d.col(5);
    EXPECT_LT((a * p4 - d4).norm(), 1e-13);
  }
}

/// The 3D disparity's Jacobian and VCD curvature restricted to the 4-DOF tangent (columns and
/// rows dt, dtheta_z) against central differences along Se3YawManifold::Plus: the 4-DOF mode of
/// the optimizer relies on that restriction.
TEST(Se3YawManifold, SensorModelDerivativesInTheFourDofTangentMatchFiniteDifferences) {
  const VdtSensorModel3 model(test::world3().map);
  const Se3YawManifold m4;
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> ux(0.5, 7.5), uy(0.5, 5.5), uz(0.0, 0.1), ua(-0.08, 0.08),
      uyaw(-3.1, 3.1), ur(0.5, 3.0), ud(-1.0, 1.0);
  const std::array<int, 4> cols = {0, 1, 2, 5};
  int tested = 0;
  while (tested < 100) {
    const Pose3 x = pose3_from_xyz_rpy(ux(rng), uy(rng), uz(rng), ua(rng), ua(rng), uyaw(rng));
    const Eigen::Vector3d u = Eigen::Vector3d(ud(rng), ud(rng), ud(rng)).normalized();
    const Eigen::Vector3d p = Eigen::Vector3d(0.0, 0.0, 0.4) + ur(rng) * u;
    const auto s = test::world3().map.evaluate(x * p);
    if (!s.inside || s.value.norm() > 0.2 || s.value.norm() < 0.03) continue;
    ++tested;
    BeamCurvature3 c;
    const BeamDisparity3 b = model.disparity(x, p, u, &c);
    const Ambient px = params(x);
    const auto at = [&](const Eigen::Vector4d& delta) {
      Ambient y;
      m4.Plus(px.data(), delta.data(), y.data());
      return pose(y);
    };
    // The chart gradient of f(delta) = |d(Plus(X, delta))|^2/2: along dtheta = (0, 0, psi) the
    // left Jacobian J_l(psi e_z) fixes e_z, so it is the (dt, dtheta_z) rows of the
    // left-perturbation gradient D^T d at Plus(X, delta).
    const auto chart = [&](const Eigen::Vector4d& delta) -> Eigen::Vector4d {
      const BeamDisparity3 bd = model.disparity(at(delta), p, u);
      const Vector6d g = bd.d_pose.transpose() * bd.d;
      return {g[0], g[1], g[2], g[5]};
    };
    const double h = 1e-4;
    for (int j = 0; j < 4; ++j) {
      const Eigen::Vector4d e = Eigen::Vector4d::Unit(j) * h;
      const Eigen::Vector3d fd =
          (model.disparity(at(e), p, u).d - model.disparity(at(-e), p, u).d) / (2 * h);
      ASSERT_LT((b.d_pose.col(cols[j]) - fd).norm(), 5e-3 * (1 + b.d_pose.norm())) << j;
      const Eigen::Vector4d fd2 = (chart(e) - chart(-e)) / (2 * h);
      for (int i = 0; i < 4; ++i) {
        ASSERT_NEAR(c.hessian(cols[i], cols[j]), fd2[i], 2e-2 * (1 + c.hessian.norm()))
            << i << "," << j;
      }
    }
  }
}

}  // namespace
}  // namespace vdtnav
