#pragma once
/// \file
/// \brief Never lost for good: any 2D tracking localizer (vdt-opt, vdt-ekf, ...) with lost
/// detection (lost_detection.hpp) and re-acquisition by global localization
/// (global_localization.hpp) — the kidnapped robot.
///
/// Each update runs the tracker, measures the fraction of the observations the map explains at
/// its estimate (as global localization's acceptance test does: disparity below
/// explained_distance) and feeds the window test. While the window says lost, the result's status
/// is kLost and, with `recover`, global localization runs on the lost scans (the 1st, 2nd, 4th,
/// 8th, ... then every max_attempt_gap-th: a robot in a part of the building the map lacks is
/// lost for long, and each search costs a fraction of a second to seconds). An acquisition is a
/// candidate only when it is accepted (explained, unambiguous) and explains the scan as well as
/// the track did before the loss (its baseline less lost.drop): in a gap of the map, a place that
/// merely resembles the robot's explains 75-85 % of a scan where the track explained 95 %. The
/// candidate is then confirmed on the next scan — the tracker restarted there must explain it at
/// that level too, after the robot moved — and only then is the loss over (status converged at
/// the confirmed pose). A refused acquisition (an ambiguous place) is never used: the status
/// stays kLost.
///
/// A smaller fall (check_drop below the baseline) is not called lost — real logs have such dips
/// at right poses, where people or furniture block the view — but it is checked: a branch and
/// bound capped at the tracker's own score (GlobalLocalizer::localize_better) looks for a pose
/// that explains the scan clearly better. Where the tracker is right that search prunes almost
/// everything at once; where it slid along a corridor onto a place that explains 80 % of the
/// scan, the right place explains all of it and is adopted (an accepted acquisition).

#include <memory>
#include <string>

#include "vdtnav/estimation/global_localization.hpp"
#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/estimation/lost_detection.hpp"
#include "vdtnav/sensor/vdt_sensor_model.hpp"

namespace vdtnav {

struct RecoveryOptions {
  /// Run the window test and report kLost (false: the tracker's results pass unchanged).
  bool detect = true;
  /// While lost, re-acquire by global localization (false: report kLost only, until the window
  /// explains lost.found_fraction again). With it, only an accepted acquisition ends a loss: a
  /// tracker that slid onto a twin of the right place explains its scans as well as the right
  /// place would.
  bool recover = true;
  /// A scan with fewer readings says nothing either way (one reading on a wall is 100 %
  /// explained anywhere along it): it does not enter the window.
  int min_readings = 10;
  /// While lost, global localization runs on lost scans 1, 2, 4, 8, ... and then every this many.
  int max_attempt_gap = 16;
  LostDetectionOptions lost;
  /// A window this far below the track's baseline (less than lost) asks whether another pose
  /// explains the scan clearly better (recover only; <= 0: never).
  double check_drop = 0.1;
  /// "Clearly better": a truncated score lower by this fraction of N tau^2 (N the scored
  /// readings, tau global.truncation).
  double check_margin = 0.1;

  /// \throws ConfigError for values out of range.
  void validate() const;
};

/// \brief A tracker with lost detection and recovery (see the file comment).
class RecoveringLocalizer final : public Localizer2D {
 public:
  /// \param tracker the localizer that tracks (owned).
  /// \param map, occupancy must outlive this; the occupancy is the map's grid (free cells are
  ///        where global localization places the robot).
  /// \param global global localization's options (its explained_distance is also the lost test's).
  /// \throws ConfigError for bad options or grids.
  RecoveringLocalizer(std::unique_ptr<Localizer2D> tracker, const VdtMap2& map,
                      const OccupancyGrid<2>& occupancy, const GlobalLocalizationOptions& global,
                      const RecoveryOptions& options = {});

  void reset(const Pose2& pose, const Eigen::Matrix3d& covariance) override;
  using Localizer2D::update;
  [[nodiscard]] LocalizationResult update(const OdometryStep& odometry,
                                          const ScanPoints& observations) override;
  [[nodiscard]] std::string name() const override { return tracker_->name(); }

  /// \return acquisitions that ended a loss (confirmed) or corrected a slide (check_drop).
  [[nodiscard]] int recoveries() const noexcept { return recoveries_; }
  [[nodiscard]] const LostDetector& detector() const noexcept { return detector_; }
  /// \return the last global localization run (lost: the acquisition attempt), e.g. to tell an
  /// ambiguous place (result.ambiguous) from an unexplained scan.
  [[nodiscard]] const GlobalLocalizationResult& last_acquisition() const noexcept {
    return last_acquisition_;
  }

 private:
  /// Restarts the tracker at the acquisition last_acquisition_ and ends the loss; its result.
  [[nodiscard]] LocalizationResult adopt(const LocalizationResult& tracked);
  /// The level an acquisition must explain: the track's baseline less lost.drop (at least
  /// global's accept_fraction).
  [[nodiscard]] double acceptable(double baseline) const;
  /// A loss begins: the schedule of attempts restarts.
  void begin_loss();

  std::unique_ptr<Localizer2D> tracker_;
  VdtSensorModel model_;  // the explained fraction at the tracker's estimate
  GlobalLocalizer global_;
  RecoveryOptions options_;
  LostDetector detector_;
  bool lost_ = false;
  int since_check_ = 0;                    // scans since the last check (one per window)
  int lost_scans_ = 0, next_attempt_ = 0;  // the attempts' schedule
  double before_loss_ = 0.0;  // the baseline before the loss: what a candidate must explain
  bool candidate_ = false;    // an acquisition waiting for its confirmation
  int recoveries_ = 0;
  GlobalLocalizationResult last_acquisition_;
};

}  // namespace vdtnav
