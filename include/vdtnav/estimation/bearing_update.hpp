#pragma once
/// \file
/// \brief Bearings to known landmarks as a second observation type of the 2D EKF (thesis 3.4.5:
/// the personal mobility device's framework localized on landmarks detected by YOLO; the VDT
/// boundary points augmented it).
///
/// A detector reports a bearing in the robot frame and, at most, the landmark's class, never
/// which landmark of that class it saw, and it also reports things that are not landmarks. Each
/// detection is therefore associated with the landmark of its class (any, when the class is
/// unknown) whose predicted bearing is nearest in the Mahalanobis sense, and used only when that
/// distance passes a chi-square gate (1 dof). A landmark is seen at most once per frame: when
/// several detections claim one, the nearest keeps it and the others count as rejected.
///
/// Observation of landmark l = (l_x, l_y) from the robot X = (x, y, phi) with the sensor at s in
/// the robot frame, q = l - (x, y) - R(phi) s:
///   h(X) = atan2(q_y, q_x) - phi,
///   H = dh/dX = [ q_y / |q|^2,  -q_x / |q|^2,  -1 + (q_y (R' s)_x - q_x (R' s)_y) / |q|^2 ]
/// with R' = dR/dphi (the sensor offset moves with the heading). Innovation nu = wrap(z - h(X)).
/// The accepted detections are independent: the batch update with S = H P H^T + R, K = P H^T S^-1
/// is applied in its information form, P+ = (P^-1 + sum H_i^T H_i / sigma_i^2)^-1,
/// X+ = X + P+ sum H_i^T nu_i / sigma_i^2 (one linearisation, at the prior).

#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"

namespace vdtnav {

/// \brief A landmark of the map: its position (world frame, metres) and class.
struct Landmark2 {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();
  int label = 0;  ///< the class a detector reports (lamp post, sign, ...)
};

/// \brief One detection: a bearing in the robot frame and the class the detector reports.
struct BearingDetection {
  double bearing = 0.0;  ///< radians, counter-clockwise from the robot's x axis
  double sigma = 0.02;   ///< its standard deviation, radians
  int label = -1;        ///< the reported class; -1: unknown (associated with any landmark)
};

/// \brief Options of the bearing update.
struct BearingUpdateOptions {
  /// Mahalanobis gate nu^2 / S on each detection (chi-square, 1 dof): 6.63 is its 99 % quantile.
  double gate = 6.63;
  /// The detector's position in the robot frame (metres).
  Eigen::Vector2d sensor_offset = Eigen::Vector2d::Zero();
  /// Landmarks closer than this to the sensor are not associated (the bearing is undefined there).
  double min_range = 0.3;
};

/// \brief What one bearing update did.
struct BearingUpdateResult {
  int accepted = 0;           ///< detections associated and used
  int rejected = 0;           ///< detections no landmark explains within the gate (false positives)
  std::vector<int> landmark;  ///< per detection: the associated landmark's index, or -1
};

/// \brief The predicted bearing of landmark `l` from `x` and its Jacobian H (1 x 3) in X.
double predicted_bearing(const Pose2& x, const Eigen::Vector2d& l,
                         const Eigen::Vector2d& sensor_offset, Eigen::RowVector3d* jacobian);

/// \brief Associates, gates and applies the detections to (x, p) in one batch update.
/// \throws ConfigError for a detection with sigma <= 0 or a non-positive gate.
BearingUpdateResult ekf_bearing_update(const std::vector<BearingDetection>& detections,
                                       const std::vector<Landmark2>& landmarks,
                                       const BearingUpdateOptions& options, Pose2& x,
                                       Eigen::Matrix3d& p);

}  // namespace vdtnav
