#include "global_reacquisition.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/guess_search.hpp"

namespace vdtnav {

namespace {

bool distinct(const Pose2& a, const Pose2& b, const GlobalLocalizationOptions& o) {
  return (a.head<2>() - b.head<2>()).norm() > o.distinct_distance ||
         std::abs(wrap_angle(a[2] - b[2])) > o.distinct_angle;
}

}  // namespace

GlobalReacquisition::GlobalReacquisition(const VdtMap2& map, const OccupancyGrid<2>& occupancy,
                                         const GlobalLocalizationOptions& global,
                                         const RecoveryOptions& options,
                                         const MapKnowledge& knowledge)
    : map_(&map),
      knowledge_(knowledge),
      model_(map, global.optimizer.sensor),
      global_(map, occupancy, global, knowledge),
      optimizer_(map, global.optimizer),
      options_(options) {
  options_.validate();
}

GlobalReacquisition::~GlobalReacquisition() { drop(); }

void GlobalReacquisition::drop() {
  if (worker_.valid()) {
    cancel_->store(true, std::memory_order_relaxed);
    worker_.wait();  // within a chunk of boxes
    worker_ = {};
  }
  search_.reset();
  candidates_.clear();
}

ScanAgreement GlobalReacquisition::weigh(const ScanPoints& observations, LocalizationResult& r) {
  at_ = scan_agreement(model_, *map_, knowledge_, observations, r.pose, options_.agreement);
  r.explained = at_.explained_fraction();
  return at_;
}

void GlobalReacquisition::follow(const OdometryStep& odometry) {
  // Nothing to weigh: the candidates and the search's leaves follow the odometry.
  for (Candidate& c : candidates_) c.pose = compose(c.pose, odometry.delta);
  if (searching()) since_search_ = compose(since_search_, odometry.delta);
}

void GlobalReacquisition::start_search(GlobalLocalizer::Search search) {
  if (!options_.search_thread) {
    search_ = std::move(search);
    return;
  }
  cancel_ = std::make_shared<std::atomic<bool>>(false);
  worker_ = std::async(std::launch::async, [s = std::move(search), cancel = cancel_]() mutable {
    // Chunks of boxes between looks at the flag: a cancelled search stops within one.
    constexpr std::size_t kChunk = 10000;
    while (!s.step(kChunk) && !cancel->load(std::memory_order_relaxed)) {
    }
    return std::move(s);
  });
}

std::optional<GlobalLocalizer::Search> GlobalReacquisition::advance_search(LocalizationResult& r) {
  if (worker_.valid()) {
    if (worker_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return std::nullopt;
    return worker_.get();
  }
  if (!search_) return std::nullopt;
  const std::size_t before = search_->nodes();
  search_->step(static_cast<std::size_t>(options_.search_boxes));
  r.work.search_boxes = static_cast<int>(search_->nodes() - before);
  if (!search_->done()) return std::nullopt;
  std::optional<GlobalLocalizer::Search> done = std::move(search_);
  search_.reset();
  return done;
}

void GlobalReacquisition::verify(const OdometryStep& odometry, const ScanPoints& observations,
                                 const ScanAgreement& track, bool screen) {
  const LostDetectionOptions& lo = options_.lost;
  std::vector<Candidate> kept;
  for (Candidate& c : candidates_) {
    // Its first solve starts from the best pose of a window around the prediction: the leaf is
    // a box and a heading step, carried forward by the odometry of the search's scans.
    Pose2 start = compose(c.pose, odometry.delta);
    if (c.scans == 0) start = local_start(observations, start);
    c.last = optimizer_.solve(observations, start);
    if (c.last.status == LocalizationStatus::kDiverged) continue;
    c.pose = c.last.pose;
    const ScanAgreement a =
        scan_agreement(model_, *map_, knowledge_, observations, c.pose, options_.agreement);
    c.last.explained = a.explained_fraction();
    if (screen) {  // weighed, not counted: kept only if clearly better on this scan
      if (clearly_better(a, track)) kept.push_back(std::move(c));
      continue;
    }
    c.own += a;
    c.track += track;
    ++c.scans;
    // Contradicted as a lost track would be: not the place.
    const bool judged = c.own.judged() > 0 && c.own.judged() >= lo.min_judged * c.own.readings;
    if (c.scans >= 2 && judged && c.own.contradiction() >= lo.lost_contradiction) continue;
    // In doubt the track is likely right and is withheld while candidates are verified: one that
    // is not clearly better on its first scan (choose()'s test on that scan) goes at once.
    if (doubt_search_ && c.scans == 1 && !clearly_better(c.own, c.track)) continue;
    kept.push_back(std::move(c));
  }
  candidates_ = std::move(kept);
}

Pose2 GlobalReacquisition::local_start(const ScanPoints& observations, const Pose2& pose) const {
  // Half a distinct pose's distance and angle each way: what the optimizer's basin cannot span.
  GuessSearchOptions w;
  w.window_xy = 0.5 * global_.options().distinct_distance;
  w.window_yaw = 0.5 * global_.options().distinct_angle;
  w.steps_xy = 5;
  w.steps_yaw = 21;
  w.max_beams = 120;
  w.truncation = global_.options().truncation;
  return search_guess(model_, observations, pose, w);
}

ScanAgreement GlobalReacquisition::judge(const ScanPoints& observations,
                                         const LocalizationResult& r, const ScanAgreement& at) {
  if (at.contradiction() < options_.lost.doubt_contradiction) return at;
  // A tracking error the tracker may still correct (a heading off by a few degrees puts the far
  // readings through walls) is not a lost track: weigh the pose the map's optimizer reaches from
  // the best start of a window around the estimate (a distinct pose's half-widths), and keep the
  // less contradicted.
  const LocalizationResult near = optimizer_.solve(observations, local_start(observations, r.pose));
  if (near.status == LocalizationStatus::kDiverged ||
      distinct(near.pose, r.pose, global_.options())) {
    return at;
  }
  const ScanAgreement a =
      scan_agreement(model_, *map_, knowledge_, observations, near.pose, options_.agreement);
  return a.contradiction() < at.contradiction() ? a : at;
}

bool GlobalReacquisition::clearly_better(const ScanAgreement& own,
                                         const ScanAgreement& track) const {
  const LostDetectionOptions& lo = options_.lost;
  const auto judged = [&](const ScanAgreement& a) {
    return a.judged() > 0 && a.judged() >= lo.min_judged * a.readings;
  };
  // The place must be one the map knows: explained as global localization accepts a scan,
  // and as little contradicted as a found track; and clearly better than the track: explaining
  // more by verify_margin and, where the map judges the track, contradicted less by as much.
  const double e = own.explained_fraction(), m = options_.verify_margin;
  return judged(own) && e >= global_.options().accept_fraction &&
         own.contradiction() <= lo.found_contradiction && e >= track.explained_fraction() + m &&
         (!judged(track) || own.contradiction() <= track.contradiction() - m);
}

std::optional<std::size_t> GlobalReacquisition::choose() {
  std::vector<std::size_t> passed;
  bool pending = false;
  for (std::size_t k = 0; k < candidates_.size(); ++k) {
    const Candidate& c = candidates_[k];
    if (c.scans < options_.verify_scans) {
      pending = true;
      continue;
    }
    if (clearly_better(c.own, c.track)) passed.push_back(k);
  }
  if (pending) return std::nullopt;  // every candidate is judged on the same scans
  if (passed.empty()) {              // none is the place (or none could be judged yet)
    candidates_.clear();
    return std::nullopt;
  }
  // The least contradicted; another distinct one that passes within global localization's
  // ambiguity margin of it makes the place ambiguous.
  std::size_t best = passed.front();
  for (std::size_t k : passed) {
    if (candidates_[k].own.contradiction() < candidates_[best].own.contradiction()) best = k;
  }
  const GlobalLocalizationOptions& go = global_.options();
  for (std::size_t k : passed) {
    if (distinct(candidates_[k].pose, candidates_[best].pose, go) &&
        candidates_[k].own.contradiction() <=
            candidates_[best].own.contradiction() + go.ambiguity_margin) {
      ++ambiguous_;
      ambiguous_poses_.clear();
      for (std::size_t j : passed) ambiguous_poses_.push_back(candidates_[j].pose);
      candidates_.clear();
      return std::nullopt;
    }
  }
  return best;
}

std::optional<GlobalReacquisition::Adopted> GlobalReacquisition::reacquire(
    const OdometryStep& odometry, const ScanPoints& observations, const LostDetector& detector,
    bool wrong, LocalizationResult& r) {
  // 1. The candidates on this scan, beside the track.
  if (!candidates_.empty()) {
    r.work.candidates = static_cast<int>(candidates_.size());
    verify(odometry, observations, at_);
    if (const std::optional<std::size_t> k = choose()) {
      const Candidate& c = candidates_[*k];
      const double h = map_->resolution();
      Adopted out{c.last, c.last.has_covariance
                              ? c.last.covariance
                              : Eigen::Vector3d(h * h, h * h, 1e-4).asDiagonal().toDenseMatrix()};
      return out;
    }
  }
  // 2. The search: started on this scan when there is none and nothing to verify (anywhere
  // when lost, clearly better than the track in doubt), advanced by the budget.
  if (searching()) {
    since_search_ = compose(since_search_, odometry.delta);
  } else if (candidates_.empty() && wrong) {
    const int leaf = static_cast<int>(
        std::floor(std::log2(std::max(1.0, options_.search_leaf / map_->resolution())) + 1e-9));
    doubt_search_ = !detector.lost();
    start_search(doubt_search_ ? global_.start(observations, &r.pose, options_.doubt_margin, leaf)
                               : global_.start(observations, nullptr, 0.0, leaf));
    since_search_ = Pose2::Zero();
  }
  if (const std::optional<GlobalLocalizer::Search> done = advance_search(r)) {
    ++searches_;
    r.work.global_searches = 1;
    // The leaves are poses at the search's scan: carried forward by the odometry since.
    for (const Pose2& leaf : done->leaves()) {
      Candidate c;
      c.pose = compose(leaf, since_search_);
      if (distinct(c.pose, r.pose, global_.options())) candidates_.push_back(c);
    }
    // In doubt, the candidates are screened on this scan at once (those not clearly better than
    // the track go, as on their first scan) — a screen, not a scan of their verification, which
    // the search's own scan cannot be.
    if (doubt_search_ && !candidates_.empty()) {
      r.work.candidates = static_cast<int>(candidates_.size());
      verify(OdometryStep{}, observations, at_, /*screen=*/true);
    }
  }
  return std::nullopt;
}

}  // namespace vdtnav
