#include "vdtnav/mapping/uncertain_vdt_map.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <utility>

#include <ceres/ceres.h>
#include <ceres/normal_prior.h>
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "vdtnav/core/error.hpp"
#include "vdtnav/mapping/marginal_covariance.hpp"

namespace vdtnav::mapping {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

class PatchCost : public ceres::CostFunction {
 protected:
  PatchCost() {
    for (int k = 0; k < 16; ++k) mutable_parameter_block_sizes()->push_back(2);
    set_num_residuals(2);
  }
};

void scatter_control_jacobian(const double* d_c, double scale, double** jacobians) {
  for (int k = 0; k < 16; ++k) {
    if (jacobians[k] == nullptr) continue;
    for (int row = 0; row < 2; ++row) {
      for (int ch = 0; ch < 2; ++ch)
        jacobians[k][row * 2 + ch] = scale * d_c[row * 32 + 2 * k + ch];
    }
  }
}

/// The Eikonal residual of one sample, weighted.
class EikonalCost final : public PatchCost {
 public:
  EikonalCost(const SplinePatchBasis& basis, double weight, bool at_boundary)
      : basis_(basis), weight_(weight), at_boundary_(at_boundary) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    double d_c[64];
    (at_boundary_ ? hessian_eikonal_residual : eikonal_residual)(
        basis_, parameters, residuals, jacobians != nullptr ? d_c : nullptr);
    residuals[0] *= weight_;
    residuals[1] *= weight_;
    if (jacobians != nullptr) scatter_control_jacobian(d_c, weight_, jacobians);
    return std::isfinite(residuals[0]) && std::isfinite(residuals[1]);
  }

 private:
  SplinePatchBasis basis_;
  double weight_;
  bool at_boundary_;
};

/// The boundary residual of one reading at its scan's pose, weighted; with the scan's pose
/// error dX as a 17th parameter block when it is estimated.
class BoundaryCost final : public PatchCost {
 public:
  BoundaryCost(const Eigen::Vector2d& corner, double h, const Pose2& pose, const Eigen::Vector2d& p,
               double weight, bool pose_block)
      : corner_(corner), h_(h), pose_(pose), p_(p), weight_(weight), pose_block_(pose_block) {
    if (pose_block_) mutable_parameter_block_sizes()->push_back(3);
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    static constexpr double kZero[3] = {0.0, 0.0, 0.0};
    double d_c[64], d_x[6];
    const bool jac = jacobians != nullptr;
    const bool jac_x = jac && pose_block_ && jacobians[16] != nullptr;
    boundary_residual(corner_, h_, pose_, pose_block_ ? parameters[16] : kZero, p_, parameters,
                      residuals, jac ? d_c : nullptr, jac_x ? d_x : nullptr);
    residuals[0] *= weight_;
    residuals[1] *= weight_;
    if (jac) scatter_control_jacobian(d_c, weight_, jacobians);
    if (jac_x) {
      for (int k = 0; k < 6; ++k) jacobians[16][k] = weight_ * d_x[k];
    }
    return std::isfinite(residuals[0]) && std::isfinite(residuals[1]);
  }

 private:
  Eigen::Vector2d corner_;
  double h_;
  Pose2 pose_;
  Eigen::Vector2d p_;
  double weight_;
  bool pose_block_;
};

/// A sample of a known VDT (the least-squares approximation of Fig. 5.2): r = DT_v(s) - target.
class ValueCost final : public PatchCost {
 public:
  ValueCost(const SplinePatchBasis& basis, const Eigen::Vector2d& target)
      : basis_(basis), target_(target) {}
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    Eigen::Vector2d v;
    Eigen::Matrix2d j;
    spline_field(basis_, parameters, &v, &j);
    residuals[0] = v.x() - target_.x();
    residuals[1] = v.y() - target_.y();
    if (jacobians != nullptr) {
      for (int k = 0; k < 16; ++k) {
        if (jacobians[k] == nullptr) continue;
        jacobians[k][0] = basis_.w[k];
        jacobians[k][1] = 0.0;
        jacobians[k][2] = 0.0;
        jacobians[k][3] = basis_.w[k];
      }
    }
    return true;
  }

 private:
  SplinePatchBasis basis_;
  Eigen::Vector2d target_;
};

}  // namespace

void UncertainMapOptions::validate() const {
  VDTNAV_CHECK(std::isfinite(spacing) && spacing > 0.0, "uncertain map: spacing must be > 0");
  VDTNAV_CHECK(std::isfinite(band), "uncertain map: band must be finite");
  VDTNAV_CHECK(samples_per_axis >= 1, "uncertain map: samples_per_axis must be >= 1");
  VDTNAV_CHECK(std::isfinite(eikonal_sigma) && eikonal_sigma > 0.0,
               "uncertain map: eikonal_sigma must be > 0");
  VDTNAV_CHECK(std::isfinite(prior_sigma) && prior_sigma > 0.0,
               "uncertain map: prior_sigma must be > 0");
  VDTNAV_CHECK(std::isfinite(near) && std::isfinite(boundary_sigma) &&
                   std::isfinite(cut_locus_ratio) && cut_locus_ratio > 0.0,
               "uncertain map: near, boundary_sigma and cut_locus_ratio must be finite");
  VDTNAV_CHECK(max_iterations >= 1 && threads >= 1,
               "uncertain map: max_iterations and threads must be >= 1");
}

// ------------------------------------------------------------------------------- the lattice

/// The lattice, the raster VDT of the points and the unknowns, shared by fit() and approximate().
struct UncertainVdtMap::Problem {
  /// A reading of a scan: robot-frame point and the cell its world point falls in.
  struct Reading {
    int scan;
    Eigen::Vector2d p;
    Eigen::Vector2i cell;
    Eigen::Matrix2d cov;  ///< of p (robot frame): the range noise along the beam
  };

  UncertainVdtMap& map;
  UncertainMapOptions options;
  double band = 0.0, near = 0.0;
  double raster_res = 0.05;
  std::vector<double> initial;

  Problem(UncertainVdtMap& m, const UncertainMapOptions& o) : map(m), options(o) {
    options.validate();
    const double h = options.spacing;
    band = options.band >= 0.0 ? options.band : std::max(0.75, 3.0 * h);
    near = options.near >= 0.0 ? options.near : 0.5 * h;
    map.h_ = h;
  }

  /// Lays the lattice over the points, builds their exact VDT and marks the band's cells.
  void layout(const std::vector<Eigen::Vector2d>& points) {
    VDTNAV_CHECK(!points.empty(), "uncertain map: no observed point to fit the map to");
    const double h = map.h_;
    Eigen::Vector2d lo = points.front(), hi = points.front();
    for (const auto& p : points) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    const double margin = band + 3.0 * h;
    map.origin_ = ((lo.array() - margin) / h).floor().matrix() * h;
    map.cells_ = ((hi.array() + margin - map.origin_.array()) / h).ceil().cast<int>().matrix();
    VDTNAV_CHECK(static_cast<double>(map.cells_.x()) * map.cells_.y() < 2e8,
                 "uncertain map: the lattice over the observed points is too large (points far "
                 "apart? spacing too small?)");
    // The exact VDT of the observed points on a grid of h/4 (at most 5 cm).
    const double res = std::min(0.05, 0.25 * h);
    const Eigen::Vector2i size =
        (map.cells_.cast<double>() * (h / res)).array().ceil().cast<int>().matrix() +
        Eigen::Vector2i::Ones();
    OccupancyGrid<2> occupied(size, GridFrame<2>(res, map.origin_));
    for (const auto& p : points) {
      const Eigen::Vector2i cell = occupied.frame().cell_of(p);
      if (occupied.contains(cell)) occupied(cell) = 1;
    }
    map.raster_ = std::make_shared<VdtMap2>(VdtMap2::build(occupied, true));
    raster_res = res;
    // The band: cells whose centre lies within band (+ half a diagonal) of an observed point.
    map.active_.assign(static_cast<std::size_t>(map.cells_.x()) * map.cells_.y(), 0);
    for (int j = 0; j < map.cells_.y(); ++j) {
      for (int i = 0; i < map.cells_.x(); ++i) {
        const Eigen::Vector2d c = map.origin_ + Eigen::Vector2d(i + 0.5, j + 0.5) * h;
        if (distance(c) <= band + 0.7072 * h) map.active_[cell_index(i, j)] = 1;
      }
    }
    // The unknowns: the 4 x 4 control points of every cell in the band.
    const int pw = map.cells_.x() + 3;
    map.vars_.assign(static_cast<std::size_t>(pw) * (map.cells_.y() + 3), -1);
    int n = 0;
    for (int j = 0; j < map.cells_.y(); ++j) {
      for (int i = 0; i < map.cells_.x(); ++i) {
        if (!map.active_[cell_index(i, j)]) continue;
        for (int b = 0; b < 4; ++b) {
          for (int a = 0; a < 4; ++a) {
            int& v = map.vars_[static_cast<std::size_t>(j + b) * pw + i + a];
            if (v >= 0) continue;
            v = n++;
            map.v_col_.push_back(i + a);
            map.v_row_.push_back(j + b);
          }
        }
      }
    }
    // Initial guess: control point m sits at node m (padded index m + 1); a cubic B-spline whose
    // control points are samples of a linear field reproduces it, and the VDT is linear near walls.
    map.coef_.assign(2 * static_cast<std::size_t>(n), 0.0);
    for (int b = 0; b < map.cells_.y() + 3; ++b) {
      for (int a = 0; a < pw; ++a) {
        const int v = map.variable(a, b);
        if (v < 0) continue;
        const Eigen::Vector2d node = map.origin_ + Eigen::Vector2d(a - 1, b - 1) * h;
        const Eigen::Vector2d value = node - map.raster_->nearest_occupied_point(node);
        map.coef_[2 * v] = value.x();
        map.coef_[2 * v + 1] = value.y();
      }
    }
    initial = map.coef_;
    map.summary_.control_points = n;
  }

  [[nodiscard]] std::size_t cell_index(int i, int j) const {
    return static_cast<std::size_t>(j) * map.cells_.x() + i;
  }
  [[nodiscard]] double distance(const Eigen::Vector2d& p) const {
    return (p - map.raster_->nearest_occupied_point(p)).norm();
  }
  /// The cell of p (may be outside the lattice).
  [[nodiscard]] Eigen::Vector2i cell_of(const Eigen::Vector2d& p) const {
    return ((p - map.origin_) / map.h_).array().floor().cast<int>().matrix();
  }
  [[nodiscard]] bool active(const Eigen::Vector2i& c) const {
    return c.x() >= 0 && c.y() >= 0 && c.x() < map.cells_.x() && c.y() < map.cells_.y() &&
           map.active_[cell_index(c.x(), c.y())];
  }
  [[nodiscard]] Eigen::Vector2d corner(const Eigen::Vector2i& c) const {
    return map.origin_ + c.cast<double>() * map.h_;
  }
  /// The 16 control-point blocks of cell c.
  [[nodiscard]] std::vector<double*> blocks(const Eigen::Vector2i& c) {
    std::vector<double*> out(16);
    for (int b = 0; b < 4; ++b) {
      for (int a = 0; a < 4; ++a)
        out[a + 4 * b] = &map.coef_[2 * map.variable(c.x() + a, c.y() + b)];
    }
    return out;
  }
  /// Whether the nearest observed point jumps around p (a cut locus of the points' VDT).
  [[nodiscard]] bool on_cut_locus(
      const Eigen::Vector2d& p,
      const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& nearest) const {
    const double delta = 0.5 * map.h_;
    const Eigen::Vector2d c0 = nearest(p);
    const double limit = options.cut_locus_ratio * delta + 2.0 * raster_res;
    for (const Eigen::Vector2d& step :
         {Eigen::Vector2d(delta, 0.0), Eigen::Vector2d(-delta, 0.0), Eigen::Vector2d(0.0, delta),
          Eigen::Vector2d(0.0, -delta)}) {
      if ((nearest(p + step) - c0).norm() > limit) return true;
    }
    return false;
  }

  /// Adds the weak prior on every control point.
  void add_control_prior(ceres::Problem* problem) {
    const Eigen::Matrix2d a = Eigen::Matrix2d::Identity() / options.prior_sigma;
    for (std::size_t v = 0; v < initial.size() / 2; ++v) {
      problem->AddResidualBlock(
          new ceres::NormalPrior(a, Eigen::Vector2d(initial[2 * v], initial[2 * v + 1])), nullptr,
          &map.coef_[2 * v]);
    }
  }

  ceres::Solver::Summary solve(ceres::Problem* problem) const {
    ceres::Solver::Options o;
    o.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    o.max_num_iterations = options.max_iterations;
    o.num_threads = options.threads;
    o.function_tolerance = options.function_tolerance;
    o.parameter_tolerance = 1e-10;
    ceres::Solver::Summary s;
    ceres::Solve(o, problem, &s);
    return s;
  }

  /// The marginal covariance of the control points (see the header): cov(c) = Z + Y Y^T from the
  /// information H = J^T J of the weighted residuals at the optimum over (c, dX), Z's blocks for
  /// the pairs of control points within three of each other (every pair one cell's support
  /// holds) on the pattern of its sparse Cholesky factor; never a dense inverse.
  void covariance(ceres::Problem* problem, const std::vector<double*>& pose_blocks,
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
            double* block =
                &map.cov_[(static_cast<std::size_t>(v) * 49 + (db + 3) * 7 + da + 3) * 4];
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

  /// What the spline cannot follow (corners come out rounded, thesis 5.4; a door jamb, a
  /// staircase of cells): a variance of DT_v per cell that cov(c) does not hold. A reading's
  /// residual r_k = DT_v(o_k) holds its scan's pose error, the field's own error, range noise and
  /// this. The scan's pose error is one 3-vector for all its readings: dX_s, fitted to them
  /// (weighted least squares with the prior cov(X_s)), is taken out, e_k = r_k - dr_k/dX dX_s.
  /// Then per cell, over its 3 x 3 neighbourhood,
  ///   var = mean_k (|e_k|^2 - trace(J R cov(p_k) R^T J^T) - trace cov(DT_v(o_k))),
  /// clamped at 0: the range noise as the field sees it and the field's error (when computed)
  /// taken out. Queries add it, shared by the readings of a cell in propagate().
  void approximation_variance(const std::vector<MapScan>& scans,
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
      boundary_residual(corner(r.cell), h, scans[s].pose, &dpose[3 * s], r.p, c.data(), res,
                        nullptr, d_x);
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
};

// ------------------------------------------------------------------------------- fit

UncertainVdtMap UncertainVdtMap::fit(const std::vector<MapScan>& scans,
                                     const UncertainMapOptions& options) {
  using Reading = Problem::Reading;
  const auto t0 = Clock::now();
  UncertainVdtMap map;
  Problem pb(map, options);
  const UncertainMapOptions& o = pb.options;
  const double h = o.spacing;
  const double floor_sigma = o.boundary_sigma >= 0.0 ? o.boundary_sigma : h / 40.0;
  map.approximation_sigma_ = floor_sigma;

  // The readings, at the given poses; non-finite ones are dropped.
  std::vector<Reading> readings;
  for (std::size_t s = 0; s < scans.size(); ++s) {
    VDTNAV_CHECK(
        scans[s].pose.allFinite() && scans[s].pose_covariance.allFinite(),
        "uncertain map: scan " + std::to_string(s) + " has a non-finite pose or covariance");
    const double sr = scans[s].points.sigma_range;
    VDTNAV_CHECK(std::isfinite(sr) && sr >= 0.0,
                 "uncertain map: scan " + std::to_string(s) + " has no valid range noise");
    const ScanPoints& pts = scans[s].points;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      if (!pts.points[i].allFinite()) continue;
      readings.push_back(
          {static_cast<int>(s), pts.points[i], Eigen::Vector2i::Zero(), pts.point_covariance(i)});
      map.observed_.push_back(transform_point(scans[s].pose, pts.points[i]));
    }
  }
  pb.layout(map.observed_);
  // At most max_points_per_cell readings of one scan in one cell, evenly spread over the scan's
  // readings there (a near wall gives dozens per cell, which cost time and add little: the
  // pose errors they share do not average out).
  {
    std::unordered_map<std::int64_t, std::pair<int, int>> per_cell;  // (count, seen)
    const auto key = [&](int scan, const Eigen::Vector2i& c) {
      return (static_cast<std::int64_t>(scan) * (map.cells_.y() + 1) + c.y()) *
                 (map.cells_.x() + 1) +
             c.x();
    };
    for (std::size_t k = 0; k < readings.size(); ++k) {
      readings[k].cell = pb.cell_of(map.observed_[k]);
      ++per_cell[key(readings[k].scan, readings[k].cell)].first;
    }
    std::vector<Reading> kept;
    std::vector<Eigen::Vector2d> kept_points;
    const long cap = o.max_points_per_cell;
    for (std::size_t k = 0; k < readings.size(); ++k) {
      auto& [count, seen] = per_cell[key(readings[k].scan, readings[k].cell)];
      const bool keep =
          cap <= 0 || count <= cap || (seen * cap) / count != ((seen + 1) * cap) / count;
      ++seen;
      if (!keep || !pb.active(readings[k].cell)) continue;
      kept.push_back(readings[k]);
      kept_points.push_back(map.observed_[k]);
    }
    readings = std::move(kept);
    map.observed_ = std::move(kept_points);
  }

  // Eikonal samples: the vector form away from the boundary, the Hessian form near it.
  const int n = o.samples_per_axis;
  const double eik_w = 1.0 / o.eikonal_sigma;
  struct Sample {
    Eigen::Vector2i cell;
    SplinePatchBasis basis;
    bool at_boundary;
  };
  std::vector<Sample> samples;
  const auto nearest = [&](const Eigen::Vector2d& q) {
    return map.raster_->nearest_occupied_point(q);
  };
  for (int j = 0; j < map.cells_.y(); ++j) {
    for (int i = 0; i < map.cells_.x(); ++i) {
      if (!map.active_[pb.cell_index(i, j)]) continue;
      for (int sy = 0; sy < n; ++sy) {
        for (int sx = 0; sx < n; ++sx) {
          const double tx = (sx + 0.5) / n, ty = (sy + 0.5) / n;
          const Eigen::Vector2d p = map.origin_ + Eigen::Vector2d(i + tx, j + ty) * h;
          const double d = pb.distance(p);
          if (d > pb.band) continue;
          if (pb.on_cut_locus(p, nearest)) {
            ++map.summary_.cut_locus_samples;
            continue;
          }
          samples.push_back({Eigen::Vector2i(i, j), spline_patch_basis(tx, ty, h), d < pb.near});
        }
      }
    }
  }
  map.summary_.eikonal_samples = static_cast<int>(samples.size());

  // The scans' pose errors dX_s: unknowns with the prior N(0, cov(X_s)) (whitened by
  // cov^-1/2 = D^-1/2 V^T, eigenvalues floored at 1e-12) when estimated; otherwise held at 0 and
  // considered: the points' weights (5.14) take their pose noise (5.13), and the covariance
  // carries it shared by each scan's points (see covariance()).
  std::vector<double> dpose(3 * scans.size(), 0.0);
  std::vector<char> has_pose(scans.size(), 0);
  for (std::size_t s = 0; s < scans.size(); ++s) {
    has_pose[s] = scans[s].pose_covariance.cwiseAbs().maxCoeff() > 0.0 ? 1 : 0;
  }

  // The weighted problem (5.15), solved by Ceres.
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  std::vector<char> has_reading(scans.size(), 0);
  for (const Reading& r : readings) {
    const auto s = static_cast<std::size_t>(r.scan);
    const double sr = scans[s].points.sigma_range;
    double var = sr * sr + floor_sigma * floor_sigma;
    if (has_pose[s] && !o.estimate_scan_poses) {
      // (5.13): the point's covariance from its scan's pose, d o / dX = [I | R' p]; its mean
      // variance over the two axes joins the reading's (5.14).
      Eigen::Matrix<double, 2, 3> jx;
      const Eigen::Vector2d rp = Eigen::Rotation2Dd(scans[s].pose[2]) * r.p;
      jx << 1.0, 0.0, -rp.y(), 0.0, 1.0, rp.x();
      var += 0.5 * (jx * scans[s].pose_covariance * jx.transpose()).trace();
    }
    std::vector<double*> blocks = pb.blocks(r.cell);
    if (has_pose[s]) blocks.push_back(&dpose[3 * s]);
    problem.AddResidualBlock(new BoundaryCost(pb.corner(r.cell), h, scans[s].pose, r.p,
                                              1.0 / std::sqrt(var), has_pose[s] != 0),
                             nullptr, blocks);
    has_reading[s] = 1;
  }
  map.summary_.boundary_points = static_cast<int>(readings.size());
  std::vector<double*> pose_blocks;
  std::vector<Eigen::Matrix3d> pose_covariances;
  for (std::size_t s = 0; s < scans.size(); ++s) {
    if (!has_pose[s] || !has_reading[s]) continue;
    pose_blocks.push_back(&dpose[3 * s]);
    pose_covariances.push_back(scans[s].pose_covariance);
    if (!o.estimate_scan_poses) {
      problem.SetParameterBlockConstant(&dpose[3 * s]);
      continue;
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(scans[s].pose_covariance);
    const Eigen::Vector3d ev = es.eigenvalues().cwiseMax(1e-12);
    const Eigen::Matrix3d a =
        ev.cwiseSqrt().cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
    problem.AddResidualBlock(new ceres::NormalPrior(a, Eigen::Vector3d::Zero()), nullptr,
                             &dpose[3 * s]);
  }
  map.summary_.scan_poses = o.estimate_scan_poses ? static_cast<int>(pose_blocks.size()) : 0;
  for (const auto& smp : samples) {
    problem.AddResidualBlock(new EikonalCost(smp.basis, eik_w, smp.at_boundary), nullptr,
                             pb.blocks(smp.cell));
  }
  pb.add_control_prior(&problem);
  const ceres::Solver::Summary summary = pb.solve(&problem);
  map.summary_.initial_cost = summary.initial_cost;
  map.summary_.final_cost = summary.final_cost;
  map.summary_.iterations = static_cast<int>(summary.iterations.size()) - 1;
  map.summary_.converged = summary.termination_type == ceres::CONVERGENCE;
  map.summary_.message = summary.BriefReport();
  for (std::size_t s = 0; s < scans.size(); ++s) {
    map.scan_poses_.push_back(scans[s].pose + Eigen::Map<const Eigen::Vector3d>(&dpose[3 * s]));
    map.scan_poses_.back()[2] = wrap_angle(map.scan_poses_.back()[2]);
  }

  // Cells no residual reached stay out of the map (their pairs of control points are not in H).
  // (Leaving out also the cells a cut locus crosses without an observed point, where the spline's
  // average of the two sides' DT_v draws a phantom wall across a doorway, was tried: the Intel
  // map's holes then cost vdt-opt 0.04 -> 0.21 m on the relations.)
  std::vector<char> used(map.active_.size(), 0);
  for (const auto& r : readings) used[pb.cell_index(r.cell.x(), r.cell.y())] = 1;
  for (const auto& smp : samples) used[pb.cell_index(smp.cell.x(), smp.cell.y())] = 1;
  for (std::size_t c = 0; c < used.size(); ++c) {
    map.active_[c] = static_cast<char>(map.active_[c] && used[c]);
  }
  map.summary_.fit_seconds = seconds_since(t0);
  if (o.compute_covariance) {
    pb.covariance(&problem, pose_blocks, o.estimate_scan_poses ? nullptr : &pose_covariances);
  }
  pb.approximation_variance(scans, readings, dpose);
  return map;
}

// ------------------------------------------------------------------------------- Fig. 5.2

UncertainVdtMap UncertainVdtMap::approximate(
    const std::vector<Eigen::Vector2d>& boundary,
    const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& vdt,
    const UncertainMapOptions& options) {
  const auto t0 = Clock::now();
  UncertainVdtMap map;
  Problem pb(map, options);
  map.observed_ = boundary;
  pb.layout(boundary);
  const double h = map.h_;
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  const auto nearest = [&](const Eigen::Vector2d& q) -> Eigen::Vector2d { return q - vdt(q); };
  constexpr int kSamples = 4;
  std::vector<char> used(map.active_.size(), 0);
  for (int j = 0; j < map.cells_.y(); ++j) {
    for (int i = 0; i < map.cells_.x(); ++i) {
      if (!map.active_[pb.cell_index(i, j)]) continue;
      for (int sy = 0; sy < kSamples; ++sy) {
        for (int sx = 0; sx < kSamples; ++sx) {
          const double tx = (sx + 0.5) / kSamples, ty = (sy + 0.5) / kSamples;
          const Eigen::Vector2d p = map.origin_ + Eigen::Vector2d(i + tx, j + ty) * h;
          if (pb.on_cut_locus(p, nearest)) {
            ++map.summary_.cut_locus_samples;
            continue;
          }
          problem.AddResidualBlock(new ValueCost(spline_patch_basis(tx, ty, h), vdt(p)), nullptr,
                                   pb.blocks(Eigen::Vector2i(i, j)));
          used[pb.cell_index(i, j)] = 1;
          ++map.summary_.eikonal_samples;
        }
      }
    }
  }
  pb.add_control_prior(&problem);
  const ceres::Solver::Summary s = pb.solve(&problem);
  for (std::size_t c = 0; c < used.size(); ++c)
    map.active_[c] = static_cast<char>(map.active_[c] && used[c]);
  map.summary_.converged = s.termination_type == ceres::CONVERGENCE;
  map.summary_.iterations = static_cast<int>(s.iterations.size());
  map.summary_.message = s.BriefReport();
  map.summary_.initial_cost = s.initial_cost;
  map.summary_.final_cost = s.final_cost;
  map.summary_.fit_seconds = seconds_since(t0);
  return map;
}

// ------------------------------------------------------------------------------- queries

bool UncertainVdtMap::cell_active(int i, int j) const noexcept {
  return i >= 0 && j >= 0 && i < cells_.x() && j < cells_.y() &&
         active_[static_cast<std::size_t>(j) * cells_.x() + i] != 0;
}

bool UncertainVdtMap::locate(const Eigen::Vector2d& p, SplinePatchBasis* basis,
                             std::array<int, 16>* vars, std::size_t* cell) const {
  if (h_ <= 0.0 || !p.allFinite()) return false;
  const Eigen::Vector2d u = (p - origin_) / h_;
  const Eigen::Vector2d fl = u.array().floor().matrix();
  if (fl.x() < 0 || fl.y() < 0 || fl.x() >= cells_.x() || fl.y() >= cells_.y()) return false;
  const int i = static_cast<int>(fl.x()), j = static_cast<int>(fl.y());
  if (!cell_active(i, j)) return false;
  if (cell != nullptr) *cell = static_cast<std::size_t>(j) * cells_.x() + i;
  *basis = spline_patch_basis(u.x() - i, u.y() - j, h_);
  for (int b = 0; b < 4; ++b) {
    for (int a = 0; a < 4; ++a) (*vars)[a + 4 * b] = variable(i + a, j + b);
  }
  return true;
}

UncertainMapSample UncertainVdtMap::evaluate(const Eigen::Vector2d& p) const {
  UncertainMapSample out;
  SplinePatchBasis b;
  std::array<int, 16> var{};
  std::size_t cell = 0;
  if (!locate(p, &b, &var, &cell)) return out;
  const double* c[16];
  for (int k = 0; k < 16; ++k) c[k] = &coef_[2 * static_cast<std::size_t>(var[k])];
  spline_field(b, c, &out.value, &out.jacobian);
  out.inside = true;
  if (cov_.empty()) return out;
  // cov(DT_v) = sum_{k,l} w_k w_l cov(c_k, c_l) = B Z B^T + (B Y)(B Y)^T over the cell's support.
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (int k = 0; k < 16; ++k) {
    const double* zk = &cov_[static_cast<std::size_t>(var[k]) * 49 * 4];
    for (int l = 0; l < 16; ++l) {
      const int da = l % 4 - k % 4, db = l / 4 - k / 4;
      const double* blk = zk + ((db + 3) * 7 + da + 3) * 4;
      const double ww = b.w[k] * b.w[l];
      cov(0, 0) += ww * blk[0];
      cov(0, 1) += ww * blk[1];
      cov(1, 0) += ww * blk[2];
      cov(1, 1) += ww * blk[3];
    }
  }
  if (y_.cols() > 0) {
    Eigen::Matrix<double, 2, Eigen::Dynamic> by =
        Eigen::Matrix<double, 2, Eigen::Dynamic>::Zero(2, y_.cols());
    for (int k = 0; k < 16; ++k)
      by += b.w[k] * y_.middleRows<2>(2 * static_cast<Eigen::Index>(var[k]));
    cov.noalias() += by * by.transpose();
  }
  out.covariance = 0.5 * (cov + cov.transpose());
  if (!approximation_var_.empty()) out.covariance.diagonal().array() += approximation_var_[cell];
  return out;
}

bool UncertainVdtMap::dt_covariance(const Eigen::Vector2d& p, Eigen::Matrix2d* cov) const {
  const UncertainMapSample s = evaluate(p);
  if (!s.inside || cov_.empty() || !s.covariance.allFinite()) return false;
  *cov = s.covariance;
  return true;
}

Eigen::Matrix3d UncertainVdtMap::propagate(const std::vector<Eigen::Vector2d>& q,
                                           const std::vector<Sensitivity>& s,
                                           std::vector<char>* known) const {
  VDTNAV_ASSERT(q.size() == s.size());
  if (known != nullptr) known->assign(q.size(), 0);
  Eigen::Matrix3d out = Eigen::Matrix3d::Zero();
  if (cov_.empty()) return out;
  // g_m = sum over the readings whose patch holds control point m of s_i w_m(q_i).
  std::unordered_map<int, Eigen::Matrix<double, 3, 2>> g;
  g.reserve(4 * q.size());
  // The approximation error, shared by the readings of one cell: sum_cells S_c var_c S_c^T.
  std::unordered_map<std::size_t, Eigen::Matrix<double, 3, 2>> per_cell;
  for (std::size_t i = 0; i < q.size(); ++i) {
    SplinePatchBasis b;
    std::array<int, 16> var{};
    std::size_t cell = 0;
    if (!locate(q[i], &b, &var, &cell)) continue;
    if (known != nullptr) (*known)[i] = 1;
    if (!approximation_var_.empty() && approximation_var_[cell] > 0.0f) {
      auto [it, fresh] = per_cell.try_emplace(cell);
      if (fresh) it->second.setZero();
      it->second += s[i];
    }
    for (int k = 0; k < 16; ++k) {
      auto [it, fresh] = g.try_emplace(var[k]);
      if (fresh) it->second.setZero();
      it->second.noalias() += b.w[k] * s[i];
    }
  }
  if (g.empty()) return out;
  for (const auto& [cell, sc] : per_cell) {
    out.noalias() += static_cast<double>(approximation_var_[cell]) * sc * sc.transpose();
  }
  // sum_{m,n} g_m Z_mn g_n^T over the pairs within three control points (Z's stored blocks; an
  // exact G^T A^-1 G by a triangular solve with A's factor changed the Experiment 2 localization's
  // ANEES by 0.1 %, at 6x the time on the Intel map).
  const int pw = cells_.x() + 3;
  for (const auto& [v, gv] : g) {
    const int a = v_col_[static_cast<std::size_t>(v)], b = v_row_[static_cast<std::size_t>(v)];
    const double* zv = &cov_[static_cast<std::size_t>(v) * 49 * 4];
    for (int db = -3; db <= 3; ++db) {
      for (int da = -3; da <= 3; ++da) {
        const double* blk = zv + ((db + 3) * 7 + da + 3) * 4;
        if (!std::isfinite(blk[0])) continue;
        const int w = vars_[static_cast<std::size_t>(b + db) * pw + a + da];
        const auto it = g.find(w);
        if (it == g.end()) continue;
        const Eigen::Map<const Eigen::Matrix<double, 2, 2, Eigen::RowMajor>> z(blk);
        out.noalias() += gv * z * it->second.transpose();
      }
    }
  }
  // (sum_m g_m Y_m)(sum_m g_m Y_m)^T: the scans' pose errors, shared by every control point.
  if (y_.cols() > 0) {
    Eigen::Matrix<double, 3, Eigen::Dynamic> gy =
        Eigen::Matrix<double, 3, Eigen::Dynamic>::Zero(3, y_.cols());
    for (const auto& [v, gv] : g)
      gy.noalias() += gv * y_.middleRows<2>(2 * static_cast<Eigen::Index>(v));
    out.noalias() += gy * gy.transpose();
  }
  return 0.5 * (out + out.transpose());
}

VdtMap2 UncertainVdtMap::to_vdt_map(double resolution) const {
  VDTNAV_CHECK(std::isfinite(resolution) && resolution > 0.0,
               "uncertain map: the resolution of the sampled map must be > 0");
  VDTNAV_CHECK(raster_ != nullptr, "uncertain map: the map has not been fitted");
  const Eigen::Vector2i size =
      (cells_.cast<double>() * (h_ / resolution)).array().ceil().cast<int>().matrix();
  OccupancyGrid<2> occupied(size, GridFrame<2>(resolution, origin_));
  for (const auto& p : observed_) {
    const Eigen::Vector2i cell = occupied.frame().cell_of(p);
    if (occupied.contains(cell)) occupied(cell) = 1;
  }
  const VdtMap2 exact = VdtMap2::build(occupied, true);
  // Samples of the fitted field at the cell centres; the exact VDT of the points outside the band.
  std::vector<float> samples(static_cast<std::size_t>(size.x()) * size.y() * 2);
  for (int y = 0; y < size.y(); ++y) {
    for (int x = 0; x < size.x(); ++x) {
      const Eigen::Vector2d c = occupied.frame().cell_center(Eigen::Vector2i(x, y));
      const UncertainMapSample s = evaluate(c);
      const Eigen::Vector2d v =
          s.inside ? s.value : Eigen::Vector2d(c - exact.nearest_occupied_point(c));
      const std::size_t k = (static_cast<std::size_t>(y) * size.x() + x) * 2;
      samples[k] = static_cast<float>(v.x());
      samples[k + 1] = static_cast<float>(v.y());
    }
  }
  return VdtMap2(exact.nearest_cells(), VdtMap2::Field(size, std::move(samples)));
}

}  // namespace vdtnav::mapping
