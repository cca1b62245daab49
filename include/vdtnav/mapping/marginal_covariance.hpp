#pragma once
/// \file
/// \brief The marginal covariance of part of a sparse least-squares problem's unknowns, without
/// a dense inverse (thesis (5.16)-(5.19) at the scale of a building).
///
/// With the Gauss-Newton information H = [A B; B^T D] of unknowns (a, d) — a many and locally
/// coupled (control points), d few and coupled to many (scan poses) — the covariance of a is
///   cov(a) = (A - B D^-1 B^T)^-1 = Z + Y Y^T,   Z = A^-1,   Y = Z B L^-T,   L L^T = D - B^T Z B
/// (Woodbury). Z is never formed: its entries on the pattern of A's sparse Cholesky factor
/// (which holds every pair A couples) come from Takahashi's recursion (Takahashi, Fagan and Chen,
/// 1973), at the cost of the factorisation; Y, n_a x n_d, is solved a few columns at a time and
/// kept sparse: a column is the response of the a unknowns to one d unknown, local where d is
/// local (a scan pose moves the control points near what it saw), and its entries below
/// `drop` times the column's largest are left out (their share of Y Y^T is below drop^2).
///
/// When the d unknowns are not estimated but held at their values, whose errors have the
/// covariance C (considered, as in a Schmidt-Kalman filter), the implicit function theorem gives
/// da/dd = -A^-1 B and cov(a) = Z + Y Y^T with Y = Z B L_C, L_C L_C^T = C (D is not used). C is
/// given by its diagonal blocks (one per scan pose: their errors are independent), so L_C is
/// block diagonal and B L_C as sparse as B.

#include <vector>

#include <Eigen/Core>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

namespace vdtnav::mapping {

/// \brief The marginal covariance of the first n_a unknowns (see the file comment).
class MarginalCovariance {
 public:
  /// \param h the information, symmetric (both triangles stored) positive definite.
  /// \param n_a the unknowns whose covariance is wanted come first.
  /// \param considered when not null, the d unknowns are held and these are the diagonal blocks
  /// of their covariance C (positive semi-definite, sizes summing to n_d).
  /// \param drop entries of a column of Y below drop times its largest are left out (0: none).
  /// \return false when A (or D - B^T A^-1 B) is not positive definite (nothing is then usable).
  bool compute(const Eigen::SparseMatrix<double>& h, Eigen::Index n_a,
               const std::vector<Eigen::MatrixXd>* considered = nullptr, double drop = 0.0);

  /// \return Z_ab = (A^-1)_ab, NaN when (a, b) is not on the pattern of A's Cholesky factor.
  [[nodiscard]] double z(Eigen::Index a, Eigen::Index b) const;
  /// \return cov(a)_ab = Z_ab + Y_a . Y_b (NaN off the pattern).
  [[nodiscard]] double covariance(Eigen::Index a, Eigen::Index b) const {
    return z(a, b) + (y_.cols() > 0 ? y_.row(a).dot(y_.row(b)) : 0.0);
  }
  /// \return Y, n_a x n_d, row-major sparse (no columns without the d unknowns).
  [[nodiscard]] const Eigen::SparseMatrix<double, Eigen::RowMajor>& y() const noexcept {
    return y_;
  }

 private:
  std::vector<int> outer_, inner_, perm_;  // the factor's pattern, permuted index of each unknown
  std::vector<double> z_;                  // Z on that pattern
  Eigen::SparseMatrix<double, Eigen::RowMajor> y_;
};

}  // namespace vdtnav::mapping
