#include "vdtnav/mapping/marginal_covariance.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/CholmodSupport>
#include <Eigen/Eigenvalues>

namespace vdtnav::mapping {

bool MarginalCovariance::compute(const Eigen::SparseMatrix<double>& h, Eigen::Index n_a,
                                 const std::vector<Eigen::MatrixXd>* considered, double drop) {
  z_.clear();
  y_.resize(0, 0);
  const Eigen::Index n_d = h.rows() - n_a;
  const Eigen::SparseMatrix<double> a = h.topLeftCorner(n_a, n_a);
  {  // the simplicial factor lives only for Takahashi's recursion
    Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> llt;
    llt.compute(a);
    if (llt.info() != Eigen::Success) return false;

    // Z on the pattern of the factor: with P A P^T = L L^T and Z = (L L^T)^-1, for j = n-1 .. 0 and
    // R_j the rows i > j of column j of L,
    //   Z_ij = -(1 / L_jj) sum_{k in R_j} Z_ik L_kj   (i in R_j),
    //   Z_jj = 1 / L_jj^2 - (1 / L_jj) sum_{k in R_j} Z_jk L_kj;
    // every Z_ik it needs lies on the pattern (the factor's pattern is chordal).
    const Eigen::SparseMatrix<double>& l = llt.matrixL().nestedExpression();
    const Eigen::Index n = l.cols();
    const int* outer = l.outerIndexPtr();
    const int* inner = l.innerIndexPtr();
    const double* lv = l.valuePtr();
    outer_.assign(outer, outer + n + 1);
    inner_.assign(inner, inner + outer[n]);
    z_.assign(static_cast<std::size_t>(outer[n]), 0.0);
    std::vector<int> pos(static_cast<std::size_t>(n), -1);
    std::vector<double> acc;
    for (Eigen::Index jj = n - 1; jj >= 0; --jj) {
      const int j0 = outer[jj], j1 = outer[jj + 1];
      if (inner[j0] != jj) return false;  // the diagonal leads every column
      const double ljj = lv[j0];
      const int m = j1 - j0 - 1;  // |R_j|
      acc.assign(static_cast<std::size_t>(m), 0.0);
      for (int q = 0; q < m; ++q) pos[static_cast<std::size_t>(inner[j0 + 1 + q])] = q;
      // acc_i = sum_{k in R_j} Z_ik L_kj, walking the stored lower part of column k of Z (rows
      // >= k) for every k in R_j; an entry Z_ik with i > k also serves Z_ki.
      for (int qk = 0; qk < m; ++qk) {
        const int k = inner[j0 + 1 + qk];
        const double lk = lv[j0 + 1 + qk];
        for (int p = outer[k]; p < outer[k + 1]; ++p) {
          const int qi = pos[static_cast<std::size_t>(inner[p])];
          if (qi < 0) continue;
          const double zik = z_[static_cast<std::size_t>(p)];
          acc[static_cast<std::size_t>(qi)] += zik * lk;
          if (inner[p] != k) acc[static_cast<std::size_t>(qk)] += zik * lv[j0 + 1 + qi];
        }
      }
      double diag = 1.0 / (ljj * ljj);
      for (int q = 0; q < m; ++q) {
        const double zij = -acc[static_cast<std::size_t>(q)] / ljj;
        z_[static_cast<std::size_t>(j0 + 1 + q)] = zij;
        diag -= zij * lv[j0 + 1 + q] / ljj;
        pos[static_cast<std::size_t>(inner[j0 + 1 + q])] = -1;
      }
      z_[static_cast<std::size_t>(j0)] = diag;
    }
    perm_.assign(llt.permutationP().indices().data(), llt.permutationP().indices().data() + n);
  }

  if (n_d == 0) return true;
  const Eigen::SparseMatrix<double> b = h.topRightCorner(n_a, n_d);
  // The columns of Y, a chunk at a time (a chunk dense: n_a x kChunk doubles), sparsified.
  std::vector<Eigen::Triplet<double>> entries;
  const auto add_columns = [&](const Eigen::MatrixXd& cols, Eigen::Index first) {
    for (Eigen::Index c = 0; c < cols.cols(); ++c) {
      const double limit = drop * cols.col(c).cwiseAbs().maxCoeff();
      for (Eigen::Index r = 0; r < n_a; ++r) {
        const double v = cols(r, c);
        if (v != 0.0 && std::abs(v) >= limit) entries.emplace_back(r, first + c, v);
      }
    }
  };
  constexpr Eigen::Index kChunk = 64;
  // The many right-hand sides by CHOLMOD's supernodal factor: its triangular solves run on
  // dense blocks (BLAS 3), ~10x the simplicial factor's column by column.
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> super;
  super.compute(a);
  if (super.info() != Eigen::Success) {
    z_.clear();
    return false;
  }
  if (considered != nullptr) {
    // Y = Z B L_C, L_C L_C^T = C block by block (a square root of a semi-definite block by its
    // eigenvectors): B L_C is as sparse as B.
    std::vector<Eigen::Triplet<double>> lc;
    Eigen::Index at = 0;
    for (const Eigen::MatrixXd& blk : *considered) {
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(blk);
      const Eigen::MatrixXd l =
          es.eigenvectors() * es.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
      for (Eigen::Index r = 0; r < l.rows(); ++r) {
        for (Eigen::Index c = 0; c < l.cols(); ++c) {
          if (l(r, c) != 0.0) lc.emplace_back(at + r, at + c, l(r, c));
        }
      }
      at += blk.rows();
    }
    if (at != n_d) {
      z_.clear();
      return false;
    }
    Eigen::SparseMatrix<double> l(n_d, n_d);
    l.setFromTriplets(lc.begin(), lc.end());
    const Eigen::SparseMatrix<double> bl = b * l;
    for (Eigen::Index c0 = 0; c0 < n_d; c0 += kChunk) {
      const Eigen::Index nc = std::min(kChunk, n_d - c0);
      add_columns(super.solve(Eigen::MatrixXd(bl.middleCols(c0, nc))), c0);
    }
  } else {
    // Y = Z B L^-T with L L^T = D - B^T Z B (the Schur complement of A); n_d is small here
    // (estimated poses), Z B dense.
    const Eigen::MatrixXd zb = super.solve(Eigen::MatrixXd(b));
    const Eigen::MatrixXd s = Eigen::MatrixXd(h.bottomRightCorner(n_d, n_d)) - b.transpose() * zb;
    const Eigen::LLT<Eigen::MatrixXd> schur(s);
    if (schur.info() != Eigen::Success) {
      z_.clear();
      return false;
    }
    add_columns(schur.matrixL().solve(zb.transpose()).transpose(), 0);
  }
  y_.resize(n_a, n_d);
  y_.setFromTriplets(entries.begin(), entries.end());
  return true;
}

double MarginalCovariance::z(Eigen::Index a, Eigen::Index b) const {
  if (z_.empty()) return std::numeric_limits<double>::quiet_NaN();
  int i = perm_[static_cast<std::size_t>(a)], k = perm_[static_cast<std::size_t>(b)];
  if (i < k) std::swap(i, k);  // row i >= column k
  const auto first = inner_.begin() + outer_[static_cast<std::size_t>(k)];
  const auto last = inner_.begin() + outer_[static_cast<std::size_t>(k) + 1];
  const auto it = std::lower_bound(first, last, i);
  if (it == last || *it != i) return std::numeric_limits<double>::quiet_NaN();
  return z_[static_cast<std::size_t>(it - inner_.begin())];
}

}  // namespace vdtnav::mapping
