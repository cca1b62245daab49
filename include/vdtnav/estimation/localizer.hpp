#pragma once
/// \file
/// \brief The interface every localizer implements, one template on the pose traits
/// (LocalizerT<2> = Localizer2D, LocalizerT<3> = Localizer3D), so that the VDT methods and the
/// baselines run side by side on the same data, and the result every localizer returns.

#include <string>

#include <Eigen/Core>

#include <limits>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/core/pose3.hpp"
#include "vdtnav/core/traits.hpp"
#include "vdtnav/sensor/laser_scan.hpp"
#include "vdtnav/sensor/odometry.hpp"

namespace vdtnav {

/// \brief Why an estimate is what it is.
enum class LocalizationStatus {
  kConverged,           ///< the estimate used the scan and converged
  kNotConverged,        ///< the solver stopped without convergence (estimate may be poor)
  kTooFewObservations,  ///< too few usable beams: prediction only / previous estimate kept
  kDiverged,            ///< the solver failed numerically; previous estimate kept
  /// The solver converged, but the map does not explain the observations there (too small a
  /// fraction explained, or a jump the acceptance test refuses): the prediction is kept.
  kRefused,
  /// The recent scans are not explained at the estimates (lost_detection.hpp): the robot is lost
  /// (kidnapped, or a wrong match kept) until a new acquisition; the pose is the tracker's.
  kLost,
  /// The map does not explain the scan where the robot is (a place the map lacks, a crowd): the
  /// pose is the scan matched against the recent scans (the local scan map across the gap), with
  /// its covariance grown from the last fix. Published by default (published_by_default()), unless
  /// the map contradicts it, which makes it refused.
  kBridged,
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
    case LocalizationStatus::kRefused:
      return "refused";
    case LocalizationStatus::kLost:
      return "lost";
    case LocalizationStatus::kBridged:
      return "bridged";
  }
  return "?";
}

/// \return whether a pose of this status goes to the default outputs (the TUM file of `vdtnav
/// localize`, the ROS node's amcl_pose and map->odom): a localization on the map (converged) or a
/// bridge across a gap of it (bridged), each with its covariance. The others are the prediction
/// or a pose the map contradicts.
[[nodiscard]] inline bool published_by_default(LocalizationStatus s) {
  return s == LocalizationStatus::kConverged || s == LocalizationStatus::kBridged;
}

/// \brief The result of one localization step (aliases LocalizationResult for 2D,
/// LocalizationResult3 for 3D).
///
/// The covariance is that of the pose perturbation of PoseTraits<Dim>: (x, y, phi) in 2D;
/// (dt, dtheta), the left perturbation in the world frame, in 3D. An estimator that holds some
/// degrees of freedom fixed (the 4-DOF mode) reports zero rows and columns for them.
template <int Dim>
struct LocalizationResultT {
  using Pose = typename PoseTraits<Dim>::Pose;
  using Covariance = typename PoseTraits<Dim>::Covariance;

  LocalizationStatus status = LocalizationStatus::kTooFewObservations;
  Pose pose = PoseTraits<Dim>::identity();
  Covariance covariance = Covariance::Zero();
  bool has_covariance = false;  ///< false for estimators that report none (C-LOG style)
  /// Solver iterations of every solve of the update, coarse levels and re-solves included.
  int iterations = 0;
  /// What the update ran besides one solve (optimizers), so that its cost can be told apart.
  struct Work {
    int solves = 0;           ///< fine-level solves (one per gate round, per start)
    int coarse_to_fine = 0;   ///< coarse-to-fine alignments (guess poorer than coarse_threshold)
    int window_searches = 0;  ///< window searches around the guess (scan poorly explained)
    int bridged = 0;          ///< scan-to-scan matches in a gap of the map
    int global_searches = 0;  ///< global localizations finished (lost: re-acquisition attempts)
    int search_boxes = 0;     ///< boxes of an anytime global search scored in this update
    int candidates = 0;       ///< re-acquisition candidates solved beside the track
  } work;
  double final_cost = 0.0;
  int inliers = 0;  ///< beams used after gating
  int dropped = 0;  ///< beams dropped: invalid readings, outside the map, gated
  /// Fraction of the observations the map explains at the pose (lost detection); < 0: not
  /// measured by this localizer.
  double explained = -1.0;
};

using LocalizationResult = LocalizationResultT<2>;
using LocalizationResult3 = LocalizationResultT<3>;

/// \brief A localizer fed with odometry and observations, one step at a time (aliases
/// Localizer2D, Localizer3D): poses, covariances and results of PoseTraits<Dim>.
template <int Dim>
class LocalizerT {
 public:
  using Pose = typename PoseTraits<Dim>::Pose;
  using Covariance = typename PoseTraits<Dim>::Covariance;
  using Odometry = typename OdometryTraits<Dim>::Step;
  using Observations = ObservationSet<Dim>;
  using Result = LocalizationResultT<Dim>;

  virtual ~LocalizerT() = default;
  /// \brief Starts (again) at `pose` with uncertainty `covariance`.
  virtual void reset(const Pose& pose, const Covariance& covariance) = 0;
  /// \brief Predicts with the odometry since the previous step, then corrects with the
  /// observations: robot-frame points with their noise (a LiDAR scan's endpoints, a camera's
  /// edge points on the ground, a 3D LiDAR's cloud, ...).
  [[nodiscard]] virtual Result update(const Odometry& odometry,
                                      const Observations& observations) = 0;
  /// \return the method's name in tables ("vdt-opt", "pf", "vdt-opt-6dof", ...).
  [[nodiscard]] virtual std::string name() const = 0;
};

/// \brief The 2D localizers: LocalizerT<2> and planar LiDAR scans.
class Localizer2D : public LocalizerT<2> {
 public:
  using LocalizerT<2>::update;
  /// \brief A LiDAR scan: update(odometry, scan_points(scan)).
  [[nodiscard]] LocalizationResult update(const OdometryStep& odometry, const LaserScan& scan) {
    return update(odometry, scan_points(scan));
  }
};

using Localizer3D = LocalizerT<3>;

}  // namespace vdtnav
