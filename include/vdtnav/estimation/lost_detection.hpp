#pragma once
/// \file
/// \brief When a tracking estimate no longer explains the data (kidnapped robot, a wrong match
/// kept): a test over a window of scans.
///
/// Per scan k, the explained fraction e_k of its readings (disparity |d_i| at the estimate below
/// explained_distance, the acceptance test of global localization), and the window's mean
/// m_k = (1/W) sum_{j=k-W+1..k} e_j. While the track holds, its baseline b and spread s are
/// the exponential mean and standard deviation of e over `baseline_scans` scans, of the scans
/// that have left the window (a fall the window is testing must not move what it is tested
/// against). The track is lost
/// when the window explains too little, absolutely or against what this track explains:
///
///     lost  <=>  m_k < lost_fraction   or   b - m_k > max(drop, sigmas * s),
///
/// the second a one-sided chi-square test with one degree of freedom, (b - m_k)^2 / s^2 >
/// sigmas^2, whose margin never falls below `drop`. The baseline makes the test fit any map and
/// sensor: on a simulated map a right pose explains nearly every reading and steadily (s ~ 0.01),
/// on a map drawn from scans of a cluttered lab 70-100 % with dips where people stand
/// (s ~ 0.1); a kidnapped tracker that slides onto a wrong place explaining 65 % is lost in the
/// first and would be a false alarm in the second. It is found again by a new acquisition
/// (reset(); recovering_localizer.hpp) or, without recovery, when the window's mean is back above
/// found_fraction. The window, not one scan, decides: one scan can see mostly what the map lacks
/// (people, an opened door) while the pose is right. A chi-square over the readings themselves
/// (sum_i d_i^2 / sigma_i^2 against N dof) is not used: on a map drawn from scans, thousands of
/// readings whose map errors are shared exceed any quantile at right poses.

#include <deque>
#include <limits>

namespace vdtnav {

struct LostDetectionOptions {
  /// W, scans in the window (>= 1).
  int window = 5;
  /// Lost when the window's mean explained fraction falls below this.
  double lost_fraction = 0.5;
  /// The smallest margin below the baseline that is lost (see the file comment).
  double drop = 0.25;
  /// The margin in standard deviations s of the track's explained fraction (3: a one-sided
  /// chi-square test at 99.9 %).
  double sigmas = 3.0;
  /// Scans over which the baseline averages (exponential mean with weight 1 / baseline_scans).
  int baseline_scans = 50;
  /// Without a new acquisition, found again when the window's mean is back above this.
  double found_fraction = 0.75;

  /// \throws ConfigError for values out of range.
  void validate() const;
};

/// \brief The window test (see the file comment). Feed it each scan's explained fraction.
class LostDetector {
 public:
  explicit LostDetector(const LostDetectionOptions& options = {});

  /// \brief Adds scan k's explained fraction (in [0, 1]). \return whether the track is lost.
  bool update(double explained);
  /// \brief A new start (a reset or a global acquisition): an empty window, not lost.
  void reset();

  [[nodiscard]] bool lost() const noexcept { return lost_; }
  /// \return the window's mean explained fraction (1 for an empty window).
  [[nodiscard]] double window_mean() const noexcept;
  /// \return the track's baseline b (NaN before the first full window).
  [[nodiscard]] double baseline() const noexcept { return baseline_; }
  /// \return the track's spread s (NaN before the first full window).
  [[nodiscard]] double spread() const noexcept;
  [[nodiscard]] const LostDetectionOptions& options() const noexcept { return options_; }

 private:
  void restart_baseline();  // b and s from the window's scans

  LostDetectionOptions options_;
  std::deque<double> window_;
  double sum_ = 0.0;
  double baseline_ = std::numeric_limits<double>::quiet_NaN();
  double variance_ = std::numeric_limits<double>::quiet_NaN();
  bool lost_ = false;
};

}  // namespace vdtnav
