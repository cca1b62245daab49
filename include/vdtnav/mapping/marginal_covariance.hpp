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
/// 1973), at the cost of the factorisation; Y is dense, n_a x n_d.
///
/// When the d unknowns are not estimated but held at their values, whose errors have the
/// covariance C (considered, as in a Schmidt-Kalman filter), the implicit function theorem gives
/// da/dd = -A^-1 B and cov(a) = Z + Y Y^T with Y = Z B L_C, L_C L_C^T = C (D is not used).

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
  /// \param considered when not null, the d unknowns are held and this is their covariance C
  /// (n_d x n_d, positive semi-definite).
  /// \return false when A (or D - B^T A^-1 B) is not positive definite (nothing is then usable).
  bool compute(const Eigen::SparseMatrix<double>& h, Eigen::Index n_a,
               const Eigen::MatrixXd* considered = nullptr);

  /// \return Z_ab = (A^-1)_ab, NaN when (a, b) is not on the pattern of A's Cholesky factor.
  [[nodiscard]] double z(Eigen::Index a, Eigen::Index b) const;
  /// \return cov(a)_ab = Z_ab + Y_a . Y_b (NaN off the pattern).
  [[nodiscard]] double covariance(Eigen::Index a, Eigen::Index b) const {
    return z(a, b) + (y_.cols() > 0 ? y_.row(a).dot(y_.row(b)) : 0.0);
  }
  /// \return Y, n_a x n_d (no columns without the d unknowns).
  [[nodiscard]] const Eigen::MatrixXd& y() const noexcept { return y_; }

 private:
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> llt_;
  std::vector<int> outer_, inner_, perm_;  // the factor's pattern, permuted index of each unknown
  std::vector<double> z_;                  // Z on that pattern
  Eigen::MatrixXd y_;
};

}  // namespace vdtnav::mapping
