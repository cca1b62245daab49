// The least-squares fits of an uncertain VDT map: to scans through the Eikonal and boundary
// residuals (thesis ch. 5, the weighted problem (5.15)) and to a known VDT (Fig. 5.2).
#include "uncertain_map_problem.hpp"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>

#include <ceres/ceres.h>
#include <ceres/normal_prior.h>
#include <Eigen/Eigenvalues>

#include "vdtnav/core/error.hpp"
#include "vdtnav/mapping/occupancy_mapper.hpp"

namespace vdtnav::mapping {

using detail::Clock;
using detail::seconds_since;

namespace {

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

/// The free-space residual of a sample the beams cross (see the file comment):
/// r_F = max(0, d_min - |DT_v(s)|) / sigma.
class FreeSpaceCost final : public ceres::CostFunction {
 public:
  FreeSpaceCost(const SplinePatchBasis& basis, double d_min, double weight)
      : basis_(basis), d_min_(d_min), weight_(weight) {
    for (int k = 0; k < 16; ++k) mutable_parameter_block_sizes()->push_back(2);
    set_num_residuals(1);
  }
  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    Eigen::Vector2d v = Eigen::Vector2d::Zero();
    for (int k = 0; k < 16; ++k)
      v += basis_.w[k] * Eigen::Vector2d(parameters[k][0], parameters[k][1]);
    const double n = std::max(v.norm(), 1e-3);
    const bool active = n < d_min_;
    residuals[0] = active ? weight_ * (d_min_ - n) : 0.0;
    if (jacobians != nullptr) {
      const Eigen::Vector2d g =
          active ? Eigen::Vector2d(-weight_ * v / n) : Eigen::Vector2d::Zero();
      for (int k = 0; k < 16; ++k) {
        if (jacobians[k] == nullptr) continue;
        jacobians[k][0] = basis_.w[k] * g.x();
        jacobians[k][1] = basis_.w[k] * g.y();
      }
    }
    return std::isfinite(residuals[0]);
  }

 private:
  SplinePatchBasis basis_;
  double d_min_, weight_;
};

/// Where the beams pass: per cell of a grid over the beams, the crossings and the ends.
struct BeamCounts {
  GridFrame<2> frame;
  Eigen::Vector2i size = Eigen::Vector2i::Zero();
  std::vector<std::uint32_t> crossed, ended;
  [[nodiscard]] std::int64_t index(const Eigen::Vector2d& p) const {
    const Eigen::Vector2i c = frame.cell_of(p);
    if (c.x() < 0 || c.y() < 0 || c.x() >= size.x() || c.y() >= size.y()) return -1;
    return static_cast<std::int64_t>(c.y()) * size.x() + c.x();
  }
};

/// Walks every beam (sensor origin o = p - r u to its end p, world frame) on a grid of `res`: the
/// cells it crosses up to where its reading may lie (3 sigma of the range and of the scan's
/// position, and a cell, before its end).
BeamCounts count_beams(const std::vector<MapScan>& scans, double res) {
  BeamCounts b;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  for (const MapScan& s : scans) {
    for (std::size_t i = 0; i < s.points.size(); ++i) {
      if (!s.points.points[i].allFinite()) continue;
      const Eigen::Vector2d e = transform_point(s.pose, s.points.points[i]);
      lo = lo.cwiseMin(e);
      hi = hi.cwiseMax(e);
    }
    lo = lo.cwiseMin(s.pose.head<2>());
    hi = hi.cwiseMax(s.pose.head<2>());
  }
  if (!lo.allFinite()) return b;
  b.frame = GridFrame<2>(res, ((lo.array() - 1.0) / res).floor().matrix() * res);
  b.size = ((hi - b.frame.origin()).array() / res + 2.0).ceil().cast<int>().matrix();
  if (static_cast<double>(b.size.x()) * b.size.y() > 4e8) return BeamCounts{};
  const auto n = static_cast<std::size_t>(b.size.x()) * b.size.y();
  b.crossed.assign(n, 0);
  b.ended.assign(n, 0);
  for (const MapScan& s : scans) {
    const ScanPoints& pts = s.points;
    const double margin = 3.0 * std::sqrt(pts.sigma_range * pts.sigma_range +
                                          s.pose_covariance.topLeftCorner<2, 2>().trace()) +
                          res;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      if (!pts.points[i].allFinite()) continue;
      const Eigen::Vector2d e = transform_point(s.pose, pts.points[i]);
      const std::int64_t ke = b.index(e);
      if (ke >= 0) ++b.ended[static_cast<std::size_t>(ke)];
      if (i >= pts.ranges.size() || i >= pts.directions.size()) continue;
      const Eigen::Vector2d o = transform_point(
          s.pose, Eigen::Vector2d(pts.points[i] - pts.ranges[i] * pts.directions[i]));
      // The cells the beam passes through before the cell it ends in, each once.
      const double len = (e - o).norm();
      const int steps = static_cast<int>((len - margin) / (0.5 * res));
      std::int64_t last = -1;
      for (int k = 0; k < steps; ++k) {
        const std::int64_t c = b.index(o + (e - o) * (k * 0.5 * res / len));
        if (c < 0 || c == last || c == ke) continue;
        ++b.crossed[static_cast<std::size_t>(c)];
        last = c;
      }
    }
  }
  return b;
}

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

// ------------------------------------------------------------------------------- fit

UncertainVdtMap UncertainVdtMap::fit(const std::vector<MapScan>& scans,
                                     const UncertainMapOptions& options) {
  using Reading = Problem::Reading;
  const auto t0 = Clock::now();
  UncertainVdtMap map;
  UncertainMapOptions given = options;
  if (given.spacing <= 0.0) given.spacing = spacing_from_data(scans);
  Problem pb(map, given);
  const UncertainMapOptions& o = pb.options;
  const double h = o.spacing;
  map.summary_.spacing = h;
  const double floor_sigma = o.boundary_sigma >= 0.0 ? o.boundary_sigma : h / 40.0;
  map.approximation_sigma_ = floor_sigma;

  // Free space: where the beams pass (before the lattice, so that what they clear is not in it).
  const double beam_res = detail::raster_resolution(h);
  const BeamCounts beams = o.free_space ? count_beams(scans, beam_res) : BeamCounts{};
  const OccupancyMapperOptions log_odds;
  // A reading is cleared when the beams cross its cell more than they end around it (its cell and
  // the 8 next to it), with the occupancy grid's log-odds. Around it, because the readings of a
  // wall scatter over the cells next to its surface with their range and pose noise, and the
  // beams that end a cell further on cross them: counted in its cell alone, a wall would lose the
  // readings on the near side of its noise (on Experiment 2 a third of them, moving its fitted
  // surface back). A person who walked on, or a reflection, is crossed by the beams of the scans
  // that saw through it and ended in by few.
  const auto cleared = [&](const Eigen::Vector2d& e) {
    const Eigen::Vector2i c = beams.frame.cell_of(e);
    if (c.x() < 1 || c.y() < 1 || c.x() >= beams.size.x() - 1 || c.y() >= beams.size.y() - 1)
      return false;
    const auto at = [&](int x, int y) { return static_cast<std::size_t>(y) * beams.size.x() + x; };
    std::uint32_t ended = 0;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) ended += beams.ended[at(c.x() + dx, c.y() + dy)];
    }
    return log_odds.l_occ * ended + log_odds.l_free * beams.crossed[at(c.x(), c.y())] <= 0.0;
  };
  // The readings, at the given poses; non-finite ones are dropped, and those the beams clear.
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
      if (!beams.crossed.empty() && cleared(transform_point(scans[s].pose, pts.points[i]))) {
        ++map.summary_.cleared_readings;
        continue;
      }
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

  // Eikonal samples: the vector form away from the boundary, the Hessian form near it; those the
  // beams cross, away from the observed points, also carry the free-space residual.
  const int n = o.samples_per_axis;
  const double eik_w = 1.0 / o.eikonal_sigma;
  struct Sample {
    Eigen::Vector2i cell;
    SplinePatchBasis basis;
    bool at_boundary;
  };
  struct FreeSample {
    Eigen::Vector2i cell;
    SplinePatchBasis basis;
    double d_min;
  };
  std::vector<Sample> samples;
  std::vector<FreeSample> free_samples;
  double sr_max = 0.0;
  for (const MapScan& sc : scans) sr_max = std::max(sr_max, sc.points.sigma_range);
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
          const Sample smp{Eigen::Vector2i(i, j), spline_patch_basis(tx, ty, h), d < pb.near};
          samples.push_back(smp);
          if (beams.crossed.empty() || smp.at_boundary) continue;
          const std::int64_t k = beams.index(p);
          if (k < 0 || beams.crossed[static_cast<std::size_t>(k)] == 0) continue;
          const double d_min = d - 2.0 * sr_max - beam_res;
          if (d_min > 0.0) free_samples.push_back({smp.cell, smp.basis, d_min});
        }
      }
    }
  }
  map.summary_.eikonal_samples = static_cast<int>(samples.size());
  map.summary_.free_space_samples = static_cast<int>(free_samples.size());

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
  auto owned_problem = std::make_unique<ceres::Problem>(po);  // freed before the factorisations
  ceres::Problem& problem = *owned_problem;
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
  const double free_w = 1.0 / (o.free_sigma > 0.0 ? o.free_sigma : 0.1 * h);
  for (const auto& fs : free_samples) {
    problem.AddResidualBlock(new FreeSpaceCost(fs.basis, fs.d_min, free_w), nullptr,
                             pb.blocks(fs.cell));
  }
  pb.add_control_prior(&problem);
  const ceres::Solver::Summary summary = pb.solve(&problem, true);
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
  map.index_cells();
  map.summary_.fit_seconds = seconds_since(t0);
  if (o.compute_covariance) {
    pb.covariance(std::move(owned_problem), pose_blocks,
                  o.estimate_scan_poses ? nullptr : &pose_covariances);
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
  VDTNAV_CHECK(options.spacing > 0.0, "uncertain map: the spacing of an approximation must be > 0");
  UncertainVdtMap map;
  Problem pb(map, options);
  map.summary_.spacing = options.spacing;
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
  const ceres::Solver::Summary s = pb.solve(&problem, false);
  for (std::size_t c = 0; c < used.size(); ++c)
    map.active_[c] = static_cast<char>(map.active_[c] && used[c]);
  map.index_cells();
  map.summary_.converged = s.termination_type == ceres::CONVERGENCE;
  map.summary_.iterations = static_cast<int>(s.iterations.size());
  map.summary_.message = s.BriefReport();
  map.summary_.initial_cost = s.initial_cost;
  map.summary_.final_cost = s.final_cost;
  map.summary_.fit_seconds = seconds_since(t0);
  return map;
}

}  // namespace vdtnav::mapping
