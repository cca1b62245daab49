#pragma once
// The kidnapped robot: a localizer tracks a recorded drive whose robot is teleported every
// `every` scans — the drive is cut into segments of consecutive scans taken from random places of
// the recording, so after each cut the scans come from elsewhere while the odometry reports an
// ordinary step. The localizer is never told.
#include <cstdint>
#include <vector>

#include "vdtnav/estimation/localizer.hpp"

namespace kidnap {

/// A recorded drive: per scan, the observations, the odometry into it and the true pose.
struct Drive {
  std::vector<vdtnav::ScanPoints> scans;
  std::vector<vdtnav::OdometryStep> odometry;  // odometry[k]: from scan k-1 to k
  std::vector<vdtnav::Pose2> truth;
};

struct Options {
  int kidnappings = 20;
  int every = 200;        // scans between teleports
  int within = 20;        // the target: recovered within this many scans
  int window = 5;         // the lost test's window: scans before it cannot count as wrong accepted
  double min_jump = 2.0;  // metres: a teleport lands at least this far away
  std::uint32_t seed = 1;
};

/// What happened after one kidnapping (scans counted from the first scan after the teleport).
struct Outcome {
  /// First scan converged and right (within 0.3 m and 0.1 rad, the global localization
  /// target) after which no converged estimate of the segment is elsewhere; -1: never.
  int scans_to_recover = -1;
  /// A converged estimate elsewhere (a different place: more than 1 m or 0.5 rad from the
  /// truth, global localization's distinct poses) `window` or more scans after the teleport (the
  /// lost test can know by then): a wrong pose accepted.
  bool wrong_accepted = false;
  int converged_wrong_early = 0;  // converged and elsewhere within the window (before any test)
  /// Converged scans after the recovery off by more than 0.3 m or 0.1 rad but not elsewhere:
  /// tracking error, not a kidnapping.
  int converged_off = 0;
  int lost_scans = 0;  // status lost
  /// Carried where it cannot be recognized: within `within` scans, every acquisition was refused
  /// as ambiguous with the truth among the candidates (a place that looks like another), or the
  /// scans had too few readings to say anything (< 10), and at least one such scan.
  bool unrecognizable = false;
  int global_searches = 0;  // global localizations run
};

/// Per scan of the run (for the figure): position error, status.
struct Trace {
  std::vector<double> error;
  std::vector<vdtnav::LocalizationStatus> status;
  std::vector<int> teleports;  // scan indices of the teleports
  std::vector<double> ms;      // each update's wall time, milliseconds
};

/// Runs `localizer` (reset at the first segment's true pose) through `options.kidnappings`
/// teleports. \throws vdtnav::ConfigError when the drive is shorter than `every` scans.
[[nodiscard]] std::vector<Outcome> run(const Drive& drive, vdtnav::Localizer2D& localizer,
                                       const Options& options, Trace* trace = nullptr);

[[nodiscard]] bool right(const vdtnav::Pose2& estimate, const vdtnav::Pose2& truth);
/// More than 1 m or 0.5 rad off: a different place.
[[nodiscard]] bool elsewhere(const vdtnav::Pose2& estimate, const vdtnav::Pose2& truth);

}  // namespace kidnap
