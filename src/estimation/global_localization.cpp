#include "vdtnav/estimation/global_localization.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <queue>
#include <random>

#include "vdtnav/core/error.hpp"
#include "vdtnav/core/parallel.hpp"
#include "vdtnav/core/pose2.hpp"
#include "vdtnav/estimation/global_decision.hpp"
#include "vdtnav/estimation/guess_search.hpp"

namespace vdtnav {

namespace {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

bool distinct(const Pose2& a, const Pose2& b, const GlobalLocalizationOptions& o) {
  return (a.head<2>() - b.head<2>()).norm() > o.distinct_distance ||
         std::abs(wrap_angle(a[2] - b[2])) > o.distinct_angle;
}

}  // namespace

void GlobalLocalizationOptions::validate() const {
  VDTNAV_CHECK(std::isfinite(truncation) && truncation > 0.0,
               "global localization: truncation must be > 0");
  VDTNAV_CHECK(max_readings >= 3, "global localization: max_readings must be >= 3");
  VDTNAV_CHECK(std::isfinite(angular_step) && angular_step < kPi,
               "global localization: angular_step must be < pi (<= 0: from the scan)");
  VDTNAV_CHECK(levels <= 12, "global localization: levels must be <= 12");
  VDTNAV_CHECK(candidates >= 1, "global localization: candidates must be >= 1");
  VDTNAV_CHECK(distinct_distance > 0.0 && distinct_angle > 0.0,
               "global localization: distinct_distance and distinct_angle must be > 0");
  VDTNAV_CHECK(alternative_margin >= 0.0 && explained_distance > 0.0 && ambiguity_margin >= 0.0,
               "global localization: margins must be >= 0 and explained_distance > 0");
  VDTNAV_CHECK(accept_fraction > 0.0 && accept_fraction <= 1.0,
               "global localization: accept_fraction must be in (0, 1]");
}

GlobalLocalizer::GlobalLocalizer(const VdtMap2& map, const OccupancyGrid<2>& occupancy,
                                 const GlobalLocalizationOptions& options,
                                 const MapKnowledge& knowledge)
    : map_(&map), options_(options), optimizer_(map, options.optimizer) {
  options_.validate();
  width_ = map.size().x();
  height_ = map.size().y();
  const double h = map.resolution();
  levels_ = options_.levels >= 0 ? options_.levels
                                 : std::max(0, static_cast<int>(std::lround(std::log2(3.2 / h))));
  const float tau2 = static_cast<float>(options_.truncation * options_.truncation);
  const auto& nearest = map.nearest_cells();
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  // The occupancy may be on another grid than the map's (a map sampled from a fitted surface, a
  // different resolution): it is looked up at the map's cell centres.
  const bool same_grid =
      occupancy.size() == map.size() && occupancy.frame().origin() == map.frame().origin() &&
      occupancy.resolution() == h && occupancy.frame().yaw() == map.frame().yaw();
  // Level 0: min(D^2, tau^2) at cell centres, D to the nearest occupied cell's centre.
  std::vector<float> level0(n);
  std::vector<std::uint8_t> free0(n);
  for (std::size_t c = 0; c < n; ++c) {
    const Eigen::Vector2i i = nearest.index_of(static_cast<std::ptrdiff_t>(c));
    const Eigen::Vector2i j = nearest.index_of(nearest[c]);
    const double d2 = (i - j).cast<double>().squaredNorm() * h * h;
    level0[c] = std::min(static_cast<float>(d2), tau2);
    const Eigen::Vector2d p = nearest.cell_center(i);
    bool occupied = true;
    if (same_grid) {
      occupied = occupancy[c] != 0;
    } else {
      const Eigen::Vector2i o = occupancy.cell_of(p);
      occupied = !occupancy.contains(o) || occupancy(o) != 0;
    }
    free0[c] = !occupied && knowledge.known(p) ? 1 : 0;
    if (free0[c] != 0) free_cells_.push_back(static_cast<std::int32_t>(c));
  }
  pooled_.push_back(std::move(level0));
  free_.push_back(std::move(free0));
  // Level k from k-1: the window [c, c + 2^k) is four windows of 2^(k-1).
  for (int k = 1; k <= levels_; ++k) {
    const int half = 1 << (k - 1);
    const std::vector<float>& prev = pooled_.back();
    const std::vector<std::uint8_t>& prev_free = free_.back();
    std::vector<float> cur(n);
    std::vector<std::uint8_t> cur_free(n);
    for (int y = 0; y < height_; ++y) {
      for (int x = 0; x < width_; ++x) {
        float m = tau2;
        std::uint8_t f = 0;
        for (int dy : {0, half}) {
          for (int dx : {0, half}) {
            const int xx = x + dx, yy = y + dy;
            if (xx >= width_ || yy >= height_) continue;
            const std::size_t c = static_cast<std::size_t>(yy) * width_ + xx;
            m = std::min(m, prev[c]);
            f = static_cast<std::uint8_t>(f | prev_free[c]);
          }
        }
        const std::size_t c = static_cast<std::size_t>(y) * width_ + x;
        cur[c] = m;
        cur_free[c] = f;
      }
    }
    pooled_.push_back(std::move(cur));
    free_.push_back(std::move(cur_free));
  }
}

GlobalLocalizer::Readings GlobalLocalizer::select_readings(const ScanPoints& scan) const {
  std::vector<std::size_t> valid;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (scan.points[i].allFinite()) valid.push_back(i);
  }
  Readings r;
  const std::size_t want = static_cast<std::size_t>(options_.max_readings);
  for (std::size_t k = 0; k < std::min(want, valid.size()); ++k) {
    const std::size_t i = valid[k * valid.size() / std::min(want, valid.size())];
    r.points.push_back(scan.points[i]);
    r.ranges.push_back(scan.points[i].norm());
  }
  return r;
}

double GlobalLocalizer::angular_step(const Readings& r, double leaf_size) const {
  if (options_.angular_step > 0.0) return options_.angular_step;
  std::vector<double> ranges = r.ranges;
  const auto p90 = ranges.begin() + static_cast<std::ptrdiff_t>(0.9 * (ranges.size() - 1));
  std::nth_element(ranges.begin(), p90, ranges.end());
  const double step = leaf_size / std::max(*p90, 1e-3);
  return std::clamp(step, 0.25 * kPi / 180.0, 2.0 * kPi / 180.0);
}

void GlobalLocalizer::offsets(const Readings& r, double phi,
                              std::vector<Eigen::Vector2i>* out) const {
  // Robot at a cell centre: the endpoint's continuous index is the cell's plus
  // R(phi - grid yaw) p / h (cell centres at integer indices).
  const Eigen::Matrix2d to_grid = map_->frame().rotation().transpose() *
                                  Eigen::Rotation2Dd(phi).toRotationMatrix() / map_->resolution();
  out->resize(r.points.size());
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    const Eigen::Vector2d u = to_grid * r.points[i];
    (*out)[i] =
        Eigen::Vector2i(static_cast<int>(std::lround(u.x())), static_cast<int>(std::lround(u.y())));
  }
}

double GlobalLocalizer::bound(int level, int cx, int cy, const std::vector<Eigen::Vector2i>& o,
                              double stop_at) const {
  const std::vector<float>& grid = pooled_[static_cast<std::size_t>(level)];
  const float tau2 = static_cast<float>(options_.truncation * options_.truncation);
  const int span = 1 << level;
  double s = 0.0;
  for (const Eigen::Vector2i& d : o) {
    int x = cx + d.x(), y = cy + d.y();
    // Most windows start inside the map: one unsigned comparison per axis, then the sum.
    if (static_cast<unsigned>(x) >= static_cast<unsigned>(width_) ||
        static_cast<unsigned>(y) >= static_cast<unsigned>(height_)) {
      // A window partly outside the map: its inside part (cells outside count tau^2).
      if (x + span <= 0 || y + span <= 0 || x >= width_ || y >= height_) {
        s += tau2;
        if (s > stop_at) return s;
        continue;
      }
      // The pooled grid starts windows at x, y >= 0: a clipped window is a sub-window of the
      // one at 0, whose minimum is no larger — still a lower bound.
      x = std::max(x, 0);
      y = std::max(y, 0);
    }
    s += grid[static_cast<std::size_t>(y) * width_ + x];
    if (s > stop_at) return s;  // a sum of non-negative terms: already past what is kept
  }
  return s;
}

GlobalLocalizationResult GlobalLocalizer::localize(const ScanPoints& scan) const {
  Search search = start(scan);
  search.run();
  return finish(scan, search);
}

GlobalLocalizationResult GlobalLocalizer::localize_better(const ScanPoints& scan, const Pose2& than,
                                                          double margin) const {
  Search search = start(scan, &than, margin);
  search.run();
  return finish(scan, search);
}

GlobalLocalizer::Search GlobalLocalizer::start(const ScanPoints& scan, const Pose2* than,
                                               double margin, int leaf_level) const {
  VDTNAV_CHECK(leaf_level >= 0, "global localization: the leaf level must be >= 0");
  if (than != nullptr) {
    VDTNAV_CHECK(std::isfinite(margin) && margin >= 0.0 && than->allFinite(),
                 "global localization: localize_better needs a finite pose and a margin >= 0");
  }
  const auto t0 = Clock::now();
  Search s;
  s.g_ = this;
  const Readings r = select_readings(scan);
  if (r.points.size() < 3) {  // done at once, no leaves: too few observations (finish())
    s.seconds_ = since(t0);
    return s;
  }
  s.n_tau2_ = static_cast<double>(r.points.size()) * options_.truncation * options_.truncation;
  // localize_better: only leaves scoring below `than`'s own leaf score (its cell, its exact
  // heading) less the margin are searched; none of them: nothing explains the scan better.
  s.cap_ = std::numeric_limits<double>::infinity();
  if (than != nullptr) {
    std::vector<Eigen::Vector2i> o;
    offsets(r, (*than)[2], &o);
    const Eigen::Vector2i c = map_->frame().cell_of(than->head<2>());
    const bool inside = c.x() >= 0 && c.y() >= 0 && c.x() < width_ && c.y() < height_;
    s.cap_ = (inside ? bound(0, c.x(), c.y(), o) : s.n_tau2_) - margin * s.n_tau2_;
    if (s.cap_ < 0.0) {
      s.seconds_ = since(t0);
      return s;
    }
  }
  s.leaf_level_ = std::min(leaf_level, levels_);
  const double leaf_size = map_->resolution() * (1 << s.leaf_level_);
  const int angles = static_cast<int>(std::ceil(2.0 * kPi / angular_step(r, leaf_size) - 1e-9));
  s.offsets_.resize(static_cast<std::size_t>(angles));
  for (int a = 0; a < angles; ++a) offsets(r, a * 2.0 * kPi / angles, &s.offsets_[a]);
  s.step_ = 2.0 * kPi / angles;
  const int span = 1 << levels_;
  for (int y = 0; y < height_; y += span) {
    for (int x = 0; x < width_; x += span) {
      if (free_[levels_][static_cast<std::size_t>(y) * width_ + x] != 0)
        s.root_cells_.emplace_back(x, y);
    }
  }
  s.phase_ = Search::Phase::kRoots;
  s.seconds_ = since(t0);
  return s;
}

std::size_t GlobalLocalizer::Search::children(const Node& node, double stop_at,
                                              std::vector<Node>* out) const {
  const int k = node.level - 1, half = 1 << k;
  std::size_t scored = 0;
  for (int dy : {0, half}) {
    for (int dx : {0, half}) {
      const int cx = node.cx + dx, cy = node.cy + dy;
      if (cx >= g_->width_ || cy >= g_->height_) continue;
      if (g_->free_[k][static_cast<std::size_t>(cy) * g_->width_ + cx] == 0) continue;
      const double lb = g_->bound(k, cx, cy, offsets_[node.angle], stop_at);
      ++scored;
      if (lb <= stop_at) out->push_back({lb, node.angle, k, cx, cy});
    }
  }
  return scored;
}

bool GlobalLocalizer::Search::step(std::size_t boxes) {
  if (done()) return true;
  const auto t0 = Clock::now();
  constexpr std::size_t kMax = std::numeric_limits<std::size_t>::max();
  const std::size_t stop = boxes >= kMax - nodes_ ? kMax : nodes_ + std::max<std::size_t>(boxes, 1);
  const GlobalLocalizer& g = *g_;
  const int levels = g.levels_;
  // 1. The roots: every free box of the coarsest level at every heading, as many as the budget
  // allows, bounded on the pool's threads (each into its own place: the same for any count).
  if (phase_ == Phase::kRoots) {
    const std::size_t cells = root_cells_.size();
    const std::size_t total = cells * offsets_.size();
    const std::size_t count = std::min(total - cursor_, stop - nodes_);
    const std::size_t first = roots_.size();
    roots_.resize(first + count);
    parallel_for_ranges(count, 256, [&](std::size_t k0, std::size_t k1) {
      for (std::size_t k = k0; k < k1; ++k) {
        const std::size_t item = cursor_ + k;
        const int angle = static_cast<int>(item / cells);
        const Eigen::Vector2i& c = root_cells_[item % cells];
        roots_[first + k] = {
            g.bound(levels, c.x(), c.y(), offsets_[static_cast<std::size_t>(angle)]), angle, levels,
            c.x(), c.y()};
      }
    });
    cursor_ += count;
    nodes_ += count;
    if (cursor_ >= total && nodes_ < stop) phase_ = Phase::kGreedy;
  }
  // 2. A first leaf by greedy descent from the best few roots: every leaf worth popping (the best
  // and its alternatives) scores at most its score plus the margin, so nodes bounded above that
  // are never needed, and their bounds stop summing there.
  if (phase_ == Phase::kGreedy) {
    double greedy = std::numeric_limits<double>::infinity();
    std::vector<Node> order = roots_;
    const std::size_t tries = std::min<std::size_t>(order.size(), 16);
    std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(tries),
                      order.end(), [](const Node& a, const Node& b) { return a.lb < b.lb; });
    // The descents on the pool's threads, each into its own place, combined in order.
    std::vector<double> leaf(tries, std::numeric_limits<double>::infinity());
    std::vector<std::size_t> scored(tries, 0);
    parallel_for(tries, [&](std::size_t t) {
      std::vector<Node> kids;
      Node node = order[t];
      while (node.level > leaf_level_) {
        kids.clear();
        scored[t] += children(node, std::numeric_limits<double>::infinity(), &kids);
        if (kids.empty()) break;
        node = *std::min_element(kids.begin(), kids.end(),
                                 [](const Node& a, const Node& b) { return a.lb < b.lb; });
      }
      if (node.level == leaf_level_) leaf[t] = node.lb;
    });
    for (std::size_t t = 0; t < tries; ++t) {
      greedy = std::min(greedy, leaf[t]);
      nodes_ += scored[t];
    }
    limit_ = std::min(greedy + g.options_.alternative_margin * n_tau2_, cap_);
    open_.reset(limit_);  // no box above the limit is ever pushed
    for (const Node& n : roots_) {
      if (n.lb <= limit_) open_.push(n);
    }
    roots_ = std::vector<Node>();
    phase_ = Phase::kBestFirst;
  }
  // 3. Best-first: leaves pop in order of score; keep the best and distinct alternatives. With
  // threads, a search run to its end (run(), localize()) expands inner boxes in batches of 64 a
  // thread (about 1 us each). A step with a budget (a tracker's anytime search) expands them one
  // at a time: a batch scores boxes past the last leaf, and the step a search ends in must not
  // depend on the thread count.
  const std::size_t batch =
      boxes == kMax && threads() > 1 ? 64 * static_cast<std::size_t>(threads()) : 1;
  while (phase_ == Phase::kBestFirst && nodes_ < stop) {
    if (open_.empty() || open_.top().lb > limit_) {
      phase_ = Phase::kDone;
      break;
    }
    const Node node = open_.top();
    open_.pop();
    if (node.level == leaf_level_) {
      // The leaf box's centre (its cells clipped to the map).
      const double half = 0.5 * ((1 << leaf_level_) - 1);
      const Eigen::Vector2d u(std::min(node.cx + half, g.width_ - 1.0),
                              std::min(node.cy + half, g.height_ - 1.0));
      const Eigen::Vector2d p = g.map_->frame().world_point(u);
      const Pose2 pose(p.x(), p.y(), wrap_angle(node.angle * step_));
      bool is_new = true;
      for (const Pose2& q : poses_) is_new = is_new && distinct(pose, q, g.options_);
      if (!is_new) continue;
      if (poses_.empty()) {
        limit_ = std::min(limit_, node.lb + g.options_.alternative_margin * n_tau2_);
        best_score_ = node.lb;
      }
      poses_.push_back(pose);
      if (static_cast<int>(poses_.size()) >= g.options_.candidates) phase_ = Phase::kDone;
      continue;
    }
    // An inner box: it and the inner boxes next in the queue's order (up to `batch`, and before
    // any leaf in the queue) are expanded at once on the pool's threads, their children pushed
    // in order. A leaf is taken only from the top, when every box ordered before it has been
    // expanded, so the leaves come in the one order of their keys (Node::operator<) for any
    // batch. What a batch expands past a leaf its own expansions find is expanded by one thread
    // later too, but for the batches that find the first leaf (which lowers the limit) and the
    // last: a whole run scores at most two batches' boxes more than one thread.
    batch_.assign(1, node);
    while (batch_.size() < batch && !open_.empty() && open_.top().level > leaf_level_ &&
           open_.top().lb <= limit_) {
      batch_.push_back(open_.top());
      open_.pop();
    }
    kids_.resize(batch_.size());
    scored_.assign(batch_.size(), 0);
    parallel_for(batch_.size(), [&](std::size_t b) {
      kids_[b].clear();
      scored_[b] = children(batch_[b], limit_, &kids_[b]);
    });
    for (std::size_t b = 0; b < batch_.size(); ++b) {
      nodes_ += scored_[b];
      for (const Node& k : kids_[b]) open_.push(k);
    }
  }
  if (done()) open_ = BoxQueue();
  seconds_ += since(t0);
  return done();
}

GlobalLocalizationResult GlobalLocalizer::finish(const ScanPoints& scan,
                                                 const Search& search) const {
  const auto t0 = Clock::now();
  GlobalLocalizationResult out;
  if (search.leaves().empty()) {
    // Too few readings to search, or (localize_better) nothing below the cap.
    out.result.status = search.n_tau2_ > 0.0 ? LocalizationStatus::kRefused
                                             : LocalizationStatus::kTooFewObservations;
  } else {
    out = decide(scan, search.leaves());
    out.best_leaf = search.leaves().front();
    out.best_leaf_score = search.best_leaf_score();
  }
  out.nodes = search.nodes();
  out.seconds = search.seconds() + since(t0);
  return out;
}

GlobalLocalizationResult GlobalLocalizer::localize_random(const ScanPoints& scan, double seconds,
                                                          unsigned seed, int min_samples) const {
  const auto t0 = Clock::now();
  GlobalLocalizationResult out;
  const Readings r = select_readings(scan);
  if (r.points.size() < 3 || free_cells_.empty()) {
    out.result.status = LocalizationStatus::kTooFewObservations;
    out.seconds = since(t0);
    return out;
  }
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<std::size_t> cell(0, free_cells_.size() - 1);
  std::uniform_real_distribution<double> heading(-kPi, kPi);
  // The best `candidates` distinct samples (a sample close to a kept one replaces it if better).
  std::vector<std::pair<double, Pose2>> best;
  std::vector<Eigen::Vector2i> o;
  const auto& grid = pooled_[0];
  std::size_t samples = 0;
  while (static_cast<int>(samples) < min_samples || since(t0) < seconds) {
    for (int batch = 0; batch < 64; ++batch, ++samples) {
      const std::int32_t c = free_cells_[cell(rng)];
      const Eigen::Vector2i i(c % width_, c / width_);
      const double phi = heading(rng);
      offsets(r, phi, &o);
      double s = 0.0;
      for (const Eigen::Vector2i& d : o) {
        const int x = i.x() + d.x(), y = i.y() + d.y();
        s += (x < 0 || y < 0 || x >= width_ || y >= height_)
                 ? options_.truncation * options_.truncation
                 : grid[static_cast<std::size_t>(y) * width_ + x];
      }
      const Eigen::Vector2d p = map_->frame().cell_center(i);
      const Pose2 pose(p.x(), p.y(), phi);
      bool merged = false;
      for (auto& b : best) {
        if (!distinct(pose, b.second, options_)) {
          if (s < b.first) b = {s, pose};
          merged = true;
          break;
        }
      }
      if (!merged) best.emplace_back(s, pose);
      std::sort(best.begin(), best.end(),
                [](const auto& a, const auto& b) { return a.first < b.first; });
      if (static_cast<int>(best.size()) > options_.candidates) best.pop_back();
    }
  }
  std::vector<Pose2> starts;
  for (const auto& b : best) starts.push_back(b.second);
  out = decide(scan, starts);
  out.nodes = samples;
  if (!best.empty()) {
    out.best_leaf = best.front().second;
    out.best_leaf_score = best.front().first;
  }
  out.seconds = since(t0);
  return out;
}

GlobalLocalizationResult GlobalLocalizer::decide(const ScanPoints& scan,
                                                 const std::vector<Pose2>& starts) const {
  GlobalDecision<2> d = refine_and_decide<2>(
      optimizer_, scan, starts,
      {options_.truncation, options_.explained_distance, options_.accept_fraction,
       options_.ambiguity_margin},
      [&](const Pose2& a, const Pose2& b) { return distinct(a, b, options_); });
  GlobalLocalizationResult out;
  out.result = std::move(d.result);
  out.ambiguous = d.ambiguous;
  out.alternatives = std::move(d.alternatives);
  out.explained = d.explained;
  return out;
}

}  // namespace vdtnav
