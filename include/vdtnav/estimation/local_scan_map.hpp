#pragma once
/// \file
/// \brief Bridging the gaps of a map: the last few scans, at their estimated poses, as a small
/// VDT map against which the localizer matches a scan the map does not explain.
///
/// A map built from one part of a run lacks the rooms the robot visits in the others (the Intel
/// lab study maps the last third of the log and localizes the first two). While the robot is in
/// such a room the map explains too few beams and the localizer refuses its solution; dead
/// reckoning alone then drifts by several centimetres and degrees per turn. Matching the scan
/// against the recent scans instead (scan-to-local-map matching, i.e. laser odometry) keeps the
/// relative motion accurate until the map comes back into view, where the window search of
/// guess_search.hpp re-anchors the estimate.

#include <deque>
#include <optional>
#include <vector>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/sensor/vdt_sensor_model.hpp"

namespace vdtnav {

struct VdtOptimizerOptions;

/// \brief The local map's extent and when its match is trusted.
struct LocalScanMapOptions {
  bool enabled = true;
  int scans = 4;            ///< the local map holds the endpoints of this many recent scans
  double resolution = 0.1;  ///< metres per cell of the local map
  double radius = 10.0;     ///< endpoints farther than this from the guess are left out, metres
  /// A match is used when the local map explains at least this fraction of the scan's beams
  /// (|d| below the search's explained_distance).
  double accept_fraction = 0.5;
  /// A bridged step grows the localizer's uncertainty (which sizes the window search) by this
  /// fraction of the odometry's variance growth.
  double uncertainty_growth = 0.5;
};

/// \brief The recent scans' endpoints in the world frame, matched against on demand.
class LocalScanMap {
 public:
  explicit LocalScanMap(const LocalScanMapOptions& options = {}) : options_(options) {}

  /// \brief Forgets every scan (after a reset).
  void clear() { scans_.clear(); }

  /// \brief Adds a scan at its estimated pose, dropping the oldest beyond options().scans.
  void add(const ScanPoints& scan, const Pose2& pose);

  /// \brief Matches `scan` against the stored scans from `guess` with the VDT optimizer (the
  /// given options, without pyramid, window search or covariance).
  /// \return the pose, or nothing when the local map is empty, the solve fails, or the match
  /// explains less than accept_fraction of the beams within `explained_distance`.
  [[nodiscard]] std::optional<Pose2> match(const ScanPoints& scan, const Pose2& guess,
                                           const VdtOptimizerOptions& optimizer,
                                           double explained_distance) const;

  [[nodiscard]] const LocalScanMapOptions& options() const noexcept { return options_; }

 private:
  LocalScanMapOptions options_;
  std::deque<std::vector<Eigen::Vector2d>> scans_;  ///< world-frame endpoints, oldest first
};

}  // namespace vdtnav
