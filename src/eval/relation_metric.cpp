#include "vdtnav/eval/relation_metric.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"

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

PoseAt pose_at(const Trajectory2& estimate, double t, const RelationMetricOptions& options) {
  // The closest sample (either neighbour of the insertion point) within the stamp tolerance.
  const auto it = std::lower_bound(estimate.begin(), estimate.end(), t,
                                   [](const StampedPose2& s, double x) { return s.t < x; });
  const StampedPose2* closest = nullptr;
  if (it != estimate.end()) closest = &*it;
  if (it != estimate.begin() && (closest == nullptr || t - (it - 1)->t < closest->t - t))
    closest = &*(it - 1);
  if (closest != nullptr && std::abs(closest->t - t) <= options.stamp_tolerance)
    return {RelationOutcome::kUsed, closest->pose};
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

}  // namespace vdtnav::eval
