#include "vdtnav/estimation/recovering_localizer.hpp"

#include <cmath>

#include "global_reacquisition.hpp"
#include "vdtnav/core/error.hpp"

namespace vdtnav {

void RecoveryOptions::validate() const {
  VDTNAV_CHECK(min_readings >= 0, "recovery: min_readings must be >= 0");
  VDTNAV_CHECK(search_boxes >= 1, "recovery: search_boxes must be >= 1");
  VDTNAV_CHECK(verify_scans >= 1, "recovery: verify_scans must be >= 1");
  VDTNAV_CHECK(std::isfinite(search_leaf), "recovery: search_leaf must be finite");
  VDTNAV_CHECK(std::isfinite(verify_margin) && verify_margin >= 0.0 && verify_margin <= 1.0,
               "recovery: verify_margin must be in [0, 1]");
  VDTNAV_CHECK(std::isfinite(doubt_margin) && doubt_margin >= 0.0,
               "recovery: doubt_margin must be >= 0");
  lost.validate();
  agreement.validate();
}

template <int Dim>
RecoveringLocalizerT<Dim>::RecoveringLocalizerT(std::unique_ptr<TrackerT<Dim>> tracker,
                                                std::unique_ptr<Reacquisition<Dim>> reacquisition,
                                                const LostWatchOptions& options)
    : tracker_(std::move(tracker)),
      reacquisition_(std::move(reacquisition)),
      options_(options),
      detector_(options.lost) {
  VDTNAV_CHECK(tracker_ != nullptr, "recovering localizer: no tracker");
  VDTNAV_CHECK(reacquisition_ != nullptr, "recovering localizer: no reacquisition");
  VDTNAV_CHECK(options_.min_readings >= 0, "recovery: min_readings must be >= 0");
  options_.lost.validate();
}

template <int Dim>
void RecoveringLocalizerT<Dim>::reset(const Pose& pose, const Covariance& covariance) {
  tracker_->reset(pose, covariance);
  detector_.reset();
  reacquisition_->drop();
  lost_scans_ = 0;
}

template <int Dim>
typename RecoveringLocalizerT<Dim>::Result RecoveringLocalizerT<Dim>::update(
    const Odometry& odometry, const Observations& observations) {
  reacquisition_->prepare(lost_scans_);
  Result r = tracker_->update(odometry, observations);
  agreement_ = reacquisition_->weigh(observations, r);
  if (!options_.detect) return r;
  const bool informative = static_cast<int>(observations.size()) >= options_.min_readings;
  ScanAgreement judged;
  if (informative) {
    judged = reacquisition_->judge(observations, r, agreement_);
    detector_.update(judged);
  }
  lost_scans_ = detector_.lost() ? lost_scans_ + 1 : 0;
  // Wrong, or possibly: lost, in doubt, or judged by nothing for a window's length (a track
  // that wandered where the map knows nothing is never contradicted).
  const bool wrong =
      detector_.lost() || detector_.in_doubt() || detector_.unjudged() >= options_.lost.window;
  if (options_.recover && !wrong && detector_.decided()) {
    reacquisition_->drop();  // the map agrees with the track: nothing to replace it with
  } else if (options_.recover && !informative) {
    reacquisition_->follow(odometry);
  } else if (options_.recover) {
    if (std::optional<typename Reacquisition<Dim>::Adopted> a =
            reacquisition_->reacquire(odometry, observations, detector_, wrong, r)) {
      tracker_->reset(a->result.pose, a->covariance);
      detector_.reset();
      reacquisition_->drop();
      lost_scans_ = 0;
      ++recoveries_;
      Result out = std::move(a->result);
      out.work = r.work;
      out.iterations += r.iterations;
      agreement_ = reacquisition_->weigh(observations, out);
      return out;
    }
  }
  // Statuses (docs/localization-2d.md): lost by the window; a converged pose in doubt is refused,
  // not a localization on the map (where doubt_refuses()); a bridged pose (the map does not
  // explain the scan) is refused when in doubt or when the map contradicts the scan itself at the
  // doubt level: a kidnapped robot's first scans bridge to the old place and put their beams
  // through its walls, a gap of the map does not.
  const LostDetectionOptions& lo = detector_.options();
  const bool scan_contradicted = judged.judged() > 0 &&
                                 judged.judged() >= lo.min_judged * judged.readings &&
                                 judged.contradiction() >= lo.doubt_contradiction;
  if (detector_.lost()) {
    r.status = LocalizationStatus::kLost;
  } else if (r.status == LocalizationStatus::kConverged && detector_.in_doubt() &&
             reacquisition_->doubt_refuses()) {
    r.status = LocalizationStatus::kRefused;
  } else if (r.status == LocalizationStatus::kBridged &&
             (detector_.in_doubt() || scan_contradicted)) {
    r.status = LocalizationStatus::kRefused;
    r.has_covariance = false;
  }
  return r;
}

template class RecoveringLocalizerT<2>;
template class RecoveringLocalizerT<3>;

RecoveringLocalizer::RecoveringLocalizer(std::unique_ptr<Localizer2D> tracker, const VdtMap2& map,
                                         const OccupancyGrid<2>& occupancy,
                                         const GlobalLocalizationOptions& global,
                                         const RecoveryOptions& options,
                                         const MapKnowledge& knowledge)
    : RecoveringLocalizerT<2>(
          std::move(tracker),
          std::make_unique<GlobalReacquisition>(map, occupancy, global, options, knowledge),
          LostWatchOptions{options.detect, options.recover, options.min_readings, options.lost}) {}

const GlobalReacquisition& RecoveringLocalizer::global() const noexcept {
  return static_cast<const GlobalReacquisition&>(reacquisition());
}
int RecoveringLocalizer::searches() const noexcept { return global().searches(); }
int RecoveringLocalizer::ambiguous() const noexcept { return global().ambiguous(); }
const std::vector<Pose2>& RecoveringLocalizer::ambiguous_poses() const noexcept {
  return global().ambiguous_poses();
}
bool RecoveringLocalizer::searching() const noexcept { return global().searching(); }
std::size_t RecoveringLocalizer::candidates() const noexcept { return global().candidates(); }

}  // namespace vdtnav
