// UncertainVdtMap::Problem (thesis ch. 5): the lattice of control points over the observed points,
// their exact raster VDT, the band of cells and the unknowns; the cut-locus test of a sample; the
// weak prior on the control points and the Ceres solve shared by fit() and approximate().
#include "uncertain_map_problem.hpp"

#include <algorithm>
#include <memory>

#include <ceres/ceres.h>
#include <ceres/normal_prior.h>

#include "vdtnav/core/error.hpp"

namespace vdtnav::mapping {

// ------------------------------------------------------------------------------- the lattice

UncertainVdtMap::Problem::Problem(UncertainVdtMap& m, const UncertainMapOptions& o)
    : map(m), options(o) {
  options.validate();
  const double h = options.spacing;
  band = options.band >= 0.0 ? options.band : std::max(0.75, 3.0 * h);
  near = options.near >= 0.0 ? options.near : 0.5 * h;
  map.h_ = h;
}

void UncertainVdtMap::Problem::layout(const std::vector<Eigen::Vector2d>& points) {
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
  const double res = detail::raster_resolution(h);
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
  raster_size = size;
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

// ------------------------------------------------------------------------------- cut loci

bool UncertainVdtMap::Problem::on_cut_locus(
    const Eigen::Vector2d& p,
    const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& nearest) const {
  const double delta = 0.5 * map.h_;
  const Eigen::Vector2d c0 = nearest(p);
  const double limit = options.cut_locus_ratio * delta + 2.0 * raster_res;
  for (const Eigen::Vector2d& step : {Eigen::Vector2d(delta, 0.0), Eigen::Vector2d(-delta, 0.0),
                                      Eigen::Vector2d(0.0, delta), Eigen::Vector2d(0.0, -delta)}) {
    if ((nearest(p + step) - c0).norm() > limit) return true;
  }
  return false;
}

// ------------------------------------------------------------------------------- the solve

void UncertainVdtMap::Problem::add_control_prior(ceres::Problem* problem) {
  const Eigen::Matrix2d a = Eigen::Matrix2d::Identity() / options.prior_sigma;
  for (std::size_t v = 0; v < initial.size() / 2; ++v) {
    problem->AddResidualBlock(
        new ceres::NormalPrior(a, Eigen::Vector2d(initial[2 * v], initial[2 * v + 1])), nullptr,
        &map.coef_[2 * v]);
  }
}

ceres::Solver::Summary UncertainVdtMap::Problem::solve(ceres::Problem* problem,
                                                       bool iterative) const {
  ceres::Solver::Options o;
  // The fit's steps by conjugate gradients on the normal equations (Jacobi preconditioned): on
  // the Intel lab 22 sparse Cholesky factorisations took 12.4 s of its 14.3 s, 27 inexact steps
  // 5.6 s, to the same tolerance on the cost. The approximation of a known VDT (linear) keeps
  // the exact step.
  o.linear_solver_type = iterative ? ceres::CGNR : ceres::SPARSE_NORMAL_CHOLESKY;
  o.preconditioner_type = ceres::JACOBI;
  o.max_num_iterations = options.max_iterations;
  o.num_threads = options.threads;
  o.function_tolerance = options.function_tolerance;
  o.parameter_tolerance = 1e-10;
  ceres::Solver::Summary s;
  ceres::Solve(o, problem, &s);
  return s;
}

}  // namespace vdtnav::mapping
