// VdtOptimizationLocalizer: Algorithm 1 as a 2D localizer (UPDATEGUESS by odometry, the
// optimizer's solve, a window search on a poor fit, and the local scan map across map gaps).
#include "vdtnav/estimation/vdt_optimizer.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include <Eigen/Cholesky>

#include "vdtnav/estimation/guess_search.hpp"
#include "vdtnav/estimation/motion_model.hpp"

namespace vdtnav {

VdtOptimizationLocalizer::VdtOptimizationLocalizer(const VdtMap2& map,
                                                   const VdtOptimizerOptions& options,
                                                   std::string name)
    : optimizer_(map, options), local_(options.bridge), name_(std::move(name)) {}

void VdtOptimizationLocalizer::reset(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  pose_ = pose;
  uncertainty_ = covariance;
  local_.clear();
  in_gap_ = false;
}

LocalizationResult VdtOptimizationLocalizer::update(const OdometryStep& odometry,
                                                    const ScanPoints& pts) {
  const GuessSearchOptions& so = optimizer_.options().search;
  Pose2 guess = pose_;  // UPDATEGUESS: X (+) odometry, its uncertainty propagated alongside
  const Eigen::Matrix3d previous_uncertainty = uncertainty_;
  ekf_predict(MotionModelKind::kOdometryIncrement, so.odometry_noise, odometry, guess,
              uncertainty_);
  const auto usable = [](const LocalizationResult& x) {
    return x.status == LocalizationStatus::kConverged ||
           x.status == LocalizationStatus::kNotConverged;
  };
  // The prediction as a prior (options().odometry_prior): its information, when its covariance is
  // positive definite.
  std::optional<PosePrior<2>> prior;
  if (optimizer_.options().odometry_prior) {
    const Eigen::LLT<Eigen::Matrix3d> llt(uncertainty_);
    if (llt.info() == Eigen::Success)
      prior = PosePrior<2>{guess, llt.solve(Eigen::Matrix3d::Identity())};
  }
  const auto solve = [&](const Pose2& from) {
    return prior ? optimizer_.solve(pts, from, *prior) : optimizer_.solve(pts, from);
  };
  LocalizationResult r = solve(guess);
  double explained =
      usable(r) ? explained_fraction(optimizer_.sensor_model(), pts, r.pose, so.explained_distance)
                : 0.0;
  if (so.enabled && explained < so.search_below) {
    // A poor fit: solve again from the best pose of a window around the guess, keep the better
    // (when the guess itself is the best candidate, the solve would repeat the first one).
    const VdtSensorModel& model = optimizer_.sensor_model();
    const Pose2 start = search_guess(model, pts, guess, so, &uncertainty_);
    r.work.window_searches = 1;
    if (start != guess) {
      LocalizationResult r2 = solve(start);
      const double e2 =
          usable(r2) ? explained_fraction(model, pts, r2.pose, so.explained_distance) : 0.0;
      // The work of both solves, whichever is kept.
      LocalizationResult::Work work = r.work;
      work.solves += r2.work.solves;
      work.coarse_to_fine += r2.work.coarse_to_fine;
      const int iterations = r.iterations + r2.iterations;
      if (e2 > explained) {
        r = r2;
        explained = e2;
      }
      r.work = work;
      r.iterations = iterations;
    }
  }
  // Back from a gap of the map, a partial match far from where the recent scans place the robot
  // is often a wrong one: re-entry then asks for more of the scan explained. "Far": outside the
  // 99 % region of the propagated uncertainty (chi-square, 3 dof: 11.34).
  double accept = so.accept_fraction;
  if ((in_gap_ || so.check_every_jump) && usable(r)) {
    const Eigen::Vector3d e = pose_error(r.pose, guess);
    const Eigen::Matrix3d p =
        uncertainty_ + Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal().toDenseMatrix();
    if (e.dot(p.ldlt().solve(e)) > 11.34) accept = std::max(accept, so.reentry_fraction);
    // Where the pattern repeats, a solve can also slide along a straight stretch far beyond
    // anything the window search could reach: such a solution is not trusted.
    if (so.check_every_jump &&
        (e.head<2>().norm() > so.max_window_xy || std::abs(e[2]) > so.max_window_yaw)) {
      accept = 2.0;  // never
    }
  }
  if (usable(r) && (!so.enabled || explained >= accept)) {
    pose_ = r.pose;
    uncertainty_ = r.has_covariance ? r.covariance : Eigen::Matrix3d::Zero();
    in_gap_ = false;
  } else {
    // Nothing usable, or the map does not explain the scan: match it against the recent scans,
    // else keep the odometry guess. Either way it is not a localization on the map. Fewer
    // explained readings than min_inliers (a camera over grass) is "too few observations", a
    // solution the acceptance test refuses "refused" (the solver's own verdict stays otherwise).
    if (usable(r)) {
      r.status = explained * static_cast<double>(pts.size()) < optimizer_.options().min_inliers
                     ? LocalizationStatus::kTooFewObservations
                     : LocalizationStatus::kRefused;
    }
    r.has_covariance = false;
    const std::optional<Pose2> bridged =
        local_.match(pts, guess, optimizer_.options(), so.explained_distance);
    pose_ = bridged ? *bridged : guess;
    r.work.bridged = bridged ? 1 : 0;
    r.pose = pose_;
    in_gap_ = true;
    if (bridged) {
      // Scan matching drifts far less than dead reckoning: a fraction of the odometry's growth.
      const double f = optimizer_.options().bridge.uncertainty_growth;
      uncertainty_ = previous_uncertainty + f * (uncertainty_ - previous_uncertainty);
      // A pose across the gap, with the uncertainty it carries (issue 57: a correct pose is not
      // withheld from the default outputs). Where the map contradicts it, the lost watch refuses
      // it (recovering_localizer.hpp).
      r.status = LocalizationStatus::kBridged;
      r.covariance = uncertainty_;
      r.has_covariance = true;
    }
  }
  local_.add(pts, pose_);
  return r;
}

}  // namespace vdtnav
