#pragma once
/// \file
/// \brief When a tracking estimate is wrong (kidnapped robot, a wrong match kept): a test over a
/// window of scans of what the map *contradicts* at the estimates, not of what it fails to explain.
///
/// Per scan, the readings the map explains (E), contradicts (C) and cannot judge
/// (scan_agreement.hpp); over the last W scans their sums, and the window's contradiction c = sum C
/// / sum (E + C). The window decides only when the map judges at least `min_judged` of its
/// readings; otherwise (the robot where the map lacks the place, readings into unknown space) it is
/// undecided and the state is kept — the tracker's own status then says refused and its prediction
/// is kept:
///
///     lost        <=>  c >= lost_contradiction              (from a decided window)
///     found again <=>  c <= found_contradiction             (from a decided window whose every
///                                                          scan the map judges: min_judged each)
///     in doubt    <=>  not lost and (c >= doubt_contradiction  or  c_scan >=
///     scan_doubt_contradiction
///                      or  c - b > max(doubt_rise, sigmas
///     s))
///
/// with b and s the exponential mean and standard deviation (over `baseline_scans`) of the
/// track's own decided windows, each joining W scans after it was tested, so that a rise the
/// window is testing never moves what it is tested against. The relative test fits the doubt to
/// the map: on an exact floor plan a right pose is contradicted by almost nothing, and a slide onto
/// a place that looks alike (a quarter contradicted) is a rise far beyond its spread; on a map
/// drawn from scans the spread is larger and the absolute level decides.
///
/// Why contradiction: a map drawn from one part of a run lacks the rooms of the others, where a
/// right pose explains as little as a quarter of a scan, so a test of the explained fraction cries
/// wolf there (the Intel study: 156 false alarms of 607 scans); but such readings end in unknown
/// space and contradict nothing. A wrong pose puts beams through walls and ends them in known free
/// space. Measured on the real logs in ../shared (scan_agreement.hpp): right poses' windows at most
/// 0.22-0.39, 99 % below 0.29; scans at other scans' poses 0.65 or more in 99 % of windows. The
/// lost level 0.5 lies between; doubt at 0.3, the top of what right poses reach, asks recovery to
/// look for a clearly better pose (recovering_localizer.hpp) without calling the robot lost.

#include <deque>
#include <limits>

#include "vdtnav/estimation/scan_agreement.hpp"

namespace vdtnav {

struct LostDetectionOptions {
  /// W, scans in the window (>= 1).
  int window = 5;
  /// Lost when the window's contradiction reaches this.
  double lost_contradiction = 0.5;
  /// Found again (after lost) when it falls to this.
  double found_contradiction = 0.3;
  /// In doubt (not lost) from this.
  double doubt_contradiction = 0.3;
  /// Also in doubt when the window's contradiction rises this much above the track's baseline...
  double doubt_rise = 0.15;
  /// ... or this many standard deviations of the track's windows, if more.
  double sigmas = 3.0;
  /// Also in doubt (from a decided window) when the scan alone is contradicted this much: a jump
  /// of the track onto a wrong pose shows in its first scan before the window's sum can rise
  /// (1: never, the 2D default, where a right scan's people and doors reach it).
  double scan_doubt_contradiction = 1.0;
  /// Windows over which the baseline averages (exponential mean, weight 1 / baseline_scans).
  int baseline_scans = 50;
  /// The window decides only when the map judges (explains or contradicts) at least this share of
  /// its readings.
  double min_judged = 0.2;

  /// \throws ConfigError for values out of range.
  void validate() const;
};

/// \brief The window test (see the file comment). Feed it each scan's agreement.
class LostDetector {
 public:
  explicit LostDetector(const LostDetectionOptions& options = {});

  /// \brief Adds a scan's agreement at the estimate. \return whether the track is lost.
  bool update(const ScanAgreement& scan);
  /// \brief A new start (a reset or a global acquisition): an empty window, not lost.
  void reset();

  [[nodiscard]] bool lost() const noexcept { return lost_; }
  /// \return whether the last window was decided and contradicted by doubt_contradiction or more
  /// without being lost.
  [[nodiscard]] bool in_doubt() const noexcept { return doubt_; }
  /// \return whether the last window was full and judged enough to decide.
  [[nodiscard]] bool decided() const noexcept { return decided_; }
  /// \return for how many updates in a row a full window was undecided (the map judging too
  /// little of it).
  [[nodiscard]] int unjudged() const noexcept { return unjudged_; }
  /// \return the window's contradiction c (0 for an empty window).
  [[nodiscard]] double contradiction() const noexcept { return sum_.contradiction(); }
  /// \return the window's summed agreement.
  [[nodiscard]] const ScanAgreement& window_sum() const noexcept { return sum_; }
  /// \return the track's baseline b and spread s of window contradictions (NaN before a window
  /// has joined).
  [[nodiscard]] double baseline() const noexcept { return baseline_; }
  [[nodiscard]] double spread() const noexcept;
  [[nodiscard]] const LostDetectionOptions& options() const noexcept { return options_; }

 private:
  LostDetectionOptions options_;
  std::deque<ScanAgreement> window_;
  ScanAgreement sum_;
  std::deque<double> tested_;  // the last W decided windows' contradictions, waiting to join b
  double baseline_ = std::numeric_limits<double>::quiet_NaN();
  double variance_ = std::numeric_limits<double>::quiet_NaN();
  bool lost_ = false, doubt_ = false, decided_ = false;
  int unjudged_ = 0;
};

}  // namespace vdtnav
