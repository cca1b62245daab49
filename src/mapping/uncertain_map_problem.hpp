#pragma once
// Internal (not installed): UncertainVdtMap::Problem, the lattice, the raster VDT of the observed
// points and the unknowns of an uncertain VDT map (thesis ch. 5), shared by fit and approximate.

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <ceres/problem.h>
#include <ceres/solver.h>
#include <Eigen/Core>

#include "vdtnav/mapping/map_scan.hpp"
#include "vdtnav/mapping/uncertain_vdt_map.hpp"

namespace vdtnav::detail {

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// The raster of the observed points' exact VDT and of the beams' crossings: h / 4, at most 5 cm.
inline double raster_resolution(double h) { return std::min(0.05, 0.25 * h); }

/// The fitted map's covariance arrays (UncertainVdtMap::CovarianceArrays points into them).
struct OwnedCovariance {
  std::vector<float> z;
  std::vector<std::uint32_t> y_row_start, y_column;
  std::vector<float> y_value;
  std::vector<float> cell_forms;
};

/// Entries of a column of Y below this fraction of its largest are left out: a scan's pose error
/// moves the control points near what it saw; its share of Y Y^T elsewhere is below 1e-6 of the
/// share where it is largest.
inline constexpr double kYDrop = 1e-3;

}  // namespace vdtnav::detail

namespace vdtnav::mapping {

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
  Eigen::Vector2i raster_size = Eigen::Vector2i::Zero();  ///< cells of the raster VDT
  std::vector<double> initial;

  Problem(UncertainVdtMap& m, const UncertainMapOptions& o);

  /// Lays the lattice over the points, builds their exact VDT and marks the band's cells.
  void layout(const std::vector<Eigen::Vector2d>& points);

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
      const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& nearest) const;

  /// Adds the weak prior on every control point.
  void add_control_prior(ceres::Problem* problem);

  /// \param iterative steps by CGNR instead of a sparse Cholesky factorisation (the fit).
  ceres::Solver::Summary solve(ceres::Problem* problem, bool iterative) const;

  /// The marginal covariance of the control points, cov(c) = Z + Y Y^T
  /// (uncertain_map_covariance.cpp); the problem is freed once its information is read.
  void covariance(std::unique_ptr<ceres::Problem> problem, const std::vector<double*>& pose_blocks,
                  const std::vector<Eigen::Matrix3d>* considered);

  /// The variance of DT_v per cell the spline cannot follow
  /// (uncertain_map_approximation_variance.cpp).
  void approximation_variance(const std::vector<MapScan>& scans,
                              const std::vector<Reading>& readings,
                              const std::vector<double>& dpose);
};

}  // namespace vdtnav::mapping
