#pragma once
/// \file
/// \brief The residuals of the uncertain VDT map's fit (thesis (5.8)-(5.15)): the cubic B-spline
/// patch of DT_x and DT_y, the Eikonal residual in its two forms and the boundary residual.
///
/// A cell (i, j) of the control lattice (spacing h) is a patch of 4 x 4 control points
/// c_{i-1+a, j-1+b}, a, b = 0..3, two coefficients each (DT_x, DT_y); at fractional offsets
/// t = (p - corner) / h,
///   DT_v(p) = sum_{a,b} w_a(t_x) w_b(t_y) c_{i-1+a, j-1+b}                          (5.8)
/// with the uniform cubic B-spline weights w (the rows of (5.9) / 6). Control point k = a + 4 b
/// of a patch; derivatives with respect to the control points are 2 x 32 row-major (column
/// 2 k + channel).

#include <array>

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"

namespace vdtnav::mapping {

/// \brief The basis of one cell at a point: w_k and dw_k/dp (per metre) of its 16 control points.
struct SplinePatchBasis {
  std::array<double, 16> w{}, wx{}, wy{};
};

/// \brief The basis at fractional offsets (tx, ty) of a cell of side h (values outside [0, 1]
/// extrapolate the cell's polynomial).
[[nodiscard]] SplinePatchBasis spline_patch_basis(double tx, double ty, double h);

/// \brief DT_v and its Jacobian J = dDT_v/dp (column d: along axis d) at a point with basis `b`
/// and control points c[k] (2 coefficients each).
void spline_field(const SplinePatchBasis& b, const double* const* c, Eigen::Vector2d* v,
                  Eigen::Matrix2d* jacobian);

/// \brief The Eikonal equation (5.3) in vector form away from the boundary,
/// r_E = (J^T - I) v / |v| (unweighted; |v| softened by 1 mm), with dr/dc when d_c is not null.
void eikonal_residual(const SplinePatchBasis& b, const double* const* c, double* r, double* d_c);

/// \brief The Eikonal equation where DT_v is small (within `near` of the boundary, where (5.3)
/// and its vector form divide by ~0): dDT_v/dp is the Hessian of DT_u^2 / 2, symmetric with a
/// unit eigenvalue (along the normal), continuous across the boundary; r = (det(J - I), J_01 -
/// J_10) (unweighted), d_c as in eikonal_residual().
void hessian_eikonal_residual(const SplinePatchBasis& b, const double* const* c, double* r,
                              double* d_c);

/// \brief The boundary residual of reading p (robot frame) of a scan at pose (x, y, phi) + dX in
/// the cell whose lower corner is `corner` (world): r_B = DT_v(o) (unweighted), with dr/dc (2 x 32
/// row-major) and dr/d(dX) (2 x 3 row-major) when not null.
void boundary_residual(const Eigen::Vector2d& corner, double h, const Pose2& pose,
                       const double* d_pose, const Eigen::Vector2d& p, const double* const* c,
                       double* r, double* d_c, double* d_dpose);

}  // namespace vdtnav::mapping
