#pragma once
/// \file
/// \brief Least-squares rigid or similarity alignment of two point sets (Umeyama 1991), in 2D, 3D
/// or a dimension chosen at run time.
///
/// S. Umeyama, "Least-squares estimation of transformation parameters between two point
/// patterns", IEEE T-PAMI 13(4), 1991. Given pairs (x_i, y_i), minimises
///   e^2(R, t, s) = 1/n sum |y_i - (s R x_i + t)|^2
/// over rotations R (det R = +1), translations t and, optionally, scales s > 0.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SVD>

#include "vdtnav/core/error.hpp"

namespace vdtnav::eval {

/// \brief Why an alignment could not be computed.
enum class AlignmentStatus {
  kOk,
  kTooFewPoints,  ///< no point pairs at all
  /// The rotation is not unique: the cross-covariance has rank < Dim - 1 (all points coincide,
  /// or in 3D they are collinear), or with scale the source points have no spread.
  kDegenerate,
};

/// \brief y = s R x + t: the transform umeyama() estimates, and how well it fits.
template <int Dim>
struct Similarity {
  using Matrix = Eigen::Matrix<double, Dim, Dim>;
  using Vector = Eigen::Matrix<double, Dim, 1>;

  AlignmentStatus status = AlignmentStatus::kTooFewPoints;
  Matrix rotation;     ///< R, a proper rotation (det +1)
  Vector translation;  ///< t
  double scale = 1.0;  ///< s (exactly 1 for a rigid alignment)
  double rmse = 0.0;   ///< sqrt(e^2): root mean square of |y_i - (s R x_i + t)|

  [[nodiscard]] bool ok() const noexcept { return status == AlignmentStatus::kOk; }
  /// \return s R x + t.
  [[nodiscard]] Vector apply(const Vector& x) const { return scale * rotation * x + translation; }
};

/// \brief The least-squares similarity (with_scale) or rigid transform taking `source` onto
/// `target`: target.col(i) ~ s R source.col(i) + t.
///
/// With mu_x, mu_y the means, sigma_x^2 = 1/n sum |x_i - mu_x|^2 and the cross-covariance
/// Sigma = 1/n sum (y_i - mu_y)(x_i - mu_x)^T = U D V^T (Umeyama's (38)):
///   R = U S V^T with S = I, or S = diag(1, ..., 1, -1) when det(U) det(V) < 0   (39)-(40), (43)
///   s = tr(D S) / sigma_x^2   (42)     t = mu_y - s R mu_x   (41)
/// (det(U) det(V) has the sign of det(Sigma) when Sigma is regular, and it is the rank Dim - 1
/// rule (43) otherwise.) Without scale, s = 1 and R is the same.
/// \param source, target Dim x n point sets with the same n (Dim = Eigen::Dynamic: any rows).
/// \param with_scale estimate s (similarity) or keep s = 1 (rigid).
/// \return the transform with status kOk, or kTooFewPoints / kDegenerate (R, t, s then identity).
/// \throws ConfigError when the sets differ in size or hold non-finite values.
template <int Dim>
[[nodiscard]] Similarity<Dim> umeyama(const Eigen::Matrix<double, Dim, Eigen::Dynamic>& source,
                                      const Eigen::Matrix<double, Dim, Eigen::Dynamic>& target,
                                      bool with_scale) {
  using Matrix = typename Similarity<Dim>::Matrix;
  using Vector = typename Similarity<Dim>::Vector;
  VDTNAV_CHECK(source.rows() == target.rows() && source.cols() == target.cols(),
               "umeyama: source and target must have the same dimension and number of points");
  VDTNAV_CHECK(source.allFinite() && target.allFinite(), "umeyama: points must be finite");
  const Eigen::Index m = source.rows();
  const Eigen::Index n = source.cols();

  Similarity<Dim> result;
  result.rotation = Matrix::Identity(m, m);
  result.translation = Vector::Zero(m);
  if (n == 0 || m == 0) return result;

  const Vector mu_x = source.rowwise().mean();
  const Vector mu_y = target.rowwise().mean();
  const Eigen::Matrix<double, Dim, Eigen::Dynamic> xc = source.colwise() - mu_x;
  const Eigen::Matrix<double, Dim, Eigen::Dynamic> yc = target.colwise() - mu_y;
  const double inv_n = 1.0 / static_cast<double>(n);
  const double sigma_x2 = xc.squaredNorm() * inv_n;    // (36)
  const Matrix sigma = (yc * xc.transpose()) * inv_n;  // (38)

  const Eigen::JacobiSVD<Matrix> svd(sigma, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const auto& d = svd.singularValues();  // descending
  // Numerical rank of Sigma, relative to the spread of both sets (an exact fit with coinciding
  // points has Sigma = 0 but must still read as degenerate).
  const double spread = std::sqrt(sigma_x2 * (yc.squaredNorm() * inv_n));
  const double tol = 1e-12 * std::max(spread, std::numeric_limits<double>::min());
  Eigen::Index rank = 0;
  for (Eigen::Index i = 0; i < d.size(); ++i) rank += d[i] > tol ? 1 : 0;
  if (rank < m - 1 || spread == 0.0 || (with_scale && sigma_x2 <= 0.0)) {
    result.status = AlignmentStatus::kDegenerate;
    return result;
  }

  Vector s_diag = Vector::Ones(m);
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) s_diag[m - 1] = -1.0;
  result.rotation = svd.matrixU() * s_diag.asDiagonal() * svd.matrixV().transpose();  // (40)
  result.scale = with_scale ? d.dot(s_diag) / sigma_x2 : 1.0;                         // (42)
  result.translation = mu_y - result.scale * result.rotation * mu_x;                  // (41)
  Eigen::Matrix<double, Dim, Eigen::Dynamic> fitted = (result.scale * result.rotation) * source;
  fitted.colwise() += result.translation;
  result.rmse = std::sqrt((target - fitted).squaredNorm() * inv_n);
  result.status = AlignmentStatus::kOk;
  return result;
}

/// \brief As umeyama() on matrices, for point lists (fixed Dim only).
template <int Dim>
[[nodiscard]] Similarity<Dim> umeyama(const std::vector<Eigen::Matrix<double, Dim, 1>>& source,
                                      const std::vector<Eigen::Matrix<double, Dim, 1>>& target,
                                      bool with_scale) {
  static_assert(Dim > 0, "point lists need a fixed dimension");
  VDTNAV_CHECK(source.size() == target.size(),
               "umeyama: source and target must have the same number of points");
  Eigen::Matrix<double, Dim, Eigen::Dynamic> x(Dim, static_cast<Eigen::Index>(source.size()));
  Eigen::Matrix<double, Dim, Eigen::Dynamic> y(Dim, static_cast<Eigen::Index>(target.size()));
  for (std::size_t i = 0; i < source.size(); ++i) {
    x.col(static_cast<Eigen::Index>(i)) = source[i];
    y.col(static_cast<Eigen::Index>(i)) = target[i];
  }
  return umeyama<Dim>(x, y, with_scale);
}

}  // namespace vdtnav::eval
