// The relation metric and the relation NEES (relation_nees.hpp): both take an estimate's poses at
// a relation's ends. (The NEES has its own header; its definitions live here, beside the end
// lookup they share, so that the eval library's source list is unchanged.)
#include "vdtnav/eval/relation_metric.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/eval/relation_nees.hpp"

namespace vdtnav::eval {
namespace {

MeanStd mean_std(const std::vector<double>& x) {
  MeanStd m;
  if (x.empty()) return m;
  double sum = 0.0;
  for (double v : x) sum += v;
  m.mean = sum / static_cast<double>(x.size());
  if (x.size() > 1) {
    double var = 0.0;
    for (double v : x) var += (v - m.mean) * (v - m.mean);
    m.std = std::sqrt(var / static_cast<double>(x.size() - 1));
  }
  return m;
}

/// The estimated pose at time t, or why there is none.
struct PoseAt {
  RelationOutcome outcome = RelationOutcome::kUsed;
  Pose2 pose = Pose2::Zero();
};

/// The index of the sample closest to t (either neighbour of the insertion point) when it lies
/// within `tolerance`, else estimate.size().
std::size_t sample_at(const Trajectory2& estimate, double t, double tolerance) {
  const auto it = std::lower_bound(estimate.begin(), estimate.end(), t,
                                   [](const StampedPose2& s, double x) { return s.t < x; });
  auto closest = it;
  if (it != estimate.begin() && (it == estimate.end() || t - (it - 1)->t < it->t - t))
    closest = it - 1;
  if (closest == estimate.end() || std::abs(closest->t - t) > tolerance) return estimate.size();
  return static_cast<std::size_t>(closest - estimate.begin());
}

PoseAt pose_at(const Trajectory2& estimate, double t, const RelationMetricOptions& options) {
  const std::size_t k = sample_at(estimate, t, options.stamp_tolerance);
  if (k < estimate.size()) return {RelationOutcome::kUsed, estimate[k].pose};
  if (!options.interpolate) return {RelationOutcome::kNoStamp, Pose2::Zero()};
  const InterpolatedPose p = detail::interpolate_unchecked(estimate, t, options.max_gap);
  switch (p.status) {
    case InterpolationStatus::kOk:
      return {RelationOutcome::kUsed, p.pose};
    case InterpolationStatus::kInGap:
      return {RelationOutcome::kInGap, Pose2::Zero()};
    default:  // empty, before the start, after the end
      return {RelationOutcome::kOutside, Pose2::Zero()};
  }
}

}  // namespace

RelationMetricResult relation_metric(const Trajectory2& estimate,
                                     const std::vector<Relation>& relations,
                                     const RelationMetricOptions& options) {
  check_trajectory(estimate, "relation_metric: estimate");
  VDTNAV_CHECK(!std::isnan(options.stamp_tolerance) && options.stamp_tolerance >= 0.0,
               "relation_metric: stamp_tolerance must be >= 0");
  VDTNAV_CHECK(!std::isnan(options.max_gap) && options.max_gap >= 0.0,
               "relation_metric: max_gap must be >= 0");
  RelationMetricResult result;
  result.errors.resize(relations.size());
  std::vector<double> trans, rot, trans2, rot2;
  for (std::size_t k = 0; k < relations.size(); ++k) {
    const Relation& r = relations[k];
    VDTNAV_CHECK(std::isfinite(r.t1) && std::isfinite(r.t2) && r.delta.allFinite(),
                 "relation_metric: relation " + std::to_string(k) + " is not finite");
    RelationError& out = result.errors[k];
    const PoseAt x1 = pose_at(estimate, r.t1, options);
    const PoseAt x2 =
        x1.outcome == RelationOutcome::kUsed ? pose_at(estimate, r.t2, options) : PoseAt{};
    out.outcome = x1.outcome != RelationOutcome::kUsed ? x1.outcome : x2.outcome;
    switch (out.outcome) {
      case RelationOutcome::kUsed:
        break;
      case RelationOutcome::kNoStamp:
        ++result.skipped_no_stamp;
        continue;
      case RelationOutcome::kOutside:
        ++result.skipped_outside;
        continue;
      case RelationOutcome::kInGap:
        ++result.skipped_in_gap;
        continue;
    }
    out.estimated_delta = between(x1.pose, x2.pose);
    out.error = between(r.delta, out.estimated_delta);  // delta*^-1 (+) delta
    out.translation = out.error.head<2>().norm();
    out.rotation = std::abs(out.error[2]);
    trans.push_back(out.translation);
    rot.push_back(out.rotation);
    trans2.push_back(out.translation * out.translation);
    rot2.push_back(out.rotation * out.rotation);
  }
  result.used = trans.size();
  result.skipped = result.skipped_no_stamp + result.skipped_outside + result.skipped_in_gap;
  result.translation = mean_std(trans);
  result.rotation = mean_std(rot);
  result.translation_squared = mean_std(trans2);
  result.rotation_squared = mean_std(rot2);
  return result;
}

// ---- Relation NEES (relation_nees.hpp) ----

RelativePoseJacobians relative_pose_jacobians(const Pose2& from, const Pose2& to) {
  RelativePoseJacobians r;
  r.delta = between(from, to);  // (1)
  const double c = std::cos(from[2]), s = std::sin(from[2]);
  // (3): d/dθ_i of R(θ_i)ᵀ (t_j − t_i) = (δ_y, −δ_x); the translation enters through ∓R(θ_i)ᵀ.
  r.d_from << -c, -s, r.delta[1], s, -c, -r.delta[0], 0.0, 0.0, -1.0;
  r.d_to << c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0;
  return r;
}

Eigen::Matrix3d relative_pose_covariance(const Pose2& from, const Pose2& to,
                                         const Eigen::Matrix3d& cov_from,
                                         const Eigen::Matrix3d& cov_to) {
  const RelativePoseJacobians j = relative_pose_jacobians(from, to);
  // (2), independent estimates.
  return j.d_from * cov_from * j.d_from.transpose() + j.d_to * cov_to * j.d_to.transpose();
}

double relation_nees(const Pose2& from, const Pose2& to, const Eigen::Matrix3d& cov_from,
                     const Eigen::Matrix3d& cov_to, const Pose2& true_delta) {
  const Eigen::Matrix3d sigma = relative_pose_covariance(from, to, cov_from, cov_to);
  // (4), (5); nees<3>() returns NaN for a non-finite or not positive definite Σ_rel.
  return nees<3>(pose_error(between(from, to), true_delta), sigma);
}

RelationNeesResult relation_nees(const Trajectory2& estimate,
                                 const std::vector<Eigen::Matrix3d>& covariances,
                                 const std::vector<Relation>& relations,
                                 const RelationNeesOptions& options) {
  check_trajectory(estimate, "relation_nees: estimate");
  VDTNAV_CHECK(covariances.size() == estimate.size(),
               "relation_nees: expected one covariance per estimate sample (" +
                   std::to_string(estimate.size()) + "), got " +
                   std::to_string(covariances.size()));
  VDTNAV_CHECK(!std::isnan(options.stamp_tolerance) && options.stamp_tolerance >= 0.0,
               "relation_nees: stamp_tolerance must be >= 0");
  VDTNAV_CHECK(!std::isnan(options.bound) && options.bound >= 0.0,
               "relation_nees: bound must be >= 0");
  RelationNeesResult result;
  result.values.assign(relations.size(), std::numeric_limits<double>::quiet_NaN());
  std::vector<double> used;
  for (std::size_t k = 0; k < relations.size(); ++k) {
    const Relation& r = relations[k];
    VDTNAV_CHECK(std::isfinite(r.t1) && std::isfinite(r.t2) && r.delta.allFinite(),
                 "relation_nees: relation " + std::to_string(k) + " is not finite");
    const std::size_t i = sample_at(estimate, r.t1, options.stamp_tolerance);
    const std::size_t j = sample_at(estimate, r.t2, options.stamp_tolerance);
    if (i == estimate.size() || j == estimate.size()) {
      ++result.skipped_no_stamp;
      continue;
    }
    if (!covariances[i].allFinite() || !covariances[j].allFinite()) {
      ++result.skipped_no_covariance;
      continue;
    }
    const double v =
        relation_nees(estimate[i].pose, estimate[j].pose, covariances[i], covariances[j], r.delta);
    if (!std::isfinite(v)) {
      ++result.skipped_singular;
      continue;
    }
    result.values[k] = v;
    used.push_back(v);
  }
  result.used = used.size();
  if (used.empty()) return result;
  const ErrorStatistics st = error_statistics(used);
  result.mean = st.mean;
  result.median = st.median;
  const auto inside =
      std::count_if(used.begin(), used.end(), [&](double v) { return v <= options.bound; });
  result.fraction_inside = static_cast<double>(inside) / static_cast<double>(used.size());
  return result;
}

}  // namespace vdtnav::eval
