// The approximation variance of an uncertain VDT map: per cell, the variance of DT_v the spline
// cannot follow (thesis 5.4), measured from the readings' residuals with the scans' pose errors,
// the range noise and the field's own variance taken out.
#include "uncertain_map_problem.hpp"

#include <algorithm>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace vdtnav::mapping {

/// What the spline cannot follow (corners come out rounded, thesis 5.4; a door jamb, a
/// staircase of cells): a variance of DT_v per cell that cov(c) does not hold. A reading's
/// residual r_k = DT_v(o_k) holds its scan's pose error, the field's own error, range noise and
/// this. The scan's pose error is one 3-vector for all its readings: dX_s, fitted to them
/// (weighted least squares with the prior cov(X_s)), is taken out, e_k = r_k - dr_k/dX dX_s.
/// Then per cell, over its 3 x 3 neighbourhood,
///   var = mean_k (|e_k|^2 - trace(J R cov(p_k) R^T J^T) - trace cov(DT_v(o_k))),
/// clamped at 0: the range noise as the field sees it and the field's error (when computed)
/// taken out. Queries add it, shared by the readings of a cell in propagate().
void UncertainVdtMap::Problem::approximation_variance(const std::vector<MapScan>& scans,
                                                      const std::vector<Reading>& readings,
                                                      const std::vector<double>& dpose) {
  const double h = map.h_;
  const std::size_t n_cells = map.active_.size();
  struct Eval {
    Eigen::Vector2d r;
    Eigen::Matrix<double, 2, 3> jx;
    double noise;
  };
  std::vector<Eval> ev(readings.size());
  std::vector<Eigen::Matrix3d> normal(scans.size(), Eigen::Matrix3d::Zero());
  std::vector<Eigen::Vector3d> rhs(scans.size(), Eigen::Vector3d::Zero());
  for (std::size_t k = 0; k < readings.size(); ++k) {
    const Reading& r = readings[k];
    const auto s = static_cast<std::size_t>(r.scan);
    const std::vector<double*> c = blocks(r.cell);
    double res[2], d_x[6];
    boundary_residual(corner(r.cell), h, scans[s].pose, &dpose[3 * s], r.p, c.data(), res, nullptr,
                      d_x);
    Eval& e = ev[k];
    e.r = Eigen::Vector2d(res[0], res[1]);
    e.jx = Eigen::Map<const Eigen::Matrix<double, 2, 3, Eigen::RowMajor>>(d_x);
    const Eigen::Matrix2d j = e.jx.leftCols<2>();  // dr/dt = J
    const Eigen::Matrix2d rot = Eigen::Rotation2Dd(scans[s].pose[2]).toRotationMatrix();
    e.noise = (j * rot * r.cov * rot.transpose() * j.transpose()).trace();
    const double w = 1.0 / std::max(e.noise, 1e-8);
    normal[s].noalias() += w * e.jx.transpose() * e.jx;
    rhs[s].noalias() += w * e.jx.transpose() * e.r;
  }
  std::vector<Eigen::Vector3d> dx(scans.size(), Eigen::Vector3d::Zero());
  for (std::size_t s = 0; s < scans.size(); ++s) {
    if (scans[s].pose_covariance.cwiseAbs().maxCoeff() <= 0.0) continue;  // an exact pose
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(scans[s].pose_covariance);
    const Eigen::Matrix3d prior = es.eigenvectors() *
                                  es.eigenvalues().cwiseMax(1e-12).cwiseInverse().asDiagonal() *
                                  es.eigenvectors().transpose();
    dx[s] = (normal[s] + prior).ldlt().solve(rhs[s]);
  }
  std::vector<double> excess(n_cells, 0.0);
  std::vector<int> count(n_cells, 0);
  constexpr int kMinReadings = 8;
  for (std::size_t k = 0; k < readings.size(); ++k) {
    const Reading& r = readings[k];
    const Eval& e = ev[k];
    const auto s = static_cast<std::size_t>(r.scan);
    double field = 0.0;
    if (!map.cov_.empty()) {
      const UncertainMapSample smp = map.evaluate(
          transform_point(scans[s].pose + Eigen::Map<const Eigen::Vector3d>(&dpose[3 * s]), r.p));
      if (smp.inside) field = smp.covariance.trace();
    }
    const std::size_t cell = cell_index(r.cell.x(), r.cell.y());
    excess[cell] += (e.r - e.jx * dx[s]).squaredNorm() - e.noise - field;
    ++count[cell];
  }
  map.approximation_var_.assign(n_cells, 0.0f);
  for (int j = 0; j < map.cells_.y(); ++j) {
    for (int i = 0; i < map.cells_.x(); ++i) {
      double e = excess[cell_index(i, j)];
      int n = count[cell_index(i, j)];
      if (n < kMinReadings) {  // too few readings of its own: the 3 x 3 neighbourhood's
        for (int dj = -1; dj <= 1; ++dj) {
          for (int di = -1; di <= 1; ++di) {
            const int i2 = i + di, j2 = j + dj;
            if ((di == 0 && dj == 0) || i2 < 0 || j2 < 0 || i2 >= map.cells_.x() ||
                j2 >= map.cells_.y()) {
              continue;
            }
            e += excess[cell_index(i2, j2)];
            n += count[cell_index(i2, j2)];
          }
        }
      }
      if (n > 0 && e > 0.0) map.approximation_var_[cell_index(i, j)] = static_cast<float>(e / n);
    }
  }
}

}  // namespace vdtnav::mapping
