#pragma once
/// \file
/// \brief EKF localization on a VDT map (thesis 3.3, corrected per SPEC).
///
/// Prediction: the velocity motion model (3.7)-(3.10), or an odometry-increment model whose noise
/// grows with the motion (for logs). Update: every gated beam contributes the observation
/// h_i(X) = d_i(X) with expected value 0, so the innovation is nu_i = -d_i(X_pred) (SPEC's (3.12)),
/// Jacobian H_i = dd_i/dX (3.15)-(3.18) and noise R_i = the disparity covariance (rank-one range
/// block + map-noise floor, or the thesis's diagonal). The beams are independent, so the batch
/// update with S = H P H^T + R (3.13) and K = P H^T S^-1 (3.19, transpose restored) equals the
/// information form
///   P+ = (P^-1 + sum_i H_i^T R_i^-1 H_i)^-1,   X+ = X + P+ sum_i H_i^T R_i^-1 nu_i
/// which costs O(n) for n beams instead of inverting a 2n x 2n matrix. Errors shared by every
/// point of a set (a camera's attitude) are considered, not estimated (a Schmidt update): P+ gains
/// S cov(theta) S^T, S = P+ sum_i H_i^T R_i^-1 d_point_i G_i (see vdt_ekf.cpp). Map errors shared
/// per square of the map (VdtSensorModelOptions::map_correlation_length) are reported on top of
/// the filter's covariance as the update's sensitivity to them (reported_covariance()), or, with
/// VdtEkfOptions::schmidt_map_errors, carried from scan to scan in a Schmidt-Kalman filter.

#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "vdtnav/estimation/bearing_update.hpp"
#include "vdtnav/estimation/guess_search.hpp"
#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/estimation/motion_model.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/sensor/vdt_sensor_model.hpp"

namespace vdtnav {

/// \brief Options of the VDT EKF.
struct VdtEkfOptions {
  VdtSensorModelOptions sensor;
  MotionModelKind motion = MotionModelKind::kVelocity;
  MotionNoise noise;
  int min_inliers = 10;  ///< fewer usable beams: prediction only, kTooFewObservations
  /// Gauss-Newton iterations of the update on the MAP cost (iterated EKF); 1 is the classic EKF,
  /// linearised once at the prediction. Later iterations relinearise at the current iterate and
  /// re-gate, which widens the basin when the prediction is off by more than the gate allows.
  int max_iterations = 3;
  /// Robust loss on each reading's squared disparity, as vdt-opt's (VdtOptimizerOptions::loss):
  /// each iteration weighs reading i by the IRLS weight w_i = rho'(|d_i|^2) at the iterate, i.e.
  /// its noise R_i / w_i (an M-estimator update). Readings of clutter inside the gate (edges of
  /// grass and cracks beside a camera's markings) then pull neither the pose nor its covariance as
  /// if they were the surface. kNone: every gated reading counts fully, (3.13)-(3.21).
  RobustLoss loss = RobustLoss::kNone;
  double loss_scale = 0.05;  ///< metres: where the robust loss departs from quadratic
  /// Poor predictions: the iterations start at the best pose of a window search around the
  /// prediction (the prior still pulls toward the prediction), and an update that leaves the
  /// scan unexplained is refused (prediction only, kRefused). See guess_search.hpp.
  GuessSearchOptions search;
  /// Start the iterations at the optimization localizer's solution from the prediction (its
  /// coarse-to-fine pyramid, robust loss and gate rounds; `start` sets them) when that explains
  /// more of the observations than the prediction: the Gauss-Newton iterations alone lock onto
  /// the wrong one of two close, parallel edges (a painted line's two sides, 0.15 m apart) when
  /// the prediction is off by more than half their spacing. The prior still pulls toward the
  /// prediction; only the linearisation point changes.
  bool optimizer_start = false;
  VdtOptimizerOptions start;
  /// How map errors shared per square (sensor.map_correlation_length > 0) enter the filter.
  /// false: the update's sensitivity to them, M = sum_k S_k sigma_c^2 S_k^T with S_k from the
  /// update's information (the prior's included: the scan's alone explodes in a direction the
  /// frame barely observes), is reported on top of the filter's covariance and not fed back.
  /// true: a Schmidt-Kalman filter that keeps cov(X, e_k) for every square k it has seen and
  /// solves each update jointly for the pose and the errors of the squares in view (the errors
  /// stay unestimated): P is the error
  /// against the world, a square seen again adds no information beyond what its error allows, and
  /// observations of the world (bearings to landmarks) correct the pose without being pulled back
  /// by the next scan. Exact when the squares' errors are independent; over-confident when they
  /// are not (measured in the README: PMD and Intel studies). Not with sensor.map_uncertainty
  /// (a map that knows its own covariance), whose term M is reported as in the default.
  bool schmidt_map_errors = false;
  /// Consistency test on the correction: an update whose correction dX = X+ - X_pred is, under
  /// the prior's covariance (P + the last map term), a larger Mahalanobis size dX^T (P + M)^-1 dX
  /// than this chi-square(3) value is refused (prediction only, kRefused): a registration to the
  /// wrong stretch of a repeating or straight structure moves the estimate several sigma in one
  /// update while it shrinks the covariance. The prior grows with each refused update, so a
  /// correct but surprising correction passes after a few. 0: off.
  double correction_gate = 0.0;
};

/// \brief Closes an information-form update: P+ = info^-1, X+ = X + P+ b, where
/// info = P^-1 + sum H^T R^-1 H and b = sum H^T R^-1 nu (shared by the VDT and UDT filters).
void ekf_apply_information(const Eigen::Matrix3d& info, const Eigen::Vector3d& b, Pose2& x,
                           Eigen::Matrix3d& p);

/// \brief vdt-ekf's defaults (its constructor's, LocalizerSettings{}'s, `vdtnav localize`'s):
/// odometry increments for the prediction (a log's odometry, not a commanded velocity), and the
/// map errors shared per 2 m square with the map builder's pose error at half a cell, as
/// vdt_opt_defaults(2). VdtEkfOptions{}: the thesis's velocity model on an exact map.
[[nodiscard]] VdtEkfOptions vdt_ekf_defaults();

/// \brief The VDT EKF localizer. Name "vdt-ekf".
class VdtEkfLocalizer final : public Localizer2D {
 public:
  /// \throws ConfigError for invalid options.
  VdtEkfLocalizer(const VdtMap2& map, const VdtEkfOptions& options = vdt_ekf_defaults(),
                  std::string name = "vdt-ekf");
  void reset(const Pose2& pose, const Eigen::Matrix3d& covariance) override;
  using Localizer2D::update;
  [[nodiscard]] LocalizationResult update(const OdometryStep& odometry,
                                          const ScanPoints& observations) override;
  [[nodiscard]] std::string name() const override { return name_; }

  /// \brief Corrects the current estimate (no prediction: call after update() of the same
  /// instant) with bearings to known landmarks, associated and gated (bearing_update.hpp) with
  /// reported_covariance().
  BearingUpdateResult update_bearings(const std::vector<BearingDetection>& detections,
                                      const std::vector<Landmark2>& landmarks,
                                      const BearingUpdateOptions& options = {});
  /// \brief The current estimate and the filter's covariance (without the map term M; with
  /// schmidt_map_errors, M = 0 and this is the error against the world).
  [[nodiscard]] const Pose2& pose() const noexcept { return x_; }
  [[nodiscard]] const Eigen::Matrix3d& covariance() const noexcept { return p_; }
  /// \brief What update() reports as the covariance: the filter's plus the map term M of the last
  /// scan update (map errors shared along the map's surfaces). update_bearings() gates and
  /// corrects with P + M (a bearing sees the error from the map too) and carries M through the
  /// correction as (I - K H) M (I - K H)^T.
  [[nodiscard]] Eigen::Matrix3d reported_covariance() const { return p_ + map_term_; }
  /// \brief How many squares' errors the Schmidt filter carries a cross-covariance with.
  [[nodiscard]] std::size_t considered_squares() const noexcept { return cross_.size(); }

 private:
  VdtSensorModel model_;
  VdtEkfOptions options_;
  std::unique_ptr<VdtOptimizer> start_;  ///< options_.optimizer_start
  Pose2 x_ = Pose2::Zero();
  Eigen::Matrix3d p_ = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d map_term_ = Eigen::Matrix3d::Zero();  ///< see reported_covariance()
  /// schmidt_map_errors: cov(X, e_k) per square k of the map (VdtSensorModel::map_error_group).
  std::unordered_map<std::int64_t, Eigen::Matrix<double, 3, 2>> cross_;
  void prune_cross();
  /// The map term M of a scan at xi with the map's own covariance (sensor.map_uncertainty).
  [[nodiscard]] Eigen::Matrix3d map_covariance(const Eigen::Matrix3d& info, const Pose2& xi,
                                               const ScanPoints& pts,
                                               std::vector<BeamDisparity>* disparities) const;
  std::string name_;
};

}  // namespace vdtnav
