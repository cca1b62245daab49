#pragma once
/// \file
/// \brief The relation-based SLAM metric of Kümmerle et al., "On measuring the accuracy of SLAM
/// algorithms", Autonomous Robots 27(4), 2009, for 2D trajectories.
///
/// A relation (t1, t2, delta*) is a verified relative pose: the robot's pose at t2 expressed in
/// its frame at t1. For an estimated trajectory X, the relation's estimate is
/// delta = between(X(t1), X(t2)) and its error the transform e = between(delta*, delta) = delta*^-1
/// (+) delta (the paper's delta (-) delta*). The metric (the paper's (1)) averages
///   trans(e)^2 and rot(e)^2,  trans(e) = |e_xy| metres,  rot(e) = |e_yaw| radians in [0, pi],
/// and the paper's tables also give the mean and standard deviation of the absolute errors
/// |trans(e)| and |rot(e)|; both are reported. In SE(2), |e_xy| = |delta_xy - delta*_xy| (the
/// rotation R(delta*_yaw)^T preserves the norm) and e_yaw = wrap(delta_yaw - delta*_yaw), so
/// the error transform and the component difference give the same numbers.

#include <cstddef>
#include <vector>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/eval/trajectory_metrics.hpp"

namespace vdtnav::eval {

/// \brief One relation: the pose at t2 in the frame at t1. Files of the benchmark are read by
/// load_relations() (io/relations.hpp, the io component), whose vdtnav::Relation has the same
/// fields: `eval::Relation{r.t1, r.t2, r.delta}`.
struct Relation {
  double t1 = 0.0;              ///< seconds
  double t2 = 0.0;              ///< seconds
  Pose2 delta = Pose2::Zero();  ///< (x, y, yaw) of the robot at t2 in its frame at t1
};

/// \brief How the poses at the ends of a relation are taken from the estimate.
struct RelationMetricOptions {
  /// An estimate sample within this many seconds of t1 (t2) is taken as the pose at t1 (t2);
  /// the closest one wins. Takes precedence over interpolation. The benchmark's stamps are the
  /// raw log's, to the microsecond, and the raw Intel log holds scans a few milliseconds apart:
  /// on the 607 first scans of the 910-scan Intel log the corrected poses match 58 relations
  /// exactly (0.0376 m / 0.38 deg), 64 within 1 ms and 70 within 10 ms (0.0384 m / 0.66 deg),
  /// the extra ones being other scans. Hence exact, to the microsecond.
  double stamp_tolerance = 1e-6;
  /// Without a sample within stamp_tolerance, interpolate the estimate at the end (linear in x
  /// and y, shortest arc in yaw). Off: such relations are skipped (kNoStamp).
  bool interpolate = false;
  /// Interpolation across two samples further apart than this (seconds) is refused (kInGap).
  double max_gap = 1.0;
};

/// \brief What became of a relation.
enum class RelationOutcome {
  kUsed,
  kNoStamp,  ///< interpolate off and no estimate sample within stamp_tolerance of an end
  kOutside,  ///< interpolate on and an end lies before the first or after the last sample
  kInGap,    ///< interpolate on and an end lies in a gap longer than max_gap
};

/// \brief The error of one relation.
struct RelationError {
  /// The outcome; a skipped relation is counted under the reason of its first failing end (t1
  /// is tried before t2).
  RelationOutcome outcome = RelationOutcome::kUsed;
  Pose2 estimated_delta = Pose2::Zero();  ///< between(X(t1), X(t2)) (kUsed only)
  Pose2 error = Pose2::Zero();            ///< e = between(delta*, delta) (kUsed only)
  double translation = 0.0;               ///< |e_xy|, metres
  double rotation = 0.0;                  ///< |e_yaw|, radians
};

/// \brief Mean and sample standard deviation (n - 1; 0 for fewer than 2 values).
struct MeanStd {
  double mean = 0.0;
  double std = 0.0;
};

/// \brief The metric over a set of relations.
struct RelationMetricResult {
  std::size_t used = 0;
  std::size_t skipped = 0;  ///< = skipped_no_stamp + skipped_outside + skipped_in_gap
  std::size_t skipped_no_stamp = 0;
  std::size_t skipped_outside = 0;
  std::size_t skipped_in_gap = 0;
  MeanStd translation;          ///< |trans(e)|, metres
  MeanStd rotation;             ///< |rot(e)|, radians
  MeanStd translation_squared;  ///< trans(e)^2, m^2 (its mean is the paper's translational part)
  MeanStd rotation_squared;     ///< rot(e)^2, rad^2 (its mean is the paper's rotational part)
  std::vector<RelationError> errors;  ///< one per relation, in input order

  /// \return true when at least one relation was used.
  [[nodiscard]] bool ok() const noexcept { return used > 0; }
};

/// \brief Evaluates `estimate` on `relations` (Kümmerle et al. 2009).
/// \throws ConfigError for an invalid trajectory (see check_trajectory), non-finite relations or
/// invalid options (negative/NaN stamp_tolerance or max_gap).
[[nodiscard]] RelationMetricResult relation_metric(const Trajectory2& estimate,
                                                   const std::vector<Relation>& relations,
                                                   const RelationMetricOptions& options = {});

}  // namespace vdtnav::eval
