#pragma once
/// \file
/// \brief A 3D LiDAR moving through a 3D map: Algorithm 1 in SE(3), one scan at a time, behind
/// the Localizer3D interface (LocalizerT<3>, localizer.hpp).
///
/// Per scan:
/// 1. Prediction (UPDATEGUESS): X- = X (+) odometry increment; with an IMU, X-'s roll and pitch are
///    the IMU's (R = Rz(yaw-) Ry(pitch_imu) Rx(roll_imu)). Its covariance P- = F P F^T + Q in the
///    left perturbation (dt, dtheta): F = [I, -[R dt_odo]x; 0, I] and Q the odometry noise
///    (per metre and per radian of the increment, in the robot frame), with the IMU's variance on
///    roll and pitch when it gives them.
/// 2. Update: the 6-DOF or 4-DOF solve (VdtOptimizer3) from X- (with optimizer.odometry_prior,
///    X- and P- as its prior, the maximum a posteriori solve 2D vdt-opt runs); the fraction of the
///    scan the map explains there (multi_start.hpp's explained_fraction) says whether it is right:
///    converged is not correct. Below accept_fraction, multi-start from X- (the starts along the
///    axes; the attitude grid too when re-acquiring, set_starts()); still below: the scan is
///    refused (status kRefused) and the prediction kept.
/// 3. Lost detection and recovery wrap this tracker as they wrap a 2D one
///    (recovering_localizer3d.hpp, RecoveringLocalizerT<3>): the window test of lost_detection.hpp
///    reports kLost, a reading the map does not explain contradicting the pose only when its beam
///    passed through a surface of the map (scan_agreement.hpp; a 3D map knows surfaces, not free
///    space): lost when half the readings a window judges contradict; while lost, the attitude
///    grid re-acquires on lost scans 1, 2, 4, 8 and then every 16th (each costs ~0.5-1 s), and
///    global localization after it. make_vdt_localizer3() builds the two together.
///
/// 4-DOF mode: roll and pitch are held at the IMU's (or, without one, at the prediction's: from
/// the start pose on), so their error goes into x, y, z and yaw through the scan. With a σ for the
/// held attitude (the IMU's sigma_imu_attitude when the odometry carries roll and pitch, else
/// held_attitude_sigma when the user gives one), the reported 6 x 6 covariance is that of the
/// 4-DOF solve plus S Sigma_rp S^T, S = -H_ff^-1 H_fr the sensitivity of the free components to
/// the held ones (H the cost's 6-DOF Gauss-Newton Hessian at the solution), with Sigma_rp in the
/// roll/pitch rows: every component has a variance (eval::nees works). Without one, roll and pitch
/// are not estimated: their rows and columns are NaN, and the free 4 x 4 block is the solve's
/// (what it is given the held attitude). No σ is invented.

#include <limits>
#include <random>
#include <string>

#include "vdtnav/estimation/global_localization3d.hpp"
#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/estimation/lost_detection.hpp"
#include "vdtnav/estimation/multi_start.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/sensor/imu.hpp"

namespace vdtnav {

/// \brief Options of the sequential 3D localizer.
struct VdtLocalizer3Options {
  /// The solve (four_dof selects the 4-DOF mode). The prediction is good when tracking, so the
  /// coarse-to-fine alignment runs only when the median disparity at it exceeds 0.1 m (in 3D the
  /// optimizer alone defaults to always), and a solve stops when a step changes the cost by less
  /// than 1e-4 of it (on the CATEC map 1e-6 costs 2x the time, 40 against 19 iterations a scan,
  /// for the same accuracy).
  VdtOptimizerOptions optimizer = [] {
    VdtOptimizerOptions o;
    o.coarse_threshold = 0.1;
    o.function_tolerance = 1e-4;
    o.sensor.map_correlation_length = 1.0;
    return o;
  }();
  /// Odometry noise (1 sigma) per metre travelled and per radian turned in an increment, and
  /// per second (a robot standing still drifts too), robot frame.
  double sigma_translation_per_metre = 0.05;
  double sigma_rotation_per_radian = 0.05;
  double sigma_translation_per_second = 0.02;  ///< m/s
  double sigma_rotation_per_second = 0.01;     ///< rad/s
  /// The IMU's roll and pitch noise (1 sigma), radians, for odometry steps that carry them
  /// (OdometryStep3::has_attitude): a consumer-grade AHRS, ~0.3 degrees.
  double sigma_imu_attitude = 0.005;
  /// The IMU's rates and specific forces (`vdtnav localize3d --imu FILE.csv`, or a bag's
  /// --imu-topic): noise densities, biases and gravity, preintegrated between scans into the
  /// prediction and its covariance (sensor/imu.hpp). The localizer itself takes the steps made
  /// from them (OdometryStep3::covariance, attitude_sigma).
  ImuNoise imu;
  /// Deskew scans whose readings carry times (ObservationSet3::times) at constant velocity
  /// (sensor/sweep_motion.hpp): first by the predicted motion (the odometry increment over its
  /// dt), then by the motion from the previous estimate to this scan's solution, solved again
  /// (deskew_passes in all, fewer when the motion settles within 1 mm over the sweep); false:
  /// every scan is taken as instantaneous.
  bool deskew = true;
  /// Solves per deskewed scan (>= 1). The refinement matters when the prediction's velocity is
  /// poor (constant velocity from two estimates the sweep distorted): each pass divides the
  /// velocity's error by about dt / (half the sweep), 2 at 10 Hz.
  int deskew_passes = 3;
  /// 4-DOF without an IMU: the held roll and pitch's standard deviation (radians), when the user
  /// knows it (`vdtnav localize3d --attitude-sigma`); NaN (the default): not estimated, NaN rows
  /// and columns in the reported covariance (see the file comment).
  double held_attitude_sigma = std::numeric_limits<double>::quiet_NaN();
  /// A reading is explained when its disparity is below this (metres).
  double explained_distance = 0.1;
  /// A solution explaining less of the scan is not accepted; multi-start runs first.
  double accept_fraction = 0.5;
  /// The map's own errors: readings in one 1 m cube share one (VdtSensorModelOptions), the
  /// optimizer's sensor.map_correlation_length above; without it the covariance of a VLP-16 scan,
  /// ~2000 readings, is 3x too small even on an exact map (tests/estimation/test_vdt_localizer3d).
  MultiStartOptions multi_start = [] {
    MultiStartOptions o;
    o.attitude_grid = 2;
    return o;
  }();
  /// Lost detection (recovering_localizer3d.hpp; the tracker alone does not use it). In doubt only
  /// by the rise above the track's own windows (doubt_rise, sigmas), not at 2D's absolute 0.3: on
  /// an outdoor point-cloud map right poses are contradicted by up to 0.39 (MulRan Riverside, the
  /// map from the odd keyframes), on an exact room map by nothing.
  /// A scan alone contradicted at the lost level is in doubt too (scan_doubt_contradiction):
  /// the track's jump onto a wrong pose shows on its first scan (a generated room's: 0.52, its
  /// right poses' 0.0005; Riverside's right poses at most 0.39, where the map lacks the place
  /// 0.56-0.90 and the tracker refuses them anyway).
  LostDetectionOptions lost = [] {
    LostDetectionOptions o;
    o.doubt_contradiction = o.lost_contradiction;
    o.scan_doubt_contradiction = o.lost_contradiction;
    return o;
  }();
  /// Recovery (recovering_localizer3d.hpp): while lost, the re-acquiring scans also run global
  /// localization over the whole map (`global`, refined with `optimizer`), and a pose it accepts
  /// is adopted; false: only the attitude grid around the prediction.
  bool global_recovery = true;
  /// Global localization (global_localization3d.hpp): `vdtnav localize3d --init global` and
  /// recovery. Its own optimizer is replaced by `optimizer` above.
  GlobalLocalization3Options global;

  /// \return the odometry noise (1 sigma) of an increment `delta` over `dt` seconds: translation
  /// (metres, per axis) and rotation (radians, per axis), the model above. What the prediction
  /// adds, and what a simulation that wants honest odometry draws.
  [[nodiscard]] Eigen::Vector2d odometry_sigmas(const Pose3& delta, double dt) const {
    return {sigma_translation_per_metre * delta.translation().norm() +
                sigma_translation_per_second * dt,
            sigma_rotation_per_radian * so3_log(delta.linear()).norm() +
                sigma_rotation_per_second * dt};
  }
  /// \return the odometry step from pose a to pose b over `dt`, drawn with odometry_sigmas() and
  /// the IMU's roll and pitch of b with sigma_imu_attitude (simulations, tests).
  [[nodiscard]] OdometryStep3 noisy_odometry(const Pose3& a, const Pose3& b, double dt,
                                             std::mt19937& rng) const;
};

/// \brief The multi-start a 3D update runs when its solve is explained below accept_fraction:
/// none, the starts along the axes (tracking), or those and the attitude grid (re-acquiring).
enum class StartSet { kNone, kAxes, kAttitudeGrid };

/// \brief The sequential 3D localizer's defaults (its constructor's, LocalizerSettings{}'s
/// `localize3d`, `vdtnav localize3d`'s): the optimizer of vdt_opt_defaults(3), a solution refused
/// when it explains less than 30 % of the scan (--min-explained), explained at 0.1 m (the
/// multi-start's distance), lost when a window explains no more (LostDetectionOptions's levels),
/// multi-start off (--multi-start: with the attitude grid, n = 2), the held attitude not estimated
/// (NaN, --attitude-sigma). VdtLocalizer3Options{}: the exact-map solver of the generated rooms.
[[nodiscard]] VdtLocalizer3Options vdt_localizer3_defaults();

/// \brief Algorithm 1 in SE(3) as a Localizer3D (names "vdt-opt-6dof", "vdt-opt-4dof"): the
/// tracker, without lost detection (make_vdt_localizer3() adds it).
class VdtOptimizationLocalizer3 final : public Localizer3D {
 public:
  /// \throws ConfigError for invalid options. The map must outlive the localizer.
  VdtOptimizationLocalizer3(const VdtField3& map,
                            const VdtLocalizer3Options& options = vdt_localizer3_defaults());
  /// \brief As above sharing `shared`'s coarse levels (same map): both modes built once.
  VdtOptimizationLocalizer3(const VdtOptimizer3& shared, const VdtLocalizer3Options& options);

  void reset(const Pose3& pose, const Matrix6d& covariance) override;
  /// \brief Predicts with `odometry`, deskews a scan whose readings carry times by that motion
  /// (options().deskew, sensor/sweep_motion.hpp), solves and accepts or refuses.
  [[nodiscard]] LocalizationResult3 update(const OdometryStep3& odometry,
                                           const ObservationSet3& observations) override;
  [[nodiscard]] std::string name() const override;
  [[nodiscard]] const VdtOptimizer3& optimizer() const noexcept { return optimizer_; }
  [[nodiscard]] const VdtLocalizer3Options& options() const noexcept { return options_; }
  /// \brief The multi-start of the following updates (kAxes after construction and reset()).
  void set_starts(StartSet starts) noexcept { starts_ = starts; }

  /// \brief The 4-DOF covariance made whole (see the file comment): `r`'s (the 4-DOF solve's,
  /// zero in the held rows) plus what a held roll and pitch of standard deviation `sigma` do to
  /// the free components, and sigma^2 in the held rows. NaN `sigma`: the held rows and columns NaN
  /// (not estimated), the free block `r`'s.
  [[nodiscard]] Matrix6d with_held_attitude(const ObservationSet3& observations,
                                            const LocalizationResult3& r, double sigma) const;

 private:
  /// update() on a scan already deskewed (or taken as instantaneous).
  [[nodiscard]] LocalizationResult3 update_with(const OdometryStep3& odometry,
                                                const ObservationSet3& observations);

  VdtLocalizer3Options options_;
  VdtOptimizer3 optimizer_;
  VdtOptimizer3 full_;  ///< the 6-DOF twin (shared pyramid): its sensor model gives the Hessian
  StartSet starts_ = StartSet::kAxes;
  Pose3 pose_ = Pose3::Identity();
  Matrix6d covariance_ = Matrix6d::Zero();
};

/// \brief One cloud localized alone from a guess: what `vdtnav localize3d` runs on a single scan
/// and on a sequence's scans until one is accepted (and the Python module's localize3d). The
/// solve from `guess` (multi-start from it when localizer.options().multi_start is enabled), the
/// fraction of the readings the map explains there (result.explained), and status kRefused when
/// a converged solution explains less than accept_fraction: converged is not correct. The
/// covariance is the solve's; in 4-DOF mode, with_held_attitude() makes it whole.
[[nodiscard]] LocalizationResult3 localize_from_guess(const VdtOptimizationLocalizer3& localizer,
                                                      const ObservationSet3& observations,
                                                      const Pose3& guess);

}  // namespace vdtnav
