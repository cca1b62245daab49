#pragma once
/// \file
/// \brief Accuracy of an estimated 2D trajectory against a reference: association by timestamp,
/// interpolation, the absolute trajectory error (ATE) and the relative pose error (RPE) of
/// Sturm et al., "A benchmark for the evaluation of RGB-D SLAM systems", IROS 2012, on SE(2).

#include <cstddef>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"

namespace vdtnav::eval {

/// \brief A pose with the time it holds at.
struct StampedPose2 {
  double t = 0.0;              ///< seconds
  Pose2 pose = Pose2::Zero();  ///< (x, y, yaw)
};

/// \brief A trajectory: stamps strictly increasing, every value finite (checked at the entry of
/// every function here, which throws ConfigError otherwise).
using Trajectory2 = std::vector<StampedPose2>;

/// \brief Throws ConfigError (naming `what` and the sample) unless the stamps of `trajectory`
/// increase strictly and every stamp and pose is finite.
void check_trajectory(const Trajectory2& trajectory, const char* what);

/// \brief Summary of a list of non-negative errors.
struct ErrorStatistics {
  std::size_t count = 0;
  double rmse = 0.0;    ///< sqrt(mean of squares)
  double mean = 0.0;    ///< arithmetic mean
  double median = 0.0;  ///< middle value (mean of the two middle ones for an even count)
  double p99 = 0.0;     ///< 99th percentile by nearest rank: the ceil(0.99 n)-th smallest value
  double std = 0.0;     ///< sample standard deviation (n - 1); 0 when count < 2
  double min = 0.0;
  double max = 0.0;
};

/// \brief The statistics of `errors` (all zero when empty).
[[nodiscard]] ErrorStatistics error_statistics(std::vector<double> errors);

/// \brief Status of a trajectory metric.
enum class MetricStatus {
  kOk,
  kNoMatches,            ///< no estimate stamp was associated (ATE) / no pair at the delta (RPE)
  kDegenerateAlignment,  ///< ATE: the matched positions do not fix a rotation (< 2 distinct)
};

/// \brief A pair of samples associated by time: estimate[estimate], reference[reference].
struct TimeAssociation {
  std::size_t estimate = 0;
  std::size_t reference = 0;
};

/// \brief Associates estimate and reference samples one to one by timestamp (like the TUM
/// benchmark's associate.py): all pairs with |t_est - t_ref| <= max_time_difference are
/// candidates; the closest pairs are taken first, each sample at most once.
/// \return the pairs, ordered by estimate index.
/// \throws ConfigError for invalid trajectories or a negative/NaN max_time_difference.
[[nodiscard]] std::vector<TimeAssociation> associate(const Trajectory2& estimate,
                                                     const Trajectory2& reference,
                                                     double max_time_difference);

/// \brief Outcome of interpolate().
enum class InterpolationStatus {
  kOk,
  kEmpty,        ///< the trajectory has no sample
  kBeforeStart,  ///< t < first stamp
  kAfterEnd,     ///< t > last stamp
  kInGap,        ///< t lies strictly between two samples further apart than max_gap
};

/// \brief A pose read off a trajectory at a time.
struct InterpolatedPose {
  InterpolationStatus status = InterpolationStatus::kEmpty;
  /// kOk and kInGap: the interpolated pose; kBeforeStart/kAfterEnd: the first/last pose;
  /// kEmpty: zero.
  Pose2 pose = Pose2::Zero();
  double gap = 0.0;  ///< time between the two bracketing samples (0 on an exact stamp)

  [[nodiscard]] bool ok() const noexcept { return status == InterpolationStatus::kOk; }
};

/// \brief The pose of `trajectory` at time t: linear in x and y, along the shortest arc in yaw,
/// between the samples at t_a <= t <= t_b. A t equal to a stamp returns that sample exactly
/// (whatever the gaps around it); otherwise t_b - t_a > max_gap gives kInGap.
/// \throws ConfigError for an invalid trajectory, a non-finite t or a NaN/negative max_gap.
[[nodiscard]] InterpolatedPose interpolate(
    const Trajectory2& trajectory, double t,
    double max_gap = std::numeric_limits<double>::infinity());

namespace detail {
/// interpolate() without its input checks, for callers that checked the trajectory once.
[[nodiscard]] InterpolatedPose interpolate_unchecked(const Trajectory2& trajectory, double t,
                                                     double max_gap);
}  // namespace detail

/// \brief Options of absolute_trajectory_error().
struct AteOptions {
  double max_time_difference = 0.01;  ///< seconds, for associate()
};

/// \brief The absolute trajectory error: translation (and yaw) error of each associated pair,
/// with the estimate unaligned and rigidly aligned to the reference.
struct AteResult {
  MetricStatus status = MetricStatus::kNoMatches;
  std::vector<TimeAssociation> matches;  ///< the pairs the errors are over
  /// T in SE(2) minimising sum |p_ref - T p_est|^2 (rigid Umeyama on the matched positions):
  /// the aligned estimate is compose(alignment, estimate pose).
  Pose2 alignment = Pose2::Zero();
  ErrorStatistics translation;            ///< |p_ref - T p_est|, metres (aligned)
  ErrorStatistics rotation;               ///< |wrap(yaw_ref - yaw(T) - yaw_est)|, radians
  ErrorStatistics unaligned_translation;  ///< |p_ref - p_est|, metres
  ErrorStatistics unaligned_rotation;     ///< |wrap(yaw_ref - yaw_est)|, radians

  [[nodiscard]] bool ok() const noexcept { return status == MetricStatus::kOk; }
};

/// \brief ATE of `estimate` against `reference` (Sturm et al. 2012, (7)-(8)): the estimate is
/// associated by time, aligned by the rigid SE(2) transform of Umeyama (no scale) and the
/// translational residuals summarised. The unaligned statistics are always filled when any pair
/// matched; the aligned ones only when the status is kOk.
/// \throws ConfigError for invalid trajectories or options.
[[nodiscard]] AteResult absolute_trajectory_error(const Trajectory2& estimate,
                                                  const Trajectory2& reference,
                                                  const AteOptions& options = {});

/// \brief What RpeOptions::delta counts.
enum class RpeDelta {
  kFrames,   ///< pairs (i, i + delta) of the associated sequence
  kSeconds,  ///< pairs (i, j), j > i the associated sample with t_j closest to t_i + delta
};

/// \brief Options of relative_pose_error().
struct RpeOptions {
  RpeDelta unit = RpeDelta::kFrames;
  double delta = 1.0;  ///< frames (an integer >= 1) or seconds (> 0)
  /// kSeconds: a pair is used only if |t_j - t_i - delta| <= delta_tolerance * delta, so that
  /// pairs spanning a gap in the data, or cut short by the end, are left out.
  double delta_tolerance = 0.1;
  double max_time_difference = 0.01;  ///< seconds, for associate()
};

/// \brief The relative pose error over a fixed delta.
struct RpeResult {
  MetricStatus status = MetricStatus::kNoMatches;
  std::size_t pairs = 0;        ///< number of (i, j) pairs the errors are over
  ErrorStatistics translation;  ///< |trans(E_ij)|, metres
  ErrorStatistics rotation;     ///< |angle(E_ij)|, radians

  [[nodiscard]] bool ok() const noexcept { return status == MetricStatus::kOk; }
};

/// \brief RPE of `estimate` against `reference` (Sturm et al. 2012, (5)):
///   E_ij = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j) = between(between(Q_i, Q_j), between(P_i, P_j))
/// for reference Q and estimate P over the associated samples, with (i, j) chosen by
/// RpeOptions; the stamps are the reference's. Alignment-free. Both RMSE and mean are in the
/// statistics.
/// \throws ConfigError for invalid trajectories or options.
[[nodiscard]] RpeResult relative_pose_error(const Trajectory2& estimate,
                                            const Trajectory2& reference,
                                            const RpeOptions& options = {});

}  // namespace vdtnav::eval
