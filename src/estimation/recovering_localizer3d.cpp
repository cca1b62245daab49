#include "vdtnav/estimation/recovering_localizer3d.hpp"

#include <cmath>
#include <memory>

namespace vdtnav {
namespace {

/// How much more of the scan a pose found while in doubt must explain than the track to replace it
/// (2D's candidates: 0.2 more than the track, recovering_localizer.hpp).
constexpr double kDoubtMargin = 0.2;

/// Recovery's 3D half (the file comment of recovering_localizer3d.hpp).
class MultiStartReacquisition final : public Reacquisition<3> {
 public:
  explicit MultiStartReacquisition(VdtOptimizationLocalizer3& tracker) : tracker_(&tracker) {}

  void prepare(int lost_scans) override {
    // Re-acquire on lost scans 1, 2, 4, 8 and then every 16th; between them, no multi-start.
    attempt_ = lost_scans > 0 && ((lost_scans & (lost_scans - 1)) == 0 || lost_scans % 16 == 0);
    tracker_->set_starts(lost_scans == 0 ? StartSet::kAxes
                         : attempt_      ? StartSet::kAttitudeGrid
                                         : StartSet::kNone);
  }

  ScanAgreement weigh(const ObservationSet3& observations, LocalizationResult3& r) override {
    // At the estimate reported (a refused scan's: the prediction): explained, contradicted (the
    // beam passed through a surface of the map) or unknown (scan_agreement.hpp). A point-cloud map
    // lacks much of what a scan 3 m further on sees; those readings contradict nothing.
    ScanAgreementOptions a;
    a.explained_distance = tracker_->options().explained_distance;
    return scan_agreement(tracker_->optimizer().sensor_model(), observations, r.pose, a);
  }

  void drop() override { doubt_scans_ = 0; }

  std::optional<Adopted> reacquire(const OdometryStep3& odometry,
                                   const ObservationSet3& observations,
                                   const LostDetector& detector, bool,
                                   LocalizationResult3& r) override {
    // The tracker's own multi-start ran (prepare); on the re-acquiring scans, while the track
    // explains less than the acceptance, global localization searches the whole map too, with
    // roll and pitch from the IMU (or the track's), and a pose it accepts is adopted. In doubt
    // (the window's contradiction risen above the track's own: lost_detection.hpp), the same
    // search runs on doubted scans 1, 2, 4, 8, then every 16th, and its pose is adopted only if it
    // explains kDoubtMargin more of the scan than the track does.
    const bool doubted = detector.in_doubt() && !detector.lost();
    doubt_scans_ = doubted ? doubt_scans_ + 1 : 0;
    const bool doubt_attempt =
        doubted && ((doubt_scans_ & (doubt_scans_ - 1)) == 0 || doubt_scans_ % 16 == 0);
    const VdtLocalizer3Options& o = tracker_->options();
    if (!(attempt_ || doubt_attempt) || !o.global_recovery ||
        r.explained >= o.global.accept_fraction) {
      return std::nullopt;
    }
    if (!global_) {  // built at the first loss: its pyramid costs ~1 s and ~50 MB on CATEC
      GlobalLocalization3Options g = o.global;
      g.optimizer = o.optimizer;
      global_ = std::make_unique<GlobalLocalizer3>(tracker_->optimizer().sensor_model().map(), g);
    }
    const Eigen::Vector3d rpy = rpy_of(r.pose.linear());
    const double roll = odometry.has_attitude() ? odometry.roll : rpy.x();
    const double pitch = odometry.has_attitude() ? odometry.pitch : rpy.y();
    const GlobalLocalization3Result found = global_->localize(observations, roll, pitch);
    r.work.solves += found.result.work.solves;
    if (found.result.status != LocalizationStatus::kConverged) return std::nullopt;
    if (!attempt_ && !(found.explained >= r.explained + kDoubtMargin)) return std::nullopt;
    Adopted a{found.result, found.result.covariance};
    return a;
  }

  // A pose in doubt is not reported as a localization (as in 2D): refused until the window
  // agrees with the track again or the search finds a clearly better pose.
  bool doubt_refuses() const override { return true; }

 private:
  VdtOptimizationLocalizer3* tracker_;
  bool attempt_ = false;
  int doubt_scans_ = 0;  ///< updates in a row in doubt (not lost)
  std::unique_ptr<GlobalLocalizer3> global_;
};

LostWatchOptions watch(const VdtLocalizer3Options& o) {
  LostWatchOptions w;
  w.min_readings = 0;  // every scan enters the window (the file comment)
  w.lost = o.lost;
  return w;
}

}  // namespace

RecoveringLocalizer3::RecoveringLocalizer3(const VdtField3& map,
                                           const VdtLocalizer3Options& options)
    : RecoveringLocalizer3(new VdtOptimizationLocalizer3(map, options)) {}

RecoveringLocalizer3::RecoveringLocalizer3(const VdtOptimizer3& shared,
                                           const VdtLocalizer3Options& options)
    : RecoveringLocalizer3(new VdtOptimizationLocalizer3(shared, options)) {}

RecoveringLocalizer3::RecoveringLocalizer3(VdtOptimizationLocalizer3* tracker)
    : RecoveringLocalizerT<3>(std::unique_ptr<Localizer3D>(tracker),
                              std::make_unique<MultiStartReacquisition>(*tracker),
                              watch(tracker->options())),
      tracker_(tracker) {}

}  // namespace vdtnav
