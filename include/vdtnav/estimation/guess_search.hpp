#pragma once
/// \file
/// \brief When the initial guess is poor: how much of a scan the map explains at a pose, and a
/// search of a window around the guess for the pose that explains it best.
///
/// The optimizer's basin of convergence is set by the gate (3.3): with a heading error of 0.1 rad
/// the far beams of a real scan land more than the gate away from their walls and drop out, and
/// the near ones alone may not pull the heading back (the Intel lab log's raw odometry errs by
/// that much between scans three seconds apart). A coarse search of a window around the guess,
/// scoring each candidate by the truncated VCD  sum_i min(|d_i|^2, tau^2)  (every beam counted,
/// an unexplained one at tau^2), gives the optimizer a start inside the basin. The explained
/// fraction (beams with |d_i| below a distance) says whether the solution is trustworthy at all:
/// where the map lacks what the robot sees, keep the odometry instead of a wrong match.
///
/// While the map explains nothing (the robot in a room the map lacks), the localizer runs on
/// odometry and its error grows; the window then grows with the predicted uncertainty
/// (window_sigmas standard deviations of the propagated covariance) at the same candidate
/// spacing, so the localizer finds itself again when the map comes back into view.

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/estimation/motion_model.hpp"
#include "vdtnav/sensor/vdt_sensor_model.hpp"

namespace vdtnav {

/// \brief The window and the thresholds.
struct GuessSearchOptions {
  bool enabled = true;
  double explained_distance = 0.1;  ///< metres: a beam with |d| below this is explained
  /// Search when the solution from the guess explains less than this fraction of the beams.
  double search_below = 0.7;
  /// Accept a solution only when it explains at least this fraction; otherwise the localizer
  /// keeps its prediction (status kRefused).
  double accept_fraction = 0.4;
  /// After refused updates (the robot in a gap of the map), accept a solution only when it
  /// explains at least this fraction: partial matches on re-entry are often wrong ones.
  double reentry_fraction = 0.7;
  /// Apply the re-entry test to every update, not only after refused ones: a solution outside the
  /// 99 % region of the prediction must explain reentry_fraction. For maps whose pattern repeats
  /// (a road's straight legs, lane lines), where a partial view fits several places; and refuse
  /// a solution farther from the guess than the largest window (max_window_xy, max_window_yaw).
  bool check_every_jump = false;
  double window_xy = 0.2;    ///< metres, half-width of the window in x and y
  double window_yaw = 0.2;   ///< radians, half-width in yaw
  int steps_xy = 3;          ///< candidates per axis in x and y (odd)
  int steps_yaw = 9;         ///< candidates in yaw (odd)
  double truncation = 0.25;  ///< tau, metres
  /// Candidates are scored on every k-th beam, k chosen so that at most this many are used
  /// (0: all).
  std::size_t max_beams = 200;
  /// The window's half-widths grow to this many standard deviations of the prediction's
  /// covariance when that exceeds window_xy / window_yaw, up to max_window_xy / max_window_yaw,
  /// with the candidate spacing of the base window.
  double window_sigmas = 3.0;
  double max_window_xy = 2.0;   ///< metres
  double max_window_yaw = 1.6;  ///< radians
  /// Odometry-increment noise with which the optimization localizer propagates its uncertainty
  /// while updates are refused (the filters use their own motion noise).
  MotionNoise odometry_noise;
};

/// \return the fraction of the scan's beams whose disparity at `pose` is an inlier below
/// `distance` (0 for an empty scan).
[[nodiscard]] double explained_fraction(const VdtSensorModel& model, const ScanPoints& scan,
                                        const Pose2& pose, double distance);

/// \return the truncated VCD sum_i min(|d_i|^2, tau^2) at `pose`, beams outside the map or
/// gated counted at tau^2.
[[nodiscard]] double truncated_vcd(const VdtSensorModel& model, const ScanPoints& scan,
                                   const Pose2& pose, double tau);

/// \return the candidate of the window around `guess` (the guess included) with the lowest
/// truncated VCD (over at most options.max_beams beams). With `covariance` (of the guess), the
/// window grows to window_sigmas standard deviations (see GuessSearchOptions).
[[nodiscard]] Pose2 search_guess(const VdtSensorModel& model, const ScanPoints& scan,
                                 const Pose2& guess, const GuessSearchOptions& options,
                                 const Eigen::Matrix3d* covariance = nullptr);

}  // namespace vdtnav
