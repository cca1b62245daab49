#include "vdtnav/eval/trajectory_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <utility>

#include "vdtnav/core/error.hpp"
#include "vdtnav/eval/umeyama.hpp"

namespace vdtnav::eval {
namespace {

void check_non_negative(double x, const char* what) {
  VDTNAV_CHECK(!std::isnan(x) && x >= 0.0, std::string(what) + " must be >= 0");
}

}  // namespace

void check_trajectory(const Trajectory2& trajectory, const char* what) {
  for (std::size_t k = 0; k < trajectory.size(); ++k) {
    const StampedPose2& s = trajectory[k];
    VDTNAV_CHECK(std::isfinite(s.t) && s.pose.allFinite(),
                 std::string(what) + ": sample " + std::to_string(k) + " is not finite");
    VDTNAV_CHECK(
        k == 0 || s.t > trajectory[k - 1].t,
        std::string(what) + ": stamps must increase strictly (sample " + std::to_string(k) + ")");
  }
}

ErrorStatistics error_statistics(std::vector<double> errors) {
  ErrorStatistics s;
  s.count = errors.size();
  if (errors.empty()) return s;
  std::sort(errors.begin(), errors.end());
  const double n = static_cast<double>(errors.size());
  double sum = 0.0, sum_sq = 0.0;
  for (double e : errors) {
    sum += e;
    sum_sq += e * e;
  }
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  const std::size_t mid = errors.size() / 2;
  s.median = errors.size() % 2 == 1 ? errors[mid] : 0.5 * (errors[mid - 1] + errors[mid]);
  // Nearest rank: the smallest value with at least 99 % of the values at or below it.
  const auto rank = static_cast<std::size_t>(std::ceil(0.99 * n));
  s.p99 = errors[std::max<std::size_t>(rank, 1) - 1];
  s.min = errors.front();
  s.max = errors.back();
  if (errors.size() > 1) {
    double var = 0.0;
    for (double e : errors) var += (e - s.mean) * (e - s.mean);
    s.std = std::sqrt(var / (n - 1.0));
  }
  return s;
}

std::vector<TimeAssociation> associate(const Trajectory2& estimate, const Trajectory2& reference,
                                       double max_time_difference) {
  check_trajectory(estimate, "associate: estimate");
  check_trajectory(reference, "associate: reference");
  check_non_negative(max_time_difference, "associate: max_time_difference");
  // Candidate pairs within the window; both lists are sorted, so each estimate stamp only
  // looks at the references in [t - max, t + max].
  std::vector<std::tuple<double, std::size_t, std::size_t>> candidates;
  const auto by_time = [](const StampedPose2& s, double t) { return s.t < t; };
  for (std::size_t i = 0; i < estimate.size(); ++i) {
    const double t = estimate[i].t;
    auto it =
        std::lower_bound(reference.begin(), reference.end(), t - max_time_difference, by_time);
    for (; it != reference.end() && it->t <= t + max_time_difference; ++it)
      candidates.emplace_back(std::abs(it->t - t), i,
                              static_cast<std::size_t>(it - reference.begin()));
  }
  // Closest first (ties by estimate, then reference index: deterministic), each sample once.
  std::sort(candidates.begin(), candidates.end());
  std::vector<char> used_estimate(estimate.size(), 0), used_reference(reference.size(), 0);
  std::vector<TimeAssociation> matches;
  for (const auto& [dt, i, j] : candidates) {
    if (used_estimate[i] || used_reference[j]) continue;
    used_estimate[i] = used_reference[j] = 1;
    matches.push_back({i, j});
  }
  std::sort(matches.begin(), matches.end(), [](const TimeAssociation& a, const TimeAssociation& b) {
    return a.estimate < b.estimate;
  });
  return matches;
}

InterpolatedPose interpolate(const Trajectory2& trajectory, double t, double max_gap) {
  check_trajectory(trajectory, "interpolate");
  VDTNAV_CHECK(std::isfinite(t), "interpolate: the time must be finite");
  check_non_negative(max_gap, "interpolate: max_gap");
  return detail::interpolate_unchecked(trajectory, t, max_gap);
}

InterpolatedPose detail::interpolate_unchecked(const Trajectory2& trajectory, double t,
                                               double max_gap) {
  InterpolatedPose out;
  if (trajectory.empty()) return out;
  if (t < trajectory.front().t) {
    out.status = InterpolationStatus::kBeforeStart;
    out.pose = trajectory.front().pose;
    return out;
  }
  if (t > trajectory.back().t) {
    out.status = InterpolationStatus::kAfterEnd;
    out.pose = trajectory.back().pose;
    return out;
  }
  // b: first sample with stamp > t (exists unless t is the last stamp); a = b - 1 has t_a <= t.
  const auto b = std::upper_bound(trajectory.begin(), trajectory.end(), t,
                                  [](double x, const StampedPose2& s) { return x < s.t; });
  const StampedPose2& sa = *(b - 1);
  out.status = InterpolationStatus::kOk;
  if (sa.t == t) {
    out.pose = sa.pose;
    return out;
  }
  const StampedPose2& sb = *b;
  out.gap = sb.t - sa.t;
  if (out.gap > max_gap) out.status = InterpolationStatus::kInGap;
  const double s = (t - sa.t) / out.gap;
  out.pose.head<2>() = (1.0 - s) * sa.pose.head<2>() + s * sb.pose.head<2>();
  out.pose[2] = wrap_angle(sa.pose[2] + s * wrap_angle(sb.pose[2] - sa.pose[2]));  // shortest arc
  return out;
}

AteResult absolute_trajectory_error(const Trajectory2& estimate, const Trajectory2& reference,
                                    const AteOptions& options) {
  AteResult result;
  result.matches = associate(estimate, reference, options.max_time_difference);
  const std::size_t n = result.matches.size();
  if (n == 0) return result;

  std::vector<double> trans(n), rot(n);
  Eigen::Matrix2Xd p_est(2, static_cast<Eigen::Index>(n)), p_ref(2, static_cast<Eigen::Index>(n));
  for (std::size_t k = 0; k < n; ++k) {
    const Pose2& e = estimate[result.matches[k].estimate].pose;
    const Pose2& r = reference[result.matches[k].reference].pose;
    const Eigen::Vector3d d = pose_error(r, e);
    trans[k] = d.head<2>().norm();
    rot[k] = std::abs(d[2]);
    p_est.col(static_cast<Eigen::Index>(k)) = e.head<2>();
    p_ref.col(static_cast<Eigen::Index>(k)) = r.head<2>();
  }
  result.unaligned_translation = error_statistics(trans);
  result.unaligned_rotation = error_statistics(rot);

  // Sturm et al. (8): the rigid transform S minimising sum |Q_i - S P_i|^2 (Umeyama, s = 1).
  const Similarity<2> s = umeyama<2>(p_est, p_ref, false);
  if (!s.ok()) {
    result.status = MetricStatus::kDegenerateAlignment;
    return result;
  }
  result.alignment =
      Pose2(s.translation.x(), s.translation.y(), std::atan2(s.rotation(1, 0), s.rotation(0, 0)));
  for (std::size_t k = 0; k < n; ++k) {
    const Pose2 aligned = compose(result.alignment, estimate[result.matches[k].estimate].pose);
    const Eigen::Vector3d d = pose_error(reference[result.matches[k].reference].pose, aligned);
    trans[k] = d.head<2>().norm();
    rot[k] = std::abs(d[2]);
  }
  result.translation = error_statistics(trans);
  result.rotation = error_statistics(rot);
  result.status = MetricStatus::kOk;
  return result;
}

RpeResult relative_pose_error(const Trajectory2& estimate, const Trajectory2& reference,
                              const RpeOptions& options) {
  VDTNAV_CHECK(std::isfinite(options.delta) && options.delta > 0.0,
               "relative_pose_error: delta must be finite and > 0");
  VDTNAV_CHECK(options.unit == RpeDelta::kSeconds ||
                   (options.delta >= 1.0 && options.delta == std::floor(options.delta) &&
                    options.delta < 2147483647.0),
               "relative_pose_error: a delta in frames must be an integer >= 1");
  check_non_negative(options.delta_tolerance, "relative_pose_error: delta_tolerance");
  VDTNAV_CHECK(std::isfinite(options.delta_tolerance),
               "relative_pose_error: delta_tolerance must be finite");
  std::vector<TimeAssociation> matches =
      associate(estimate, reference, options.max_time_difference);
  // In reference time order (the time delta is measured on the reference's stamps).
  std::sort(matches.begin(), matches.end(), [](const TimeAssociation& a, const TimeAssociation& b) {
    return a.reference < b.reference;
  });
  const std::size_t n = matches.size();
  std::vector<double> times(n);
  for (std::size_t k = 0; k < n; ++k) times[k] = reference[matches[k].reference].t;

  std::vector<double> trans, rot;
  auto add_pair = [&](std::size_t i, std::size_t j) {
    const Pose2 dq =
        between(reference[matches[i].reference].pose, reference[matches[j].reference].pose);
    const Pose2 dp =
        between(estimate[matches[i].estimate].pose, estimate[matches[j].estimate].pose);
    const Pose2 e = between(dq, dp);  // (Q_i^-1 Q_j)^-1 (P_i^-1 P_j), Sturm et al. (5)
    trans.push_back(e.head<2>().norm());
    rot.push_back(std::abs(e[2]));
  };
  if (options.unit == RpeDelta::kFrames) {
    const auto step = static_cast<std::size_t>(options.delta);
    for (std::size_t i = 0; i + step < n; ++i) add_pair(i, i + step);
  } else {
    const double tolerance = options.delta_tolerance * options.delta;
    for (std::size_t i = 0; i + 1 < n; ++i) {
      const double target = times[i] + options.delta;
      if (target - tolerance > times.back()) break;  // later i have no partner either
      // The closest of the two samples around the target, after i (like the TUM benchmark's
      // find_closest_index: robust to stamps that are not exact multiples of delta).
      const auto first = times.begin() + static_cast<std::ptrdiff_t>(i) + 1;
      auto it = std::lower_bound(first, times.end(), target);
      if (it == times.end() || (it != first && target - *(it - 1) < *it - target)) --it;
      if (std::abs(*it - target) > tolerance) continue;
      add_pair(i, static_cast<std::size_t>(it - times.begin()));
    }
  }
  RpeResult result;
  result.pairs = trans.size();
  if (result.pairs == 0) return result;
  result.translation = error_statistics(std::move(trans));
  result.rotation = error_statistics(std::move(rot));
  result.status = MetricStatus::kOk;
  return result;
}

}  // namespace vdtnav::eval
