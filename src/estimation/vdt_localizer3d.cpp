#include "vdtnav/estimation/vdt_localizer3d.hpp"

#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Cholesky>

#include "vdtnav/core/error.hpp"
#include "vdtnav/sensor/sweep_motion.hpp"

namespace vdtnav {
namespace {

/// Metres a rotation-rate change is weighed at when deciding whether the sweep's motion settled:
/// the range at which a reading moves as much as the sensor does.
constexpr double kDeskewLeverArm = 10.0;

void check(const VdtLocalizer3Options& o) {
  VDTNAV_CHECK(o.sigma_translation_per_metre >= 0.0 && o.sigma_rotation_per_radian >= 0.0 &&
                   o.sigma_translation_per_second >= 0.0 && o.sigma_rotation_per_second >= 0.0 &&
                   o.sigma_imu_attitude > 0.0,
               "localizer3d: odometry and IMU sigmas must be >= 0 (the IMU's > 0)");
  VDTNAV_CHECK(std::isnan(o.held_attitude_sigma) || o.held_attitude_sigma > 0.0,
               "localizer3d: held_attitude_sigma must be > 0, or NaN (not estimated)");
  VDTNAV_CHECK(o.explained_distance > 0.0, "localizer3d: explained_distance must be > 0");
  VDTNAV_CHECK(o.deskew_passes >= 1, "localizer3d: deskew_passes must be >= 1");
  VDTNAV_CHECK(o.accept_fraction >= 0.0 && o.accept_fraction <= 1.0,
               "localizer3d: accept_fraction must be in [0, 1]");
  o.lost.validate();
  o.global.validate();
  o.imu.validate();
}

/// The prediction as a prior (VdtOptimizerOptions::odometry_prior): the information of its
/// covariance over the components it gives a variance (a held roll and pitch without a sigma
/// have none: no information there), when that block is positive definite.
std::optional<PosePrior<3>> prediction_prior(const Pose3& mean, const Matrix6d& covariance) {
  std::vector<int> k;
  for (int i = 0; i < 6; ++i)
    if (covariance(i, i) > 0.0) k.push_back(i);
  const int n = static_cast<int>(k.size());
  if (n == 0) return std::nullopt;
  Eigen::MatrixXd block(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) block(i, j) = covariance(k[i], k[j]);
  const Eigen::LLT<Eigen::MatrixXd> llt(block);
  if (llt.info() != Eigen::Success) return std::nullopt;
  const Eigen::MatrixXd information = llt.solve(Eigen::MatrixXd::Identity(n, n));
  PosePrior<3> prior;
  prior.mean = mean;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) prior.information(k[i], k[j]) = information(i, j);
  return prior;
}

VdtOptimizerOptions six_dof(VdtOptimizerOptions o) {
  o.four_dof = false;
  return o;
}

}  // namespace

OdometryStep3 VdtLocalizer3Options::noisy_odometry(const Pose3& a, const Pose3& b, double dt,
                                                   std::mt19937& rng) const {
  std::normal_distribution<double> n(0.0, 1.0);
  const Pose3 d = a.inverse() * b;
  const Eigen::Vector2d sigmas = odometry_sigmas(d, dt);
  OdometryStep3 s;
  s.dt = dt;
  s.delta = d;
  s.delta.translation() += sigmas[0] * Eigen::Vector3d(n(rng), n(rng), n(rng));
  s.delta.linear() = so3_exp(sigmas[1] * Eigen::Vector3d(n(rng), n(rng), n(rng))) * d.linear();
  const Eigen::Vector3d rpy = rpy_of(b.linear());
  s.roll = rpy.x() + sigma_imu_attitude * n(rng);
  s.pitch = rpy.y() + sigma_imu_attitude * n(rng);
  return s;
}

VdtOptimizationLocalizer3::VdtOptimizationLocalizer3(const VdtField3& map,
                                                     const VdtLocalizer3Options& options)
    : options_(options),
      optimizer_(map, options.optimizer),
      full_(optimizer_, six_dof(options.optimizer)) {
  check(options);
}

VdtOptimizationLocalizer3::VdtOptimizationLocalizer3(const VdtOptimizer3& shared,
                                                     const VdtLocalizer3Options& options)
    : options_(options),
      optimizer_(shared, options.optimizer),
      full_(shared, six_dof(options.optimizer)) {
  check(options);
}

void VdtOptimizationLocalizer3::reset(const Pose3& pose, const Matrix6d& covariance) {
  pose_ = pose;
  covariance_ = covariance;
  starts_ = StartSet::kAxes;
}

std::string VdtOptimizationLocalizer3::name() const {
  return optimizer_.options().four_dof ? "vdt-opt-4dof" : "vdt-opt-6dof";
}

Matrix6d VdtOptimizationLocalizer3::with_held_attitude(const ObservationSet3& observations,
                                                       const LocalizationResult3& r,
                                                       double sigma) const {
  const int f[4] = {0, 1, 2, 5}, h[2] = {3, 4};
  Matrix6d out = r.covariance;
  if (std::isnan(sigma)) {  // not estimated: no number for it
    for (int k : h) {
      out.row(k).setConstant(std::numeric_limits<double>::quiet_NaN());
      out.col(k).setConstant(std::numeric_limits<double>::quiet_NaN());
    }
    return out;
  }
  // The cost's 6-DOF Gauss-Newton Hessian at the solution, H = sum_i J_i^T J_i over the inliers
  // (J_i = dd_i/dX): the solve zeroes the free gradient, so a held error dtheta_h moves the free
  // components by S dtheta_h with S = -H_ff^-1 H_fh.
  std::vector<BeamDisparity3> d;
  full_.sensor_model().disparities(r.pose.linear(), r.pose.translation(), observations, nullptr, &d,
                                   DisparityParts::kPose);
  Matrix6d hessian = Matrix6d::Zero();
  for (const BeamDisparity3& b : d)
    if (b.inlier) hessian.noalias() += b.d_pose.transpose() * b.d_pose;
  const double s2 = sigma * sigma;
  Eigen::Matrix4d hff;
  Eigen::Matrix<double, 4, 2> hfh;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) hff(i, j) = hessian(f[i], f[j]);
    for (int j = 0; j < 2; ++j) hfh(i, j) = hessian(f[i], h[j]);
  }
  const Eigen::LDLT<Eigen::Matrix4d> ldlt(hff);
  if (ldlt.info() == Eigen::Success && ldlt.isPositive()) {
    const Eigen::Matrix<double, 4, 2> sens = -ldlt.solve(hfh);
    const Eigen::Matrix4d add = s2 * sens * sens.transpose();
    const Eigen::Matrix<double, 4, 2> cross = s2 * sens;
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j < 4; ++j) out(f[i], f[j]) += add(i, j);
      for (int j = 0; j < 2; ++j) out(f[i], h[j]) = out(h[j], f[i]) = cross(i, j);
    }
  }
  for (int j = 0; j < 2; ++j) out(h[j], h[j]) = s2;
  return out;
}

LocalizationResult3 VdtOptimizationLocalizer3::update(const OdometryStep3& odometry,
                                                      const ObservationSet3& scan) {
  if (!options_.deskew || scan.times.empty() || !(odometry.dt > 0.0))
    return update_with(odometry, scan);
  // Deskewing (sweep_motion.hpp): the readings move to the stamp's frame at constant velocity,
  // the motion held during each solve: first the prediction's, then the motion from the previous
  // estimate to the solution, until it settles (options.deskew_passes).
  const Pose3 previous = pose_;
  const Matrix6d previous_covariance = covariance_;
  double sweep = 0.0;
  for (const double t : scan.times) sweep = std::max(sweep, std::abs(t));
  SweepMotion motion = SweepMotion::from_increment(odometry.delta, odometry.dt);
  LocalizationResult3 r;
  long iterations = 0;
  for (int pass = 1;; ++pass) {
    ObservationSet3 deskewed = scan;
    deskew(deskewed, motion);
    r = update_with(odometry, deskewed);
    iterations += r.iterations;
    if (pass >= options_.deskew_passes || r.status != LocalizationStatus::kConverged) break;
    const SweepMotion refined =
        SweepMotion::from_increment(previous.inverse() * r.pose, odometry.dt);
    const double change = sweep * ((refined.velocity - motion.velocity).norm() +
                                   (refined.rates - motion.rates).norm() * kDeskewLeverArm);
    motion = refined;
    if (change < 1e-3) break;  // under 1 mm over the sweep
    pose_ = previous;
    covariance_ = previous_covariance;
  }
  r.iterations = iterations;
  return r;
}

LocalizationResult3 VdtOptimizationLocalizer3::update_with(const OdometryStep3& odometry,
                                                           const ObservationSet3& observations) {
  // 1. Prediction.
  Pose3 guess = pose_ * odometry.delta;
  Matrix6d f = Matrix6d::Identity();
  f.topRightCorner<3, 3>() = -skew(pose_.linear() * odometry.delta.translation());
  Matrix6d q = Matrix6d::Zero();
  if (odometry.has_covariance) {
    // The increment's own (an IMU's): in the previous robot frame, turned into the map's,
    // pose_ oplus(D, e) = oplus(pose_ D, (R dt, R dtheta)).
    Matrix6d r = Matrix6d::Zero();
    r.topLeftCorner<3, 3>() = pose_.linear();
    r.bottomRightCorner<3, 3>() = pose_.linear();
    q = r * odometry.covariance * r.transpose();
  } else {
    const Eigen::Vector2d sigmas = options_.odometry_sigmas(odometry.delta, odometry.dt);
    const double st = sigmas[0], sr = sigmas[1];
    q.topLeftCorner<3, 3>().diagonal().setConstant(st * st);  // isotropic: any frame
    q.bottomRightCorner<3, 3>().diagonal().setConstant(sr * sr);
  }
  Matrix6d predicted = f * covariance_ * f.transpose() + q;
  const bool four_dof = optimizer_.options().four_dof;
  // The held attitude's sigma: the IMU's (the step's own, else the setting), else (4-DOF) the
  // user's or none (NaN).
  const double held_sigma = odometry.has_attitude()
                                ? (std::isnan(odometry.attitude_sigma) ? options_.sigma_imu_attitude
                                                                       : odometry.attitude_sigma)
                                : options_.held_attitude_sigma;
  if (odometry.has_attitude()) {
    const Eigen::Vector3d rpy = rpy_of(guess.linear());
    guess.linear() = pose3_from_xyz_rpy(0, 0, 0, odometry.roll, odometry.pitch, rpy.z()).linear();
  }
  if (odometry.has_attitude() || four_dof) {  // roll and pitch are what is held, not predicted
    for (int k = 3; k <= 4; ++k) {
      predicted.row(k).setZero();
      predicted.col(k).setZero();
      predicted(k, k) = std::isnan(held_sigma) ? 0.0 : held_sigma * held_sigma;
    }
  }

  // 2. Update, and whether the map explains the scan there.
  const VdtSensorModel3& model = optimizer_.sensor_model();
  // The prediction as a prior (options.optimizer.odometry_prior), as in 2D: a direction the scan
  // leaves free (a floor alone fixes z, roll and pitch) stays at the prediction, with its variance.
  // The multi-start below solves without it: it looks for where the map explains the scan.
  const std::optional<PosePrior<3>> prior =
      optimizer_.options().odometry_prior ? prediction_prior(guess, predicted) : std::nullopt;
  LocalizationResult3 r =
      prior ? optimizer_.solve(observations, guess, *prior) : optimizer_.solve(observations, guess);
  const auto usable = [](const LocalizationResult3& x) {
    return x.status == LocalizationStatus::kConverged ||
           x.status == LocalizationStatus::kNotConverged;
  };
  // A solve that did not converge goes to the multi-start (which continues it and tries the
  // starts around the prediction): on CATEC accepting it as it is costs 3x in attitude. What the
  // map explains at it is still measured: lost detection judges every update, whatever its
  // status (issue 57).
  const double explained_at =
      usable(r) ? explained_fraction(model, observations, r.pose, options_.explained_distance)
                : 0.0;
  double explained = r.status == LocalizationStatus::kConverged ? explained_at : 0.0;
  bool replaced = false;  // by the multi-start's solution (explained is then measured at it)
  if (explained < options_.accept_fraction && starts_ != StartSet::kNone) {
    MultiStartOptions ms = options_.multi_start;
    // The attitude grid (~120 subsample solves) only to re-acquire: a tracked scan needs the starts
    // along the axes at most.
    if (starts_ == StartSet::kAxes) ms.attitude_grid = 0;
    ms.explained_distance = options_.explained_distance;
    ms.accept_fraction = std::max(ms.accept_fraction, options_.accept_fraction);
    LocalizationResult3 m = solve_multi_start(optimizer_, observations, guess, ms);
    const double e =
        usable(m) ? explained_fraction(model, observations, m.pose, options_.explained_distance)
                  : 0.0;
    m.work.solves += r.work.solves;
    m.iterations += r.iterations;
    if (e > explained) {
      r = std::move(m);
      explained = e;
      replaced = true;
    } else {
      r.work.solves = m.work.solves;
      r.iterations = m.iterations;
    }
  }
  const bool accepted = usable(r) && r.has_covariance && explained >= options_.accept_fraction;
  // The fraction reported (and judged by lost detection): at the solution kept, converged or not.
  r.explained = replaced ? explained : explained_at;
  if (accepted) {
    if (four_dof) r.covariance = with_held_attitude(observations, r, held_sigma);
    pose_ = r.pose;
    covariance_ = r.covariance;
    if (four_dof && std::isnan(held_sigma)) {  // kept as the solve gave it (zero held rows)
      covariance_.row(3).setZero();
      covariance_.row(4).setZero();
      covariance_.col(3).setZero();
      covariance_.col(4).setZero();
    }
  } else {
    if (r.status == LocalizationStatus::kConverged) r.status = LocalizationStatus::kRefused;
    pose_ = guess;
    covariance_ = predicted;
    r.pose = guess;
    r.covariance = predicted;
    r.has_covariance = true;
    if (four_dof && std::isnan(held_sigma)) {
      for (int k = 3; k <= 4; ++k) {  // not estimated (the file comment)
        r.covariance.row(k).setConstant(std::numeric_limits<double>::quiet_NaN());
        r.covariance.col(k).setConstant(std::numeric_limits<double>::quiet_NaN());
      }
    }
  }
  return r;
}

LocalizationResult3 localize_from_guess(const VdtOptimizationLocalizer3& localizer,
                                        const ObservationSet3& observations, const Pose3& guess) {
  const VdtLocalizer3Options& o = localizer.options();
  const VdtOptimizer3& optimizer = localizer.optimizer();
  LocalizationResult3 r = o.multi_start.enabled
                              ? solve_multi_start(optimizer, observations, guess, o.multi_start)
                              : optimizer.solve(observations, guess);
  r.explained =
      explained_fraction(optimizer.sensor_model(), observations, r.pose, o.explained_distance);
  if (r.status == LocalizationStatus::kConverged && r.explained < o.accept_fraction)
    r.status = LocalizationStatus::kRefused;  // converged, not on this map's surfaces
  return r;
}

}  // namespace vdtnav
