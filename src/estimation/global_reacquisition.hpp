#pragma once
/// \file
/// \brief Recovery's 2D half (recovering_localizer.hpp): scans weighed by tracing them through
/// the map, candidates from an anytime branch and bound over the whole map, each verified beside
/// the track over verify_scans scans before it is adopted.

#include <atomic>
#include <future>
#include <memory>
#include <optional>
#include <vector>

#include "vdtnav/estimation/recovering_localizer.hpp"

namespace vdtnav {

class GlobalReacquisition final : public Reacquisition<2> {
 public:
  /// \throws ConfigError for bad options.
  GlobalReacquisition(const VdtMap2& map, const OccupancyGrid<2>& occupancy,
                      const GlobalLocalizationOptions& global, const RecoveryOptions& options,
                      const MapKnowledge& knowledge);
  ~GlobalReacquisition() override;
  GlobalReacquisition(const GlobalReacquisition&) = delete;
  GlobalReacquisition& operator=(const GlobalReacquisition&) = delete;

  [[nodiscard]] ScanAgreement weigh(const ScanPoints& observations, LocalizationResult& r) override;
  [[nodiscard]] ScanAgreement judge(const ScanPoints& observations, const LocalizationResult& r,
                                    const ScanAgreement& at) override;
  void drop() override;
  void follow(const OdometryStep& odometry) override;
  [[nodiscard]] std::optional<Adopted> reacquire(const OdometryStep& odometry,
                                                 const ScanPoints& observations,
                                                 const LostDetector& detector, bool wrong,
                                                 LocalizationResult& r) override;

  [[nodiscard]] int searches() const noexcept { return searches_; }
  [[nodiscard]] int ambiguous() const noexcept { return ambiguous_; }
  [[nodiscard]] const std::vector<Pose2>& ambiguous_poses() const noexcept {
    return ambiguous_poses_;
  }
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
  /// With `screen`: weighs them on this scan and keeps the clearly better ones (choose()'s test),
  /// without counting the scan towards their verification.
  void verify(const OdometryStep& odometry, const ScanPoints& observations,
              const ScanAgreement& track, bool screen = false);
  /// The best start of a window around `pose` (guess_search.hpp) for the optimizer.
  [[nodiscard]] Pose2 local_start(const ScanPoints& observations, const Pose2& pose) const;
  /// Whether a candidate's agreement `own` is clearly better than the track's over the same
  /// scans (recovering_localizer.hpp).
  [[nodiscard]] bool clearly_better(const ScanAgreement& own, const ScanAgreement& track) const;
  /// The candidate to adopt, if exactly one distinct place passes (recovering_localizer.hpp).
  [[nodiscard]] std::optional<std::size_t> choose();
  /// Starts `search` (in this thread's budget or on the worker, options_.search_thread).
  void start_search(GlobalLocalizer::Search search);
  /// Advances the search by this update's budget (or looks at the worker): the finished search,
  /// if it finished.
  [[nodiscard]] std::optional<GlobalLocalizer::Search> advance_search(LocalizationResult& r);

  const VdtMap2* map_;
  MapKnowledge knowledge_;
  VdtSensorModel model_;  // the agreement at the tracker's estimate
  GlobalLocalizer global_;
  VdtOptimizer optimizer_;  // the candidates' solves
  RecoveryOptions options_;
  ScanAgreement at_;                               // the last scan's, at the tracker's estimate
  std::optional<GlobalLocalizer::Search> search_;  // in the updates' budget
  std::future<GlobalLocalizer::Search> worker_;    // or on the worker thread
  std::shared_ptr<std::atomic<bool>> cancel_;      // tells the worker to stop
  Pose2 since_search_ = Pose2::Zero();             // odometry since the search's scan
  std::vector<Candidate> candidates_;
  std::vector<Pose2> ambiguous_poses_;
  bool doubt_search_ = false;  // the search, and its candidates, are for a better pose in doubt
  int searches_ = 0, ambiguous_ = 0;
};

}  // namespace vdtnav
