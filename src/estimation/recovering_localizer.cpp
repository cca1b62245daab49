#include "vdtnav/estimation/recovering_localizer.hpp"

#include <algorithm>
#include <cmath>

#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/guess_search.hpp"

namespace vdtnav {

RecoveringLocalizer::RecoveringLocalizer(std::unique_ptr<Localizer2D> tracker, const VdtMap2& map,
                                         const OccupancyGrid<2>& occupancy,
                                         const GlobalLocalizationOptions& global,
                                         const RecoveryOptions& options)
    : tracker_(std::move(tracker)),
      model_(map, global.optimizer.sensor),
      global_(map, occupancy, global),
      options_(options),
      detector_(options.lost) {
  VDTNAV_CHECK(tracker_ != nullptr, "recovering localizer: no tracker");
  options_.validate();
}

void RecoveryOptions::validate() const {
  VDTNAV_CHECK(min_readings >= 0, "recovery: min_readings must be >= 0");
  VDTNAV_CHECK(max_attempt_gap >= 1, "recovery: max_attempt_gap must be >= 1");
  VDTNAV_CHECK(std::isfinite(check_drop) && std::isfinite(check_margin) && check_margin >= 0.0,
               "recovery: check_drop must be finite and check_margin >= 0");
  lost.validate();
}

void RecoveringLocalizer::reset(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  tracker_->reset(pose, covariance);
  detector_.reset();
  lost_ = candidate_ = false;
}

void RecoveringLocalizer::begin_loss() {
  const double b = detector_.baseline();
  before_loss_ = std::isnan(b) ? 0.0 : b;
  lost_scans_ = next_attempt_ = 0;
  candidate_ = false;
}

double RecoveringLocalizer::acceptable(double baseline) const {
  return std::max(global_.options().accept_fraction, baseline - options_.lost.drop);
}

LocalizationResult RecoveringLocalizer::update(const OdometryStep& odometry,
                                               const ScanPoints& observations) {
  LocalizationResult r = tracker_->update(odometry, observations);
  const double distance = global_.options().explained_distance;
  r.explained = explained_fraction(model_, observations, r.pose, distance);
  if (!options_.detect) return r;
  const bool informative = static_cast<int>(observations.size()) >= options_.min_readings;
  if (candidate_ && informative) {
    // The tracker was restarted at the candidate on the previous scan and has just tracked this
    // one from it: confirmed when it explains this scan at the level the candidate had to.
    candidate_ = false;
    if (r.status == LocalizationStatus::kConverged && r.explained >= acceptable(before_loss_)) {
      ++recoveries_;
      detector_.reset();
      lost_ = false;
      return r;
    }
  }
  if (informative) {
    const bool detector_lost = detector_.update(r.explained);
    // With recovery, only a confirmed acquisition ends a loss (see RecoveryOptions::recover).
    const bool was_lost = lost_;
    lost_ = options_.recover ? (lost_ || detector_lost) : detector_lost;
    if (lost_ && !was_lost) begin_loss();
  }
  ++since_check_;
  if (!lost_) {
    // A smaller fall: is there a pose that explains the scan clearly better? (file comment)
    const double b = detector_.baseline();
    if (options_.recover && options_.check_drop > 0.0 && !std::isnan(b) &&
        b - detector_.window_mean() > options_.check_drop && since_check_ >= options_.lost.window &&
        informative) {
      since_check_ = 0;
      last_acquisition_ = global_.localize_better(observations, r.pose, options_.check_margin);
      r.work.global_searches += 1;
      if (last_acquisition_.result.status == LocalizationStatus::kConverged &&
          last_acquisition_.explained >= acceptable(b)) {
        ++recoveries_;
        return adopt(r);
      }
    }
    return r;
  }
  r.status = LocalizationStatus::kLost;
  if (!options_.recover || !informative) return r;
  // Lost: an attempt on scans 1, 2, 4, 8, ... of the loss, then every max_attempt_gap.
  const int i = lost_scans_++;
  if (i != next_attempt_) return r;
  next_attempt_ = i + std::min(std::max(1, i), options_.max_attempt_gap);
  last_acquisition_ = global_.localize(observations);
  r.work.global_searches += 1;
  const GlobalLocalizationResult& g = last_acquisition_;
  if (g.result.status != LocalizationStatus::kConverged || g.explained < acceptable(before_loss_)) {
    return r;
  }
  // A candidate: the tracker restarts there; the next informative scan confirms it or not.
  LocalizationResult out = adopt(r);
  out.status = LocalizationStatus::kLost;
  lost_ = true;
  candidate_ = true;
  return out;
}

LocalizationResult RecoveringLocalizer::adopt(const LocalizationResult& tracked) {
  const GlobalLocalizationResult& g = last_acquisition_;
  LocalizationResult out = g.result;
  out.explained = g.explained;
  out.work.global_searches = tracked.work.global_searches;
  out.iterations += tracked.iterations;
  // Without a covariance (a refinement that could not compute one): a cell and a heading step.
  const double h = model_.map().resolution();
  tracker_->reset(out.pose, out.has_covariance
                                ? out.covariance
                                : Eigen::Vector3d(h * h, h * h, 1e-4).asDiagonal().toDenseMatrix());
  detector_.reset();
  lost_ = false;
  return out;
}

}  // namespace vdtnav
