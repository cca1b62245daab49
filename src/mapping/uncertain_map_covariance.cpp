// The marginal covariance of an uncertain VDT map's control points (thesis (5.16)-(5.19)):
// H = J^T J at the optimum, its sparse inverse's local blocks Z and the scans' shared Y.
#include "uncertain_map_problem.hpp"

#include <chrono>
#include <limits>

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
void UncertainVdtMap::Problem::covariance(ceres::Problem* problem,
                                          const std::vector<double*>& pose_blocks,
                                          const std::vector<Eigen::Matrix3d>* considered) {
  const auto t0 = Clock::now();
  for (double* b : pose_blocks) problem->SetParameterBlockVariable(b);  // their Jacobians
  const int n_ctrl = map.summary_.control_points;
  ceres::Problem::EvaluateOptions eo;
  for (int v = 0; v < n_ctrl; ++v) eo.parameter_blocks.push_back(&map.coef_[2 * v]);
  for (double* b : pose_blocks) eo.parameter_blocks.push_back(b);
  ceres::CRSMatrix crs;
  double cost = 0.0;
  problem->Evaluate(eo, &cost, nullptr, nullptr, &crs);
  const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>> j(
      crs.num_rows, crs.num_cols, static_cast<Eigen::Index>(crs.values.size()), crs.rows.data(),
      crs.cols.data(), crs.values.data());
  const Eigen::SparseMatrix<double> jc = j;
  const Eigen::SparseMatrix<double> h = jc.transpose() * jc;
  Eigen::MatrixXd c;
  if (considered != nullptr) {
    c = Eigen::MatrixXd::Zero(3 * static_cast<Eigen::Index>(considered->size()),
                              3 * static_cast<Eigen::Index>(considered->size()));
    for (std::size_t s = 0; s < considered->size(); ++s) {
      c.block<3, 3>(3 * static_cast<Eigen::Index>(s), 3 * static_cast<Eigen::Index>(s)) =
          (*considered)[s];
    }
  }
  MarginalCovariance mc;
  map.summary_.covariance_ok =
      mc.compute(h, 2 * static_cast<Eigen::Index>(n_ctrl), considered != nullptr ? &c : nullptr);
  if (!map.summary_.covariance_ok) {
    map.summary_.message += " | covariance: H is not positive definite, no marginal blocks";
    map.summary_.covariance_seconds = seconds_since(t0);
    return;
  }
  const int pw = map.cells_.x() + 3, ph = map.cells_.y() + 3;
  map.cov_.assign(static_cast<std::size_t>(n_ctrl) * 49 * 4,
                  std::numeric_limits<double>::quiet_NaN());
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
          double* block = &map.cov_[(static_cast<std::size_t>(v) * 49 + (db + 3) * 7 + da + 3) * 4];
          for (int r = 0; r < 2; ++r) {
            for (int c = 0; c < 2; ++c) block[2 * r + c] = mc.z(2 * v + r, 2 * w + c);
          }
        }
      }
    }
  }
  map.y_ = mc.y();
  map.summary_.covariance_seconds = seconds_since(t0);
}

}  // namespace vdtnav::mapping
