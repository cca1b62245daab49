#pragma once
/// \file
/// \brief The pose of one scan with no prior on a 2D VDT map: branch and bound over (x, y, phi),
/// and LaMa's random sampling for comparison.
///
/// The score of a pose is the truncated VCD  S = sum_i min(D(q_i)^2, tau^2)  of N readings of
/// the scan, D the distance from an endpoint's cell to the nearest occupied cell (exact at cell
/// centres: the VDT's stored nearest cells). Headings are taken in steps small enough that the
/// scan's far readings move by about a cell; for each heading the readings' cell offsets are
/// integers, and over a box of 2^k x 2^k robot cells the smallest distance an endpoint can have is
/// the minimum of D over a 2^k window — a pyramid of min-pooled grids, built once per map, makes
/// that a lookup, so  LB = sum_i min(M_k(c + o_i)^2, tau^2)  is an exact lower bound of S over the
/// box (the distance field is 1-Lipschitz; the pooling is its tightest form on the grid). Boxes
/// are expanded best-first: the first leaf popped is the best cell-and-heading pose of the whole
/// map, and the leaves popped after it come in order of score — the distinct ones among them are
/// the alternatives. The best few are refined by the VDT optimizer; the result is refused when the
/// refined best leaves the scan unexplained or when a distinct alternative explains it as well
/// (a symmetric building: the ambiguity is reported, not guessed).

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/map/grid.hpp"
#include "vdtnav/map/map_knowledge.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/sensor/laser_scan.hpp"

namespace vdtnav {

struct GlobalLocalizationOptions {
  /// tau, metres: a reading farther than this from the map counts tau^2 (unexplained).
  double truncation = 0.3;
  /// Readings scored, evenly over the scan's valid ones (the refinement uses them all).
  int max_readings = 120;
  /// Radians between headings; <= 0: resolution / r90 (r90 the scan's 90th-percentile range:
  /// its far readings move by a cell), clamped into [0.25, 2] degrees.
  double angular_step = -1.0;
  /// The coarsest box is 2^levels cells on a side; < 0: about 3.2 m.
  int levels = -1;
  /// Distinct candidates refined by the optimizer (the best and its alternatives).
  int candidates = 6;
  /// Two poses are distinct when this far apart (metres) or this much turned (radians).
  double distinct_distance = 1.0;
  double distinct_angle = 0.5;
  /// Alternatives are looked for among leaves scoring at most best + this fraction of N tau^2.
  double alternative_margin = 0.15;
  /// A reading is explained when its disparity is below this (metres).
  double explained_distance = 0.1;
  /// The refined best must explain this fraction of the scan, else kRefused.
  double accept_fraction = 0.75;
  /// Ambiguous when a distinct refined alternative explains at least the best's fraction less
  /// this (and passes accept_fraction itself).
  double ambiguity_margin = 0.05;
  /// The refinement (its defaults: the optimizer's, with its coarse levels).
  VdtOptimizerOptions optimizer;

  /// \throws ConfigError for values out of range.
  void validate() const;
};

/// \brief What a global localization found.
struct GlobalLocalizationResult {
  /// The refined best pose and covariance; status kConverged when accepted, kRefused when the
  /// scan is unexplained or the pose ambiguous, kTooFewObservations for a scan without readings.
  LocalizationResult result;
  bool ambiguous = false;
  std::vector<Pose2> alternatives;  ///< distinct refined poses that explain the scan as well
  double explained = 0.0;           ///< fraction of the scan the best explains
  std::size_t nodes = 0;            ///< boxes scored (branch and bound) or poses (sampling)
  /// The best cell-and-heading pose of the search (before refinement) and its score
  /// sum_i min(D_i^2, tau^2) over the scored readings.
  Pose2 best_leaf = Pose2::Zero();
  double best_leaf_score = 0.0;
  double seconds = 0.0;  ///< wall time of the search and the refinement
};

/// \brief Global localization on one map (see the file comment). Thread-compatible: localize()
/// is const.
class GlobalLocalizer {
 public:
  class Search;

  /// \param map must outlive the localizer (and every Search it starts).
  /// \param occupancy where the robot cannot be: the map's occupied cells, on any grid (looked up
  ///        at the map's cell centres; outside it, nowhere).
  /// \param knowledge where the map knows what is there: the robot is placed in known free cells
  ///        only (default: every free cell).
  /// \throws ConfigError for bad options.
  GlobalLocalizer(const VdtMap2& map, const OccupancyGrid<2>& occupancy,
                  const GlobalLocalizationOptions& options = {},
                  const MapKnowledge& knowledge = {});

  /// \brief Branch and bound.
  [[nodiscard]] GlobalLocalizationResult localize(const ScanPoints& scan) const;

  /// \brief Branch and bound for a pose that explains the scan clearly better than `than`: only
  /// leaves scoring below than's own score (at its cell and exact heading) less
  /// margin * N tau^2 are searched, so that where `than` is as good as anything (a tracker that
  /// is right) nearly every box is pruned at once. Status kRefused with no pose when there is
  /// none; otherwise the refinement and acceptance of localize().
  /// \throws ConfigError for a non-finite pose or a negative margin.
  [[nodiscard]] GlobalLocalizationResult localize_better(const ScanPoints& scan, const Pose2& than,
                                                         double margin) const;

  /// \brief The branch and bound of localize() (or, with `than`, of localize_better()) as an
  /// anytime computation: Search::step() scores at most a given number of boxes, so that a
  /// tracker can spread a search over many scans; finish() refines and decides as localize().
  /// \param leaf_level the search stops at boxes of 2^leaf_level cells (0: single cells), whose
  ///        centres are the leaves, and takes headings in steps for that size: a coarser search
  ///        whose leaves the optimizer's coarse levels still refine.
  /// \throws ConfigError as localize_better() when `than` is given, or for a negative leaf_level.
  [[nodiscard]] Search start(const ScanPoints& scan, const Pose2* than = nullptr,
                             double margin = 0.0, int leaf_level = 0) const;
  /// \brief The refinement and acceptance of the leaves of a finished search (its scan).
  [[nodiscard]] GlobalLocalizationResult finish(const ScanPoints& scan, const Search& search) const;

  /// \brief LaMa's way: poses drawn uniformly over the free cells and headings, each scored as
  /// a leaf, until `seconds` of wall time (at least `min_samples`), then the same refinement and
  /// acceptance.
  [[nodiscard]] GlobalLocalizationResult localize_random(const ScanPoints& scan, double seconds,
                                                         unsigned seed,
                                                         int min_samples = 100) const;

  [[nodiscard]] const GlobalLocalizationOptions& options() const noexcept { return options_; }
  [[nodiscard]] const VdtMap2& map() const noexcept { return *map_; }
  /// \return the cells where the robot may be placed (known free cells of the map's grid).
  [[nodiscard]] std::size_t free_cells() const noexcept { return free_cells_.size(); }

 private:
  struct Readings {  // the scored readings: robot-frame points and ranges
    std::vector<Eigen::Vector2d> points;
    std::vector<double> ranges;
  };
  [[nodiscard]] Readings select_readings(const ScanPoints& scan) const;
  /// Headings for leaves of `leaf_size` metres.
  [[nodiscard]] double angular_step(const Readings& r, double leaf_size) const;
  /// Cell offsets of the readings at heading phi (grid axes).
  void offsets(const Readings& r, double phi, std::vector<Eigen::Vector2i>* out) const;
  /// Truncated score of box (level, cx, cy) with the given offsets; stops summing (returning
  /// a value above it) once past stop_at.
  [[nodiscard]] double bound(int level, int cx, int cy, const std::vector<Eigen::Vector2i>& o,
                             double stop_at = std::numeric_limits<double>::infinity()) const;
  /// Refines the leaves (distinct, best first) and decides.
  [[nodiscard]] GlobalLocalizationResult decide(const ScanPoints& scan,
                                                const std::vector<Pose2>& starts) const;

  const VdtMap2* map_;
  GlobalLocalizationOptions options_;
  VdtOptimizer optimizer_;
  int levels_ = 0;
  int width_ = 0, height_ = 0;
  /// pooled_[k](x, y) = min over the 2^k window from (x, y) of min(D^2, tau^2) (cells outside
  /// the map count tau^2); free_[k] = whether the window holds a free cell.
  std::vector<std::vector<float>> pooled_;
  std::vector<std::vector<std::uint8_t>> free_;
  std::vector<std::int32_t> free_cells_;
};

/// \brief One branch and bound in progress (GlobalLocalizer::start): the boxes scored so far, the
/// queue of those still open, the leaves found. Holds its localizer by pointer: it must outlive
/// the search.
class GlobalLocalizer::Search {
 public:
  Search() = default;

  /// \brief Scores at most `boxes` more boxes (at least one step of the search's current phase).
  /// \return done().
  bool step(std::size_t boxes);
  /// \brief step() until done.
  void run() { step(std::numeric_limits<std::size_t>::max()); }

  [[nodiscard]] bool done() const noexcept { return phase_ == Phase::kDone; }
  /// \return boxes scored so far.
  [[nodiscard]] std::size_t nodes() const noexcept { return nodes_; }
  /// \return the distinct leaves found (best first; complete once done()): the centres of the
  /// leaf boxes and headings of the search's grid.
  [[nodiscard]] const std::vector<Pose2>& leaves() const noexcept { return poses_; }
  /// \return the best leaf's score sum_i min(D_i^2, tau^2) (NaN before one is found).
  [[nodiscard]] double best_leaf_score() const noexcept { return best_score_; }
  /// \return wall time spent in step() so far, seconds.
  [[nodiscard]] double seconds() const noexcept { return seconds_; }

 private:
  friend class GlobalLocalizer;
  enum class Phase { kRoots, kGreedy, kBestFirst, kDone };
  struct Node {
    double lb;
    int angle, level, cx, cy;
    /// The heap's order, a min-heap of the key (lb, -level, angle, cy, cx): a total order in
    /// which a box comes after its parent (lb never lower, level lower), so that the leaves come
    /// in one order whatever the order of the expansions between them.
    bool operator<(const Node& o) const {
      if (lb != o.lb) return lb > o.lb;
      if (level != o.level) return level < o.level;
      if (angle != o.angle) return angle > o.angle;
      if (cy != o.cy) return cy > o.cy;
      return cx > o.cx;
    }
  };
  /// The open boxes, taken in the order of Node::operator<: buckets of lb (a child never falls
  /// below its parent's), the lowest nonempty one a heap, the others plain lists made heaps when
  /// they become the lowest. A push is an append but in the lowest bucket: not the log n of one
  /// heap of every open box (a tenth of a search's time with one heap).
  class BoxQueue {
   public:
    /// Empties the queue for bounds in [0, max_lb].
    void reset(double max_lb) {
      buckets_.assign(kBuckets, {});
      scale_ = kBuckets / std::max(max_lb, 1e-300);
      current_ = 0;
      size_ = 0;
      heaped_ = false;
    }
    [[nodiscard]] bool empty() const noexcept { return size_ == 0; }
    /// The first box (not empty()).
    [[nodiscard]] const Node& top() {
      settle();
      return buckets_[current_].front();
    }
    void pop() {
      settle();
      std::vector<Node>& b = buckets_[current_];
      std::pop_heap(b.begin(), b.end());
      b.pop_back();
      --size_;
    }
    void push(const Node& n) {
      const std::size_t k = std::min<std::size_t>(
          kBuckets - 1, static_cast<std::size_t>(std::max(0.0, n.lb * scale_)));
      if (k < current_) {  // not for a child; kept correct anyway
        current_ = k;
        heaped_ = false;
      }
      std::vector<Node>& b = buckets_[k];
      b.push_back(n);
      if (k == current_ && heaped_) std::push_heap(b.begin(), b.end());
      ++size_;
    }

   private:
    static constexpr std::size_t kBuckets = 1024;
    void settle() {
      while (buckets_[current_].empty()) {
        ++current_;
        heaped_ = false;
      }
      if (!heaped_) {
        std::make_heap(buckets_[current_].begin(), buckets_[current_].end());
        heaped_ = true;
      }
    }
    std::vector<std::vector<Node>> buckets_;
    double scale_ = 1.0;
    std::size_t current_ = 0, size_ = 0;
    bool heaped_ = false;
  };

  /// The children of `node` bounded at most stop_at (all its free sub-boxes are scored).
  /// \return the boxes scored.
  std::size_t children(const Node& node, double stop_at, std::vector<Node>* out) const;

  const GlobalLocalizer* g_ = nullptr;
  Phase phase_ = Phase::kDone;
  std::vector<std::vector<Eigen::Vector2i>> offsets_;  // per heading
  double step_ = 0.0, n_tau2_ = 0.0, cap_ = 0.0, limit_ = 0.0;
  int leaf_level_ = 0;
  std::vector<Eigen::Vector2i> root_cells_;  // the free boxes of the coarsest level
  std::size_t cursor_ = 0;                   // the next root: heading * root_cells_ + box
  std::vector<Node> roots_, batch_;
  BoxQueue open_;
  std::vector<std::vector<Node>> kids_;  // of each box of a batch
  std::vector<std::size_t> scored_;
  std::vector<Pose2> poses_;
  double best_score_ = std::numeric_limits<double>::quiet_NaN();
  std::size_t nodes_ = 0;
  double seconds_ = 0.0;
};

}  // namespace vdtnav
