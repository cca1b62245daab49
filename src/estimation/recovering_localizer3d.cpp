#include "vdtnav/estimation/recovering_localizer3d.hpp"

#include <cmath>

namespace vdtnav {
namespace {

/// Recovery's 3D half (the file comment of recovering_localizer3d.hpp).
class MultiStartReacquisition final : public Reacquisition<3> {
 public:
  explicit MultiStartReacquisition(VdtOptimizationLocalizer3& tracker) : tracker_(&tracker) {}

  void prepare(int lost_scans) override {
    // Re-acquire on lost scans 1, 2, 4, 8 and then every 16th; between them, no multi-start.
    const bool attempt = (lost_scans & (lost_scans - 1)) == 0 || lost_scans % 16 == 0;
    tracker_->set_starts(lost_scans == 0 ? StartSet::kAxes
                         : attempt       ? StartSet::kAttitudeGrid
                                         : StartSet::kNone);
  }

  ScanAgreement weigh(const ObservationSet3& observations, LocalizationResult3& r) override {
    // The tracker's explained fraction (at its solution; 0 when no solve converged): every
    // reading the map does not explain contradicts the pose.
    return ScanAgreement::all_judged(static_cast<int>(observations.size()), r.explained);
  }

  std::optional<Adopted> reacquire(const OdometryStep3&, const ObservationSet3&,
                                   const LostDetector&, bool, LocalizationResult3&) override {
    return std::nullopt;  // the tracker's own multi-start re-acquires (prepare)
  }

  bool doubt_refuses() const override { return false; }

 private:
  VdtOptimizationLocalizer3* tracker_;
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
