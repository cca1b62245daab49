#pragma once
/// \file
/// \brief Never lost for good, never made wrong: a tracking localizer with lost detection
/// (lost_detection.hpp) and re-acquisition — the kidnapped robot — whose update time is bounded.
/// One template over the pose traits, RecoveringLocalizerT<Dim>, runs the window test, the
/// statuses and the adoption for both dimensions; what depends on the space searched is a
/// Reacquisition<Dim> (below; 3D's in recovering_localizer3d.hpp). In 2D, RecoveringLocalizer
/// wraps any 2D tracker (vdt-opt, vdt-ekf, ...) and re-acquires by global localization
/// (global_localization.hpp):
///
/// Each update runs the tracker, then weighs the scan at its estimate (scan_agreement.hpp: what
/// the map explains, contradicts, cannot judge) in the window test. Status kLost only when the
/// map contradicts the window; a scan the map cannot judge (a place the map lacks) keeps the
/// tracker's own status (refused, and its prediction, when it did not match).
///
/// While the window is lost or in doubt, a branch and bound looks for other poses — for a clearly
/// better one than the track (localize_better) in doubt, anywhere when lost — as an anytime
/// computation: each update scores at most `search_boxes` boxes, the search's queue is kept
/// between updates (or, with `search_thread`, it runs on a worker thread), so tracking never
/// waits for it. Its leaves (poses at the scan it started on)
/// are carried forward with the odometry to become candidates. A candidate is then tracked beside
/// the track for `verify_scans` scans (solved on the map from its odometry prediction, the first
/// time from the best pose of a window around it; each scan weighed at its pose), and adopted only
/// when, over those scans, the map judges it, it explains at least global localization's
/// accept_fraction and `verify_margin` more than the track, the map contradicts it at most
/// found_contradiction and (where it judges the track) `verify_margin` less than the track —
/// never on one scan, never while the map agrees with the track (the search and the candidates
/// are dropped once the window is decided below doubt), and never when another distinct candidate
/// passes within the ambiguity margin (an ambiguous place: the loss is kept). In doubt, where the
/// track is likely right, a candidate not clearly better than it on the scan the search finished
/// on, or on its first scan of the verification, is dropped at once.

#include <atomic>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "vdtnav/estimation/global_localization.hpp"
#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/estimation/lost_detection.hpp"
#include "vdtnav/estimation/scan_agreement.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/map/map_knowledge.hpp"
#include "vdtnav/sensor/vdt_sensor_model.hpp"

namespace vdtnav {

/// \brief The localizer interface a tracker of Dim implements: Localizer2D (which also takes a
/// LaserScan) in 2D, Localizer3D in 3D.
template <int Dim>
using TrackerT = std::conditional_t<Dim == 2, Localizer2D, Localizer3D>;

/// \brief What recovery does that depends on the space searched, where 2D and 3D stay apart:
/// how a scan is weighed at a pose and how another pose is found. In 2D the scan is traced
/// through the map (scan_agreement.hpp: explained, contradicted, or where the map knows nothing)
/// and a branch and bound over the whole map (x, y, phi: global_localization.hpp) proposes
/// candidates; in 3D the maps know surfaces, not free space, so a reading contradicts only when
/// its beam passed through a surface (scan_agreement.hpp), and re-acquisition runs on the lost
/// scans 1, 2, 4, 8, ...: multi-start around the prediction (multi_start.hpp), then a branch and
/// bound over the whole map (x, y, z, yaw with roll and pitch from gravity:
/// global_localization3d.hpp; recovering_localizer3d.hpp). The window test, the statuses and the
/// adoption are RecoveringLocalizerT's, shared.
template <int Dim>
class Reacquisition {
 public:
  using Covariance = typename PoseTraits<Dim>::Covariance;
  using Odometry = typename OdometryTraits<Dim>::Step;
  using Observations = ObservationSet<Dim>;
  using Result = LocalizationResultT<Dim>;
  /// A pose to adopt: the result reported, and the covariance the tracker restarts with.
  struct Adopted {
    Result result;
    Covariance covariance;
  };

  virtual ~Reacquisition() = default;
  /// \brief Before the tracker's update, after `lost_scans` updates in a row reported lost.
  virtual void prepare(int lost_scans) { static_cast<void>(lost_scans); }
  /// \brief The scan weighed at the tracker's result (which gains its explained fraction).
  [[nodiscard]] virtual ScanAgreement weigh(const Observations& observations, Result& r) = 0;
  /// \brief What the window test is given: `at` (weighed at the estimate) or what says better
  /// whether the track is wrong.
  [[nodiscard]] virtual ScanAgreement judge(const Observations& observations, const Result& r,
                                            const ScanAgreement& at) {
    static_cast<void>(observations);
    static_cast<void>(r);
    return at;
  }
  /// \brief The map agrees with the track, or the track starts again: nothing to replace it.
  virtual void drop() {}
  /// \brief A scan with too few readings to weigh: what is held follows the odometry.
  virtual void follow(const Odometry& odometry) { static_cast<void>(odometry); }
  /// \brief The track is wrong (`detector` lost, in doubt, or unjudged for a window) or was;
  /// `r` the tracker's result (its work gains what this update ran).
  /// \return a pose to adopt instead of the track, if one is found.
  [[nodiscard]] virtual std::optional<Adopted> reacquire(const Odometry& odometry,
                                                         const Observations& observations,
                                                         const LostDetector& detector, bool wrong,
                                                         Result& r) = 0;
  /// \return whether a window in doubt (not lost) refuses a converged result: where a search for
  /// a clearly better pose runs (2D), a doubted pose is not reported as a localization.
  [[nodiscard]] virtual bool doubt_refuses() const { return true; }
};

/// \brief What the window test and recovery of RecoveringLocalizerT do (the rest is the
/// Reacquisition's).
struct LostWatchOptions {
  bool detect = true;   ///< run the window test and report kLost
  bool recover = true;  ///< while wrong, ask the Reacquisition for another pose
  /// A scan with fewer readings does not enter the window (it says nothing either way).
  int min_readings = 10;
  LostDetectionOptions lost;
};

/// \brief Lost detection and recovery around a tracker of either dimension (the pose traits'):
/// each update runs the tracker, weighs the scan at its estimate (Reacquisition::weigh), feeds
/// the window test (lost_detection.hpp) and, while the window is wrong, lets the Reacquisition
/// look for another pose; one it finds restarts the tracker there (RecoveringLocalizer in 2D,
/// RecoveringLocalizer3 in 3D).
template <int Dim>
class RecoveringLocalizerT : public TrackerT<Dim> {
 public:
  using typename LocalizerT<Dim>::Pose;
  using typename LocalizerT<Dim>::Covariance;
  using typename LocalizerT<Dim>::Odometry;
  using typename LocalizerT<Dim>::Observations;
  using typename LocalizerT<Dim>::Result;

  /// \throws ConfigError for a null tracker or reacquisition, or bad options.
  RecoveringLocalizerT(std::unique_ptr<TrackerT<Dim>> tracker,
                       std::unique_ptr<Reacquisition<Dim>> reacquisition,
                       const LostWatchOptions& options);

  void reset(const Pose& pose, const Covariance& covariance) override;
  using TrackerT<Dim>::update;
  [[nodiscard]] Result update(const Odometry& odometry, const Observations& observations) override;
  [[nodiscard]] std::string name() const override { return tracker_->name(); }

  /// \return candidates adopted (each ended a loss or a doubt).
  [[nodiscard]] int recoveries() const noexcept { return recoveries_; }
  [[nodiscard]] const LostDetector& detector() const noexcept { return detector_; }
  /// \return the last scan's agreement at the reported pose.
  [[nodiscard]] const ScanAgreement& agreement() const noexcept { return agreement_; }

 protected:
  [[nodiscard]] const Reacquisition<Dim>& reacquisition() const noexcept { return *reacquisition_; }

 private:
  std::unique_ptr<TrackerT<Dim>> tracker_;
  std::unique_ptr<Reacquisition<Dim>> reacquisition_;
  LostWatchOptions options_;
  LostDetector detector_;
  ScanAgreement agreement_;
  int lost_scans_ = 0;  ///< updates in a row reported lost
  int recoveries_ = 0;
};

extern template class RecoveringLocalizerT<2>;
extern template class RecoveringLocalizerT<3>;

struct RecoveryOptions {
  /// Run the window test and report kLost (false: the tracker's results pass unchanged).
  bool detect = true;
  /// While lost or in doubt, search for the pose (false: report kLost only, until the window is
  /// found again).
  bool recover = true;
  /// A scan with fewer readings says nothing either way (one reading on a wall is explained
  /// anywhere along it): it does not enter the window.
  int min_readings = 10;
  LostDetectionOptions lost;
  /// How a scan is weighed at a pose (explained, contradicted, unknown).
  ScanAgreementOptions agreement;
  /// Boxes of the branch and bound scored per update: the search's share of an update's time
  /// (0.2-0.4 microseconds a box on the Intel lab's map, ~1.1 on MIT Killian Court's 250 x 240 m:
  /// 30000 boxes cost 6-35 ms).
  int search_boxes = 30000;
  /// Run the search on a worker thread instead (a second core): updates never spend time on it
  /// and a search finishes within a scan period or two, whatever the map; when it finishes
  /// depends on the machine's load, so runs are not repeated bit for bit. search_boxes is unused.
  bool search_thread = false;
  /// The search's leaves: boxes of about this size (metres; at least the map's cell, in powers of
  /// two of it), with headings in steps that move the scan's far readings by as much. The
  /// candidates' solves refine them (the optimizer's coarse levels reach that far).
  double search_leaf = 0.2;
  /// Scans over which a candidate is tracked beside the track before it can be adopted.
  int verify_scans = 3;
  /// Clearly better: over those scans the candidate explains this much more than the track and,
  /// where the map judges the track, is contradicted this much less.
  double verify_margin = 0.2;
  /// In doubt (not lost), the search keeps only poses whose truncated score (global localization's)
  /// is below the track's by this fraction of N tau^2.
  double doubt_margin = 0.1;

  /// \throws ConfigError for values out of range.
  void validate() const;
};

class GlobalReacquisition;

/// \brief A 2D tracker with lost detection and recovery by global localization (see the file
/// comment): RecoveringLocalizerT<2> with the branch and bound's Reacquisition.
class RecoveringLocalizer final : public RecoveringLocalizerT<2> {
 public:
  /// \param tracker the localizer that tracks (owned).
  /// \param map, occupancy must outlive this; occupancy tells where the robot cannot be (any
  ///        grid, looked up at the map's cells).
  /// \param global global localization's options (its optimizer solves the candidates).
  /// \param knowledge where the map knows what is there (default: everywhere inside it).
  /// \throws ConfigError for bad options.
  RecoveringLocalizer(std::unique_ptr<Localizer2D> tracker, const VdtMap2& map,
                      const OccupancyGrid<2>& occupancy, const GlobalLocalizationOptions& global,
                      const RecoveryOptions& options = {}, const MapKnowledge& knowledge = {});

  /// \return searches finished, and verifications in which two distinct candidates passed.
  [[nodiscard]] int searches() const noexcept;
  [[nodiscard]] int ambiguous() const noexcept;
  /// \return the candidates that passed together in the last ambiguous verification.
  [[nodiscard]] const std::vector<Pose2>& ambiguous_poses() const noexcept;
  /// \return whether a search is in progress, and how many candidates are being verified.
  [[nodiscard]] bool searching() const noexcept;
  [[nodiscard]] std::size_t candidates() const noexcept;

 private:
  [[nodiscard]] const GlobalReacquisition& global() const noexcept;
};

}  // namespace vdtnav
