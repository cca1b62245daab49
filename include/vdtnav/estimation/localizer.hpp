#pragma once
/// \file
/// \brief The interface every 2D localizer implements, so that the VDT methods and the baselines
/// run side by side on the same data.

#include <string>

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/sensor/laser_scan.hpp"

namespace vdtnav {

/// \brief What odometry reports between two scans.
struct OdometryStep {
  double dt = 0.0;              ///< seconds since the previous scan
  double v = 0.0;               ///< measured linear velocity, m/s (velocity model)
  double w = 0.0;               ///< measured angular velocity, rad/s
  Pose2 delta = Pose2::Zero();  ///< measured increment in the previous robot frame
};

/// \brief Why an estimate is what it is.
enum class LocalizationStatus {
  kConverged,           ///< the estimate used the scan and converged
  kNotConverged,        ///< the solver stopped without convergence (estimate may be poor)
  kTooFewObservations,  ///< too few usable beams: prediction only / previous estimate kept
  kDiverged,            ///< the solver failed numerically; previous estimate kept
};

/// \return a short name for a status ("converged", ...).
[[nodiscard]] inline const char* to_string(LocalizationStatus s) {
  switch (s) {
    case LocalizationStatus::kConverged:
      return "converged";
    case LocalizationStatus::kNotConverged:
      return "not converged";
    case LocalizationStatus::kTooFewObservations:
      return "too few observations";
    case LocalizationStatus::kDiverged:
      return "diverged";
  }
  return "?";
}

/// \brief The result of one localization step.
struct LocalizationResult {
  LocalizationStatus status = LocalizationStatus::kTooFewObservations;
  Pose2 pose = Pose2::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  bool has_covariance = false;  ///< false for estimators that report none (C-LOG style)
  int iterations = 0;
  double final_cost = 0.0;
  int inliers = 0;  ///< beams used after gating
  int dropped = 0;  ///< beams dropped: invalid readings, outside the map, gated
};

/// \brief A 2D localizer fed with odometry and scans, one step at a time.
class Localizer2D {
 public:
  virtual ~Localizer2D() = default;
  /// \brief Starts (again) at `pose` with uncertainty `covariance`.
  virtual void reset(const Pose2& pose, const Eigen::Matrix3d& covariance) = 0;
  /// \brief Predicts with the odometry since the previous step, then corrects with the scan.
  [[nodiscard]] virtual LocalizationResult update(const OdometryStep& odometry,
                                                  const LaserScan& scan) = 0;
  /// \return the method's name in tables ("vdt-opt", "pf", ...).
  [[nodiscard]] virtual std::string name() const = 0;
};

}  // namespace vdtnav
