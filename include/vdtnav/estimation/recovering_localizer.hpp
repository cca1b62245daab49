#pragma once
/// \file
/// \brief Never lost for good, never made wrong: any 2D tracking localizer (vdt-opt, vdt-ekf, ...)
/// with lost detection (lost_detection.hpp) and re-acquisition by global localization
/// (global_localization.hpp) — the kidnapped robot — whose update time is bounded.
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
/// passes within the ambiguity margin (an ambiguous place: the loss is kept).

#include <atomic>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vdtnav/estimation/global_localization.hpp"
#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/estimation/lost_detection.hpp"
#include "vdtnav/estimation/scan_agreement.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/map/map_knowledge.hpp"
#include "vdtnav/sensor/vdt_sensor_model.hpp"

namespace vdtnav {

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

/// \brief A tracker with lost detection and recovery (see the file comment).
class RecoveringLocalizer final : public Localizer2D {
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

  ~RecoveringLocalizer() override;
  RecoveringLocalizer(const RecoveringLocalizer&) = delete;
  RecoveringLocalizer& operator=(const RecoveringLocalizer&) = delete;

  void reset(const Pose2& pose, const Eigen::Matrix3d& covariance) override;
  using Localizer2D::update;
  [[nodiscard]] LocalizationResult update(const OdometryStep& odometry,
                                          const ScanPoints& observations) override;
  [[nodiscard]] std::string name() const override { return tracker_->name(); }

  /// \return candidates adopted (each ended a loss or a doubt).
  [[nodiscard]] int recoveries() const noexcept { return recoveries_; }
  /// \return searches finished, and verifications in which two distinct candidates passed.
  [[nodiscard]] int searches() const noexcept { return searches_; }
  [[nodiscard]] int ambiguous() const noexcept { return ambiguous_; }
  /// \return the candidates that passed together in the last ambiguous verification.
  [[nodiscard]] const std::vector<Pose2>& ambiguous_poses() const noexcept {
    return ambiguous_poses_;
  }
  [[nodiscard]] const LostDetector& detector() const noexcept { return detector_; }
  /// \return the last scan's agreement at the reported pose.
  [[nodiscard]] const ScanAgreement& agreement() const noexcept { return agreement_; }
  /// \return whether a search is in progress, and how many candidates are being verified.
  [[nodiscard]] bool searching() const noexcept { return search_.has_value() || worker_.valid(); }
  [[nodiscard]] std::size_t candidates() const noexcept { return candidates_.size(); }

 private:
  struct Candidate {
    Pose2 pose = Pose2::Zero();
    LocalizationResult last;   // its last solve
    int scans = 0;             // scans it was weighed on
    ScanAgreement own, track;  // summed over those scans: at its poses, at the track's
  };
  /// Solves the candidates on this scan and weighs them; drops the failed and the contradicted.
  void verify(const OdometryStep& odometry, const ScanPoints& observations,
              const ScanAgreement& track);
  /// The best start of a window around `pose` (guess_search.hpp) for the optimizer.
  [[nodiscard]] Pose2 local_start(const ScanPoints& observations, const Pose2& pose) const;
  /// The agreement the window weighs: agreement_ (at the estimate) or, when that is in doubt,
  /// at the pose the optimizer reaches from the estimate, if less contradicted.
  [[nodiscard]] ScanAgreement near_agreement(const ScanPoints& observations, const Pose2& estimate);
  /// The candidate to adopt, if exactly one distinct place passes (file comment).
  [[nodiscard]] std::optional<std::size_t> choose();
  void drop_search();
  /// Starts `search` (in this thread's budget or on the worker, options_.search_thread).
  void start_search(GlobalLocalizer::Search search);
  /// Advances the search by this update's budget (or looks at the worker): the finished search,
  /// if it finished.
  [[nodiscard]] std::optional<GlobalLocalizer::Search> advance_search(LocalizationResult& r);

  std::unique_ptr<Localizer2D> tracker_;
  const VdtMap2* map_;
  MapKnowledge knowledge_;
  VdtSensorModel model_;  // the agreement at the tracker's estimate
  GlobalLocalizer global_;
  VdtOptimizer optimizer_;  // the candidates' solves
  RecoveryOptions options_;
  LostDetector detector_;
  ScanAgreement agreement_;
  std::optional<GlobalLocalizer::Search> search_;  // in the updates' budget
  std::future<GlobalLocalizer::Search> worker_;    // or on the worker thread
  std::shared_ptr<std::atomic<bool>> cancel_;      // tells the worker to stop
  Pose2 since_search_ = Pose2::Zero();             // odometry since the search's scan
  std::vector<Candidate> candidates_;
  std::vector<Pose2> ambiguous_poses_;
  int recoveries_ = 0, searches_ = 0, ambiguous_ = 0;
};

}  // namespace vdtnav
