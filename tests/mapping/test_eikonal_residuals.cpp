// The residuals of the uncertain map's fit (thesis (5.8)-(5.15)): the B-spline patch against its
// definition, every analytic Jacobian against central differences, and the Eikonal residuals
// vanish on an exact VDT (a linear field across a wall) and not on a flattened one.
#include "vdtnav/mapping/eikonal_residuals.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <random>

#include <Eigen/Geometry>

namespace vdtnav::mapping {
namespace {

/// 16 control points of two coefficients each, and the pointers the residuals take.
struct Patch {
  std::array<std::array<double, 2>, 16> c{};
  std::array<const double*, 16> ptr{};
  Patch() { bind(); }
  Patch(const Patch& o) : c(o.c) { bind(); }
  Patch& operator=(const Patch& o) {
    c = o.c;
    bind();
    return *this;
  }
  void bind() {
    for (int k = 0; k < 16; ++k) ptr[k] = c[k].data();
  }
};

Patch random_patch(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 0.4);
  Patch p;
  for (auto& ck : p.c) ck = {n(rng), n(rng)};
  return p;
}

/// Control points of the linear field DT_v(p) = a (p - o): a B-spline reproduces it exactly when
/// control point (i - 1 + a, j - 1 + b) of the cell with lower corner `corner` takes its value at
/// its node.
Patch linear_patch(const Eigen::Matrix2d& a, const Eigen::Vector2d& o,
                   const Eigen::Vector2d& corner, double h) {
  Patch p;
  for (int b = 0; b < 4; ++b) {
    for (int aa = 0; aa < 4; ++aa) {
      const Eigen::Vector2d node = corner + Eigen::Vector2d(aa - 1, b - 1) * h;
      const Eigen::Vector2d v = a * (node - o);
      p.c[aa + 4 * b] = {v.x(), v.y()};
    }
  }
  return p;
}

/// Central differences of a 2-valued residual in each of the 32 coefficients.
Eigen::Matrix<double, 2, 32> numeric_dc(
    Patch p, const std::function<void(const double* const*, double*)>& f) {
  Eigen::Matrix<double, 2, 32> d;
  constexpr double kStep = 1e-6;
  for (int k = 0; k < 16; ++k) {
    for (int ch = 0; ch < 2; ++ch) {
      const double x0 = p.c[k][ch];
      double rp[2], rm[2];
      p.c[k][ch] = x0 + kStep;
      f(p.ptr.data(), rp);
      p.c[k][ch] = x0 - kStep;
      f(p.ptr.data(), rm);
      p.c[k][ch] = x0;
      d(0, 2 * k + ch) = (rp[0] - rm[0]) / (2 * kStep);
      d(1, 2 * k + ch) = (rp[1] - rm[1]) / (2 * kStep);
    }
  }
  return d;
}

TEST(SplinePatch, BasisIsAPartitionOfUnityWithTheDerivativesOfItsWeights) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const double tx = u(rng), ty = u(rng), h = 0.25;
    const SplinePatchBasis b = spline_patch_basis(tx, ty, h);
    double sw = 0.0, swx = 0.0, swy = 0.0;
    for (int k = 0; k < 16; ++k) {
      sw += b.w[k];
      swx += b.wx[k];
      swy += b.wy[k];
    }
    EXPECT_NEAR(sw, 1.0, 1e-14);
    EXPECT_NEAR(swx, 0.0, 1e-12);
    EXPECT_NEAR(swy, 0.0, 1e-12);
    // dw/dp against central differences of w in the offsets (p = corner + t h).
    constexpr double kStep = 1e-6;
    const SplinePatchBasis bx = spline_patch_basis(tx + kStep, ty, h);
    const SplinePatchBasis bxm = spline_patch_basis(tx - kStep, ty, h);
    const SplinePatchBasis by = spline_patch_basis(tx, ty + kStep, h);
    const SplinePatchBasis bym = spline_patch_basis(tx, ty - kStep, h);
    for (int k = 0; k < 16; ++k) {
      EXPECT_NEAR(b.wx[k], (bx.w[k] - bxm.w[k]) / (2 * kStep * h), 1e-7);
      EXPECT_NEAR(b.wy[k], (by.w[k] - bym.w[k]) / (2 * kStep * h), 1e-7);
    }
  }
}

TEST(SplinePatch, ReproducesALinearField) {
  const double h = 0.2;
  const Eigen::Vector2d corner(1.0, -2.0), o(1.1, -1.9);
  Eigen::Matrix2d a;
  a << 0.8, 0.3, -0.2, 0.5;
  const Patch p = linear_patch(a, o, corner, h);
  for (const Eigen::Vector2d& t :
       {Eigen::Vector2d(0.1, 0.7), Eigen::Vector2d(0.5, 0.5), Eigen::Vector2d(0.95, 0.02)}) {
    Eigen::Vector2d v;
    Eigen::Matrix2d j;
    spline_field(spline_patch_basis(t.x(), t.y(), h), p.ptr.data(), &v, &j);
    EXPECT_LT((v - a * (corner + t * h - o)).norm(), 1e-12);
    EXPECT_LT((j - a).norm(), 1e-12);
  }
}

TEST(EikonalResiduals, JacobiansMatchCentralDifferences) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.05, 0.95);
  for (int trial = 0; trial < 10; ++trial) {
    const Patch p = random_patch(rng);
    const SplinePatchBasis b = spline_patch_basis(u(rng), u(rng), 0.25);
    for (const auto& f : {eikonal_residual, hessian_eikonal_residual}) {
      double r[2], d_c[64];
      f(b, p.ptr.data(), r, d_c);
      const Eigen::Map<const Eigen::Matrix<double, 2, 32, Eigen::RowMajor>> analytic(d_c);
      const Eigen::Matrix<double, 2, 32> numeric =
          numeric_dc(p, [&](const double* const* c, double* out) { f(b, c, out, nullptr); });
      EXPECT_LT((analytic - numeric).cwiseAbs().maxCoeff(), 1e-6 * (1.0 + numeric.norm()))
          << "trial " << trial;
    }
  }
}

TEST(EikonalResiduals, VanishOnTheVdtOfAWallAndNotOnAFlattenedField) {
  // The VDT of the wall y = 0: DT_v(p) = (0, y), J = diag(0, 1), on both sides of the wall.
  const double h = 0.25;
  const Eigen::Vector2d corner(0.0, -0.1);
  Eigen::Matrix2d wall;
  wall << 0.0, 0.0, 0.0, 1.0;
  const Patch exact = linear_patch(wall, Eigen::Vector2d::Zero(), corner, h);
  const Patch flat = linear_patch(0.3 * wall, Eigen::Vector2d::Zero(), corner, h);
  for (const double ty : {0.2, 0.4, 0.7}) {  // y = -0.05, 0, 0.075: across the wall
    const SplinePatchBasis b = spline_patch_basis(0.5, ty, h);
    double r[2];
    hessian_eikonal_residual(b, exact.ptr.data(), r, nullptr);
    EXPECT_NEAR(r[0], 0.0, 1e-12);
    EXPECT_NEAR(r[1], 0.0, 1e-12);
    hessian_eikonal_residual(b, flat.ptr.data(), r, nullptr);
    EXPECT_NEAR(r[0], 0.7, 1e-12);               // det(diag(-1, -0.7))
    if (std::abs(corner.y() + ty * h) > 0.04) {  // away from the wall, the vector form too
      eikonal_residual(b, exact.ptr.data(), r, nullptr);
      EXPECT_LT(std::hypot(r[0], r[1]), 1e-9);
      eikonal_residual(b, flat.ptr.data(), r, nullptr);
      EXPECT_GT(std::hypot(r[0], r[1]), 0.6);  // (J^T - I) v / |v| = (0.3 - 1) along y
    }
  }
}

TEST(BoundaryResidual, IsTheFieldAtTheEndpointWithItsJacobians) {
  std::mt19937 rng(5);
  const double h = 0.25;
  const Eigen::Vector2d corner(1.85, 2.9);
  const Pose2 pose(1.2, 2.1, 0.4);
  const Eigen::Vector2d p(1.0, 0.55);  // robot frame; lands inside the cell
  for (int trial = 0; trial < 10; ++trial) {
    Patch c = random_patch(rng);
    std::normal_distribution<double> small(0.0, 0.01);
    double dx[3] = {small(rng), small(rng), small(rng)};
    double r[2], d_c[64], d_x[6];
    boundary_residual(corner, h, pose, dx, p, c.ptr.data(), r, d_c, d_x);
    // The value: the patch at o = R(phi + dphi) p + t + dt.
    const Eigen::Vector2d o =
        Eigen::Rotation2Dd(pose[2] + dx[2]) * p + pose.head<2>() + Eigen::Vector2d(dx[0], dx[1]);
    const Eigen::Vector2d t = (o - corner) / h;
    ASSERT_TRUE(t.minCoeff() > 0.0 && t.maxCoeff() < 1.0);
    Eigen::Vector2d v;
    Eigen::Matrix2d j;
    spline_field(spline_patch_basis(t.x(), t.y(), h), c.ptr.data(), &v, &j);
    EXPECT_LT((Eigen::Vector2d(r[0], r[1]) - v).norm(), 1e-12);
    const Eigen::Map<const Eigen::Matrix<double, 2, 32, Eigen::RowMajor>> analytic(d_c);
    const Eigen::Matrix<double, 2, 32> numeric =
        numeric_dc(c, [&](const double* const* cc, double* out) {
          boundary_residual(corner, h, pose, dx, p, cc, out, nullptr, nullptr);
        });
    EXPECT_LT((analytic - numeric).cwiseAbs().maxCoeff(), 1e-7);
    for (int q = 0; q < 3; ++q) {
      constexpr double kStep = 1e-7;
      double xp[3] = {dx[0], dx[1], dx[2]}, xm[3] = {dx[0], dx[1], dx[2]};
      xp[q] += kStep;
      xm[q] -= kStep;
      double rp[2], rm[2];
      boundary_residual(corner, h, pose, xp, p, c.ptr.data(), rp, nullptr, nullptr);
      boundary_residual(corner, h, pose, xm, p, c.ptr.data(), rm, nullptr, nullptr);
      EXPECT_NEAR(d_x[q], (rp[0] - rm[0]) / (2 * kStep), 1e-6);
      EXPECT_NEAR(d_x[3 + q], (rp[1] - rm[1]) / (2 * kStep), 1e-6);
    }
  }
}

}  // namespace
}  // namespace vdtnav::mapping
