// The least-squares fits of an uncertain VDT map: to scans through the Eikonal and boundary
// residuals (thesis ch. 5, the weighted problem (5.15)) and to a known VDT (Fig. 5.2).
#include "uncertain_map_problem.hpp"

#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>

#include <ceres/ceres.h>
#include <ceres/normal_prior.h>
#include <Eigen/Eigenvalues>

#include "vdtnav/core/error.hpp"

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

}  // namespace vdtnav::mapping
