#include "vdtnav/mapping/eikonal_residuals.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace vdtnav::mapping {

namespace {

/// Uniform cubic B-spline weights of nodes i-1 .. i+2 at t and their derivatives in t (5.9 / 6).
void cubic_weights(double t, double w[4], double dw[4]) {
  const double s = 1.0 - t;
  w[0] = s * s * s / 6.0;
  w[1] = (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0;
  w[2] = (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0;
  w[3] = t * t * t / 6.0;
  dw[0] = -0.5 * s * s;
  dw[1] = (9.0 * t * t - 12.0 * t) / 6.0;
  dw[2] = (-9.0 * t * t + 6.0 * t + 3.0) / 6.0;
  dw[3] = 0.5 * t * t;
}

/// Metres: the softening of |v| in the Eikonal residual (below the noise of any range sensor).
constexpr double kEikonalEpsilon = 1e-3;

}  // namespace

void spline_field(const SplinePatchBasis& b, const double* const* c, Eigen::Vector2d* v,
                  Eigen::Matrix2d* jac) {
  // v = sum w_k c_k and J = [sum wx_k c_k, sum wy_k c_k] (5.8)
  v->setZero();
  jac->setZero();
  for (int k = 0; k < 16; ++k) {
    const Eigen::Vector2d ck(c[k][0], c[k][1]);
    *v += b.w[k] * ck;
    jac->col(0) += b.wx[k] * ck;
    jac->col(1) += b.wy[k] * ck;
  }
}

SplinePatchBasis spline_patch_basis(double tx, double ty, double h) {
  double wx[4], dwx[4], wy[4], dwy[4];
  cubic_weights(tx, wx, dwx);
  cubic_weights(ty, wy, dwy);
  SplinePatchBasis b;
  for (int bb = 0; bb < 4; ++bb) {
    for (int a = 0; a < 4; ++a) {
      const int k = a + 4 * bb;
      b.w[k] = wx[a] * wy[bb];
      b.wx[k] = dwx[a] * wy[bb] / h;
      b.wy[k] = wx[a] * dwy[bb] / h;
    }
  }
  return b;
}

void eikonal_residual(const SplinePatchBasis& b, const double* const* c, double* r, double* d_c) {
  // r = (J^T - I) v / |v|, the vector form of (5.3); |v| is softened by kEikonalEpsilon so that a
  // sample the fit crosses a zero at does not blow the Jacobian up.
  Eigen::Vector2d v;
  Eigen::Matrix2d j;
  spline_field(b, c, &v, &j);
  const Eigen::Matrix2d jt_i = j.transpose() - Eigen::Matrix2d::Identity();
  const Eigen::Vector2d w = jt_i * v;
  const double n = std::sqrt(v.squaredNorm() + kEikonalEpsilon * kEikonalEpsilon);
  r[0] = w.x() / n;
  r[1] = w.y() / n;
  if (d_c == nullptr) return;
  // d(J^T v)/dc_k = g_k v^T + w_k J^T (g_k = (wx_k, wy_k)) and dn/dc_k = w_k v^T / n, so
  // dr/dc_k = (g_k v^T + w_k (J^T - I)) / n - w (w_k v^T / n) / n^2.
  const Eigen::Vector2d vhat = v / n;
  for (int k = 0; k < 16; ++k) {
    const Eigen::Vector2d g(b.wx[k], b.wy[k]);
    const Eigen::Matrix2d d =
        (g * v.transpose() + b.w[k] * jt_i) / n - (w * (b.w[k] * vhat.transpose())) / (n * n);
    for (int row = 0; row < 2; ++row) {
      for (int ch = 0; ch < 2; ++ch) d_c[row * 32 + 2 * k + ch] = d(row, ch);
    }
  }
}

void hessian_eikonal_residual(const SplinePatchBasis& b, const double* const* c, double* r,
                              double* d_c) {
  // J = dDT_v/dp is the Hessian of DT_u^2 / 2 with the unit eigenvalue along the normal
  // (J v = v off the boundary, continuous across it): r = (det(J - I), J_01 - J_10).
  Eigen::Vector2d v;
  Eigen::Matrix2d j;
  spline_field(b, c, &v, &j);
  r[0] = (j(0, 0) - 1.0) * (j(1, 1) - 1.0) - j(0, 1) * j(1, 0);
  r[1] = j(0, 1) - j(1, 0);
  if (d_c == nullptr) return;
  // J_00 = sum wx_k cx_k, J_01 = sum wy_k cx_k, J_10 = sum wx_k cy_k, J_11 = sum wy_k cy_k.
  for (int k = 0; k < 16; ++k) {
    d_c[2 * k] = b.wx[k] * (j(1, 1) - 1.0) - b.wy[k] * j(1, 0);
    d_c[2 * k + 1] = b.wy[k] * (j(0, 0) - 1.0) - b.wx[k] * j(0, 1);
    d_c[32 + 2 * k] = b.wy[k];
    d_c[32 + 2 * k + 1] = -b.wx[k];
  }
}

void boundary_residual(const Eigen::Vector2d& corner, double h, const Pose2& pose,
                       const double* d_pose, const Eigen::Vector2d& p, const double* const* c,
                       double* r, double* d_c, double* d_dpose) {
  // o = R(phi + dphi) p + t + dt (5.12 corrected per SPEC), r = DT_v(o) (5.4).
  const double phi = pose[2] + d_pose[2];
  const Eigen::Rotation2Dd rot(phi);
  const Eigen::Vector2d rp = rot * p;
  const Eigen::Vector2d o = rp + pose.head<2>() + Eigen::Vector2d(d_pose[0], d_pose[1]);
  const Eigen::Vector2d t = (o - corner) / h;
  const SplinePatchBasis b = spline_patch_basis(t.x(), t.y(), h);
  Eigen::Vector2d v;
  Eigen::Matrix2d j;
  spline_field(b, c, &v, &j);
  r[0] = v.x();
  r[1] = v.y();
  if (d_c != nullptr) {
    std::fill(d_c, d_c + 64, 0.0);
    for (int k = 0; k < 16; ++k) {
      d_c[2 * k] = b.w[k];           // row 0, channel x
      d_c[32 + 2 * k + 1] = b.w[k];  // row 1, channel y
    }
  }
  if (d_dpose != nullptr) {
    const Eigen::Vector2d dphi = j * Eigen::Vector2d(-rp.y(), rp.x());  // J dR/dphi p
    d_dpose[0] = j(0, 0);
    d_dpose[1] = j(0, 1);
    d_dpose[2] = dphi.x();
    d_dpose[3] = j(1, 0);
    d_dpose[4] = j(1, 1);
    d_dpose[5] = dphi.y();
  }
}

}  // namespace vdtnav::mapping
