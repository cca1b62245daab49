// The marginal covariance of an uncertain VDT map's control points (thesis (5.16)-(5.19)):
// H = J^T J at the optimum, its sparse inverse's local blocks Z and the scans' shared Y.
#include "uncertain_map_problem.hpp"

#include <array>
#include <chrono>
#include <limits>
#include <memory>

#include <ceres/ceres.h>
#include <Eigen/SparseCore>

#include "vdtnav/mapping/marginal_covariance.hpp"

namespace vdtnav::mapping {

using detail::Clock;
using detail::seconds_since;

/// The marginal covariance of the control points (see uncertain_vdt_map.hpp): cov(c) = Z + Y Y^T
/// from the information H = J^T J of the weighted residuals at the optimum over (c, dX), Z's blocks
/// for the pairs of control points within three of each other (every pair one cell's support holds)
/// on the pattern of its sparse Cholesky factor; never a dense inverse.
void UncertainVdtMap::Problem::covariance(std::unique_ptr<ceres::Problem> problem,
                                          const std::vector<double*>& pose_blocks,
                                          const std::vector<Eigen::Matrix3d>* considered) {
  const auto t0 = Clock::now();
  for (double* b : pose_blocks) problem->SetParameterBlockVariable(b);  // their Jacobians
  const int n_ctrl = map.summary_.control_points;
  ceres::Problem::EvaluateOptions eo;
  for (int v = 0; v < n_ctrl; ++v) eo.parameter_blocks.push_back(&map.coef_[2 * v]);
  for (double* b : pose_blocks) eo.parameter_blocks.push_back(b);
  Eigen::SparseMatrix<double> h;
  {  // J and its copies go before the factorisations
    ceres::CRSMatrix crs;
    double cost = 0.0;
    problem->Evaluate(eo, &cost, nullptr, nullptr, &crs);
    const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>> j(
        crs.num_rows, crs.num_cols, static_cast<Eigen::Index>(crs.values.size()), crs.rows.data(),
        crs.cols.data(), crs.values.data());
    h = Eigen::SparseMatrix<double>(j.transpose() * j);
  }
  problem.reset();
  std::vector<Eigen::MatrixXd> blocks;
  if (considered != nullptr) blocks.assign(considered->begin(), considered->end());
  MarginalCovariance mc;
  map.summary_.covariance_ok =
      mc.compute(h, 2 * static_cast<Eigen::Index>(n_ctrl),
                 considered != nullptr ? &blocks : nullptr, detail::kYDrop);
  if (!map.summary_.covariance_ok) {
    map.summary_.message += " | covariance: H is not positive definite, no marginal blocks";
    map.summary_.covariance_seconds = seconds_since(t0);
    return;
  }
  auto owned = std::make_shared<detail::OwnedCovariance>();
  // Z's blocks within three control points.
  const int pw = map.cells_.x() + 3, ph = map.cells_.y() + 3;
  owned->z.assign(static_cast<std::size_t>(n_ctrl) * 49 * 4,
                  std::numeric_limits<float>::quiet_NaN());
  for (int b = 0; b < ph; ++b) {
    for (int a = 0; a < pw; ++a) {
      const int v = map.variable(a, b);
      if (v < 0) continue;
      for (int db = -3; db <= 3; ++db) {
        for (int da = -3; da <= 3; ++da) {
          const int a2 = a + da, b2 = b + db;
          if (a2 < 0 || b2 < 0 || a2 >= pw || b2 >= ph) continue;
          const int w = map.variable(a2, b2);
          if (w < 0) continue;
          float* block = &owned->z[(static_cast<std::size_t>(v) * 49 + (db + 3) * 7 + da + 3) * 4];
          for (int r = 0; r < 2; ++r) {
            for (int c = 0; c < 2; ++c)
              block[2 * r + c] = static_cast<float>(mc.z(2 * v + r, 2 * w + c));
          }
        }
      }
    }
  }
  // Y in compressed rows.
  const auto& y = mc.y();
  owned->y_row_start.assign(1, 0);
  if (y.cols() > 0) {
    for (Eigen::Index r = 0; r < y.rows(); ++r) {
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(y, r); it; ++it) {
        owned->y_column.push_back(static_cast<std::uint32_t>(it.col()));
        owned->y_value.push_back(static_cast<float>(it.value()));
      }
      owned->y_row_start.push_back(static_cast<std::uint32_t>(owned->y_column.size()));
    }
  } else {
    owned->y_row_start.assign(2 * static_cast<std::size_t>(n_ctrl) + 1, 0);
  }
  CovarianceArrays& ca = map.cov_;
  ca.z = owned->z.data();
  ca.y_row_start = owned->y_row_start.data();
  ca.y_column = owned->y_column.data();
  ca.y_value = owned->y_value.data();
  ca.y_columns = static_cast<std::uint32_t>(y.cols());
  // Per cell of the band (numbered by fit()'s index_cells()), cov(DT_v) as quadratic forms in the
  // 16 weights.
  owned->cell_forms.assign(map.band_cells_ * 3 * kFormTerms, 0.0f);
  std::vector<int> local(ca.y_columns, -1);
  std::vector<std::uint32_t> touched;
  Eigen::MatrixXd g;
  for (int j = 0; j < map.cells_.y(); ++j) {
    for (int i = 0; i < map.cells_.x(); ++i) {
      const std::int32_t slot = map.cell_slot_[cell_index(i, j)];
      if (slot < 0) continue;
      std::array<int, 16> var{};
      for (int k = 0; k < 16; ++k) var[k] = map.variable(i + k % 4, j + k / 4);
      // The cell's 32 rows of Y, dense over the columns any of them holds.
      touched.clear();
      for (int k = 0; k < 32; ++k) {
        const std::size_t row = 2 * static_cast<std::size_t>(var[k / 2]) + k % 2;
        for (std::uint32_t e = ca.y_row_start[row]; e < ca.y_row_start[row + 1]; ++e) {
          int& l = local[ca.y_column[e]];
          if (l < 0) {
            l = static_cast<int>(touched.size());
            touched.push_back(ca.y_column[e]);
          }
        }
      }
      g.setZero(32, static_cast<Eigen::Index>(touched.size()));
      for (int k = 0; k < 32; ++k) {
        const std::size_t row = 2 * static_cast<std::size_t>(var[k / 2]) + k % 2;
        for (std::uint32_t e = ca.y_row_start[row]; e < ca.y_row_start[row + 1]; ++e)
          g(k, local[ca.y_column[e]]) = ca.y_value[e];
      }
      for (const std::uint32_t c : touched) local[c] = -1;
      Eigen::Matrix<double, 32, 32> m = g * g.transpose();
      for (int k = 0; k < 16; ++k) {
        for (int l = 0; l < 16; ++l) {
          const int da = l % 4 - k % 4, db = l / 4 - k / 4;
          const float* blk =
              &owned->z[(static_cast<std::size_t>(var[k]) * 49 + (db + 3) * 7 + da + 3) * 4];
          for (int r = 0; r < 4; ++r) m(2 * k + r / 2, 2 * l + r % 2) += blk[r];
        }
      }
      float* f = &owned->cell_forms[static_cast<std::size_t>(slot) * 3 * kFormTerms];
      int t = 0;
      for (int k = 0; k < 16; ++k) {
        for (int l = k; l < 16; ++l, ++t) {
          const double twice = k == l ? 0.0 : 1.0;  // w_k w_l and w_l w_k
          f[t] = static_cast<float>(m(2 * k, 2 * l) + twice * m(2 * l, 2 * k));
          f[kFormTerms + t] = static_cast<float>(m(2 * k, 2 * l + 1) + twice * m(2 * l, 2 * k + 1));
          f[2 * kFormTerms + t] =
              static_cast<float>(m(2 * k + 1, 2 * l + 1) + twice * m(2 * l + 1, 2 * k + 1));
        }
      }
    }
  }
  ca.cell_forms = owned->cell_forms.data();
  ca.owner = std::move(owned);
  map.summary_.covariance_seconds = seconds_since(t0);
}

}  // namespace vdtnav::mapping
