#include "vdtnav/estimation/global_localization3d.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <queue>

#include "vdtnav/core/error.hpp"
#include "vdtnav/core/parallel.hpp"
#include "vdtnav/core/pose2.hpp"
#include "vdtnav/estimation/global_decision.hpp"

namespace vdtnav {

namespace global3d {

using Clock = std::chrono::steady_clock;

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

constexpr double kDegree = kPi / 180.0;

double yaw_of(const Pose3& p) { return std::atan2(p.linear()(1, 0), p.linear()(0, 0)); }

bool distinct(const Pose3& a, const Pose3& b, const GlobalLocalization3Options& o) {
  return (a.translation() - b.translation()).norm() > o.distinct_distance ||
         std::abs(wrap_angle(yaw_of(a) - yaw_of(b))) > o.distinct_angle;
}

}  // namespace global3d

using global3d::Clock;
using global3d::kDegree;

void GlobalLocalization3Options::validate() const {
  VDTNAV_CHECK(std::isfinite(truncation) && truncation > 0.0,
               "3D global localization: truncation must be > 0");
  VDTNAV_CHECK(max_readings >= 3, "3D global localization: max_readings must be >= 3");
  VDTNAV_CHECK(std::isfinite(resolution), "3D global localization: resolution must be finite");
  VDTNAV_CHECK(std::isfinite(angular_step) && angular_step < kPi,
               "3D global localization: angular_step must be < pi (<= 0: from the scan)");
  VDTNAV_CHECK(levels <= 10, "3D global localization: levels must be <= 10");
  VDTNAV_CHECK(clearance >= 0.0 && std::isfinite(clearance),
               "3D global localization: clearance must be >= 0");
  VDTNAV_CHECK(!std::isinf(min_z) && !std::isinf(max_z) && !(min_z > max_z),
               "3D global localization: min_z must be <= max_z (NaN: no bound)");
  VDTNAV_CHECK(candidates >= 1, "3D global localization: candidates must be >= 1");
  VDTNAV_CHECK(distinct_distance > 0.0 && distinct_angle > 0.0,
               "3D global localization: distinct_distance and distinct_angle must be > 0");
  VDTNAV_CHECK(alternative_margin >= 0.0 && explained_distance > 0.0 && ambiguity_margin >= 0.0,
               "3D global localization: margins must be >= 0 and explained_distance > 0");
  VDTNAV_CHECK(accept_fraction > 0.0 && accept_fraction <= 1.0,
               "3D global localization: accept_fraction must be in (0, 1]");
  VDTNAV_CHECK(max_nodes >= 1, "3D global localization: max_nodes must be >= 1");
}

/// A cube of the search: 2^level cells from b, at heading `heading`.
struct GlobalLocalizer3::Node {
  std::uint32_t lb;
  int heading, level;
  Eigen::Vector3i b;
  /// Lower bounds first; among equal bounds the smaller cube (nearer a leaf).
  bool operator<(const Node& o) const {
    if (lb != o.lb) return lb > o.lb;
    return level > o.level;
  }
};

GlobalLocalizer3::GlobalLocalizer3(const VdtField3& map, const GlobalLocalization3Options& options)
    : map_(&map), options_(options), optimizer_(map, options.optimizer) {
  options_.validate();
  // The default edge: the map's cells, at least 0.1 m, and coarse enough that the grid holds at
  // most 2^25 cells (~0.4 GB with its pyramid: a building-sized sparse map stays in memory).
  const double volume = static_cast<double>(map.size().x()) * map.size().y() * map.size().z() *
                        std::pow(map.resolution(), 3);
  const double h = options_.resolution > 0.0
                       ? options_.resolution
                       : std::max({map.resolution(), 0.1, std::cbrt(volume / (1 << 25))});
  frame_ = GridFrame<3>(h, map.frame().origin(), map.frame().yaw());
  std::int64_t n = 1;
  for (int d = 0; d < 3; ++d) {
    size_[d] = std::max(1, static_cast<int>(std::ceil(map.size()[d] * map.resolution() / h)));
    n *= size_[d];
  }
  VDTNAV_CHECK(n < (std::int64_t{1} << 31),
               "3D global localization: the search grid has more than 2^31 cells; raise "
               "its resolution");
  levels_ = options_.levels >= 0 ? options_.levels
                                 : std::max(0, static_cast<int>(std::lround(std::log2(3.2 / h))));
  const std::size_t cells = static_cast<std::size_t>(n);
  const double tau2 = options_.truncation * options_.truncation;

  // Level 0: q(D^2) at the search cells' centres, and where the sensor may be.
  pooled_.assign(levels_ + 1, {});
  free_.assign(levels_ + 1, {});
  pooled_[0].resize(cells);
  free_[0].resize(cells);
  const std::size_t nx = size_.x(), nxy = nx * size_.y();
  const double c2 = options_.clearance * options_.clearance;
  parallel_for_ranges(cells, 1 << 14, [&](std::size_t begin, std::size_t end) {
    std::vector<Eigen::Vector3d> p(end - begin);
    std::vector<VdtSample<3>> s(end - begin);
    for (std::size_t c = begin; c < end; ++c) {
      const Eigen::Vector3i i(static_cast<int>(c % nx), static_cast<int>((c / nx) % size_.y()),
                              static_cast<int>(c / nxy));
      p[c - begin] = frame_.cell_center(i);
    }
    map.evaluate(p.data(), p.size(), s.data(), false);
    for (std::size_t c = begin; c < end; ++c) {
      const VdtSample<3>& v = s[c - begin];
      const double d2 = v.inside ? v.value.squaredNorm() : tau2;
      pooled_[0][c] = static_cast<std::uint8_t>(std::floor(255.0 * std::min(d2, tau2) / tau2));
      const double z = p[c - begin].z();
      free_[0][c] = v.inside && d2 >= c2 && !(z < options_.min_z) && !(z > options_.max_z);
    }
  });
  free_cells_ = static_cast<std::size_t>(std::count(free_[0].begin(), free_[0].end(), 1));
  // Level k from level k-1: the 2^k cube from c is the eight 2^(k-1) cubes from c + half s,
  // s in {0, 1}^3 (cells past the grid: outside the map, 255 and not free).
  for (int k = 1; k <= levels_; ++k) {
    const int half = 1 << (k - 1);
    const std::vector<std::uint8_t>& m = pooled_[k - 1];
    const std::vector<std::uint8_t>& f = free_[k - 1];
    pooled_[k].resize(cells);
    free_[k].resize(cells);
    parallel_for(static_cast<std::size_t>(size_.z()), [&](std::size_t zz) {
      const int z = static_cast<int>(zz);
      for (int y = 0; y < size_.y(); ++y) {
        for (int x = 0; x < size_.x(); ++x) {
          std::uint8_t lo = 255, any = 0;
          for (int s = 0; s < 8; ++s) {
            const Eigen::Vector3i c(x + (s & 1) * half, y + ((s >> 1) & 1) * half,
                                    z + ((s >> 2) & 1) * half);
            if (c.x() >= size_.x() || c.y() >= size_.y() || c.z() >= size_.z()) continue;
            const std::size_t l = linear(c);
            lo = std::min(lo, m[l]);
            any = static_cast<std::uint8_t>(any | f[l]);
          }
          const std::size_t l = linear({x, y, z});
          pooled_[k][l] = lo;
          free_[k][l] = any;
        }
      }
    });
  }
}

bool GlobalLocalizer3::free(int level, const Eigen::Vector3i& b) const {
  return free_[level][linear(b)] != 0;
}

std::uint32_t GlobalLocalizer3::bound(int level, const Eigen::Vector3i& b,
                                      const std::vector<Eigen::Vector3i>& offsets,
                                      std::uint32_t stop_at) const {
  const int w = 1 << level;
  const std::vector<std::uint8_t>& g = pooled_[level];
  std::uint32_t s = 0;
  for (const Eigen::Vector3i& o : offsets) {
    Eigen::Vector3i c = b + o;
    bool outside = false;
    for (int d = 0; d < 3; ++d) {
      if (c[d] >= size_[d] || c[d] + w <= 0) {
        outside = true;
        break;
      }
      // A window that starts below the grid: the window from 0 holds its part inside (a
      // minimum over more cells, still a bound).
      c[d] = std::max(c[d], 0);
    }
    s += outside ? 255u : g[linear(c)];
    if (s > stop_at) return s;
  }
  return s;
}

GlobalLocalization3Result GlobalLocalizer3::localize(const ObservationSet3& scan, double roll,
                                                     double pitch) const {
  const Clock::time_point t0 = Clock::now();
  GlobalLocalization3Result out;
  VDTNAV_CHECK(std::isfinite(roll) && std::isfinite(pitch),
               "3D global localization: roll and pitch must be finite");
  if (scan.size() < 3 || free_cells_ == 0) {
    out.result.status = LocalizationStatus::kTooFewObservations;
    return out;
  }
  // The scored readings, evenly over the scan; r90 sets the heading step.
  const std::size_t m = std::min<std::size_t>(scan.size(), options_.max_readings);
  std::vector<Eigen::Vector3d> points(m);
  std::vector<double> ranges(m);
  for (std::size_t k = 0; k < m; ++k) {
    points[k] = scan.points[k * scan.size() / m];
    ranges[k] = points[k].norm();
  }
  std::nth_element(ranges.begin(), ranges.begin() + static_cast<std::ptrdiff_t>(0.9 * (m - 1)),
                   ranges.end());
  const double r90 = std::max(ranges[static_cast<std::size_t>(0.9 * (m - 1))], 1e-3);
  const double h = frame_.resolution();
  const double step_wanted = options_.angular_step > 0.0
                                 ? options_.angular_step
                                 : std::clamp(h / r90, 0.5 * kDegree, 3.0 * kDegree);
  const int headings = static_cast<int>(std::ceil(2.0 * kPi / step_wanted));
  const double step = 2.0 * kPi / headings;
  out.headings = static_cast<std::size_t>(headings);
  const Eigen::Matrix3d rp = pose3_from_xyz_rpy(0, 0, 0, roll, pitch, 0).linear();
  const Eigen::Matrix3d to_grid = frame_.rotation().transpose() / h;
  const auto rotation = [&](int a) {
    return Eigen::Matrix3d(Eigen::AngleAxisd(a * step, Eigen::Vector3d::UnitZ()) * rp);
  };
  std::vector<std::vector<Eigen::Vector3i>> offsets(headings);
  parallel_for(static_cast<std::size_t>(headings), [&](std::size_t a) {
    const Eigen::Matrix3d r = to_grid * rotation(static_cast<int>(a));
    offsets[a].resize(m);
    for (std::size_t k = 0; k < m; ++k) {
      const Eigen::Vector3d u = r * points[k];
      offsets[a][k] = Eigen::Vector3i(static_cast<int>(std::lround(u.x())),
                                      static_cast<int>(std::lround(u.y())),
                                      static_cast<int>(std::lround(u.z())));
    }
  });
  const auto leaf_pose = [&](const Node& n) {
    Pose3 p = Pose3::Identity();
    p.linear() = rotation(n.heading);
    p.translation() = frame_.cell_center(n.b);
    return p;
  };

  // Roots: the free cubes of the coarsest level at every heading, scored on the pool.
  const int top = levels_, w = 1 << top;
  std::vector<Eigen::Vector3i> root_cubes;
  for (int z = 0; z < size_.z(); z += w) {
    for (int y = 0; y < size_.y(); y += w) {
      for (int x = 0; x < size_.x(); x += w) {
        if (free(top, {x, y, z})) root_cubes.emplace_back(x, y, z);
      }
    }
  }
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::vector<Node> roots(root_cubes.size() * headings);
  parallel_for(static_cast<std::size_t>(headings), [&](std::size_t a) {
    for (std::size_t r = 0; r < root_cubes.size(); ++r) {
      roots[a * root_cubes.size() + r] = Node{bound(top, root_cubes[r], offsets[a], kNone),
                                              static_cast<int>(a), top, root_cubes[r]};
    }
  });
  out.nodes = roots.size();

  // Children of a cube that are free, scored (stopping past stop_at).
  const auto children = [&](const Node& n, std::uint32_t stop_at, std::vector<Node>* kids) {
    kids->clear();
    const int half = 1 << (n.level - 1);
    for (int s = 0; s < 8; ++s) {
      const Eigen::Vector3i c = n.b + half * Eigen::Vector3i(s & 1, (s >> 1) & 1, (s >> 2) & 1);
      if (c.x() >= size_.x() || c.y() >= size_.y() || c.z() >= size_.z()) continue;
      if (!free(n.level - 1, c)) continue;
      const std::uint32_t lb = bound(n.level - 1, c, offsets[n.heading], stop_at);
      ++out.nodes;
      if (lb <= stop_at) kids->push_back(Node{lb, n.heading, n.level - 1, c});
    }
  };

  // A greedy descent from the best root to a leaf: an upper bound of the best leaf's score, so
  // that cubes that cannot hold the best or an alternative are never queued.
  const std::uint32_t margin = static_cast<std::uint32_t>(
      std::lround(options_.alternative_margin * static_cast<double>(m) * 255.0));
  std::uint32_t upper = kNone;
  std::vector<Node> kids;
  {
    std::vector<Node> order(roots);
    std::sort(order.begin(), order.end(), [](const Node& a, const Node& b) { return b < a; });
    for (std::size_t r = 0; r < std::min<std::size_t>(order.size(), 8); ++r) {
      Node n = order[r];
      while (n.level > 0) {
        children(n, kNone, &kids);
        if (kids.empty()) break;
        n = *std::min_element(kids.begin(), kids.end(),
                              [](const Node& a, const Node& b) { return b < a; });
      }
      if (n.level == 0) upper = std::min(upper, n.lb);
    }
  }
  const auto cutoff = [&](std::uint32_t best) {
    return best == kNone ? kNone
                         : static_cast<std::uint32_t>(
                               std::min<std::uint64_t>(kNone - 1, std::uint64_t{best} + margin));
  };
  std::priority_queue<Node> open;
  std::uint32_t stop_at = cutoff(upper);
  for (const Node& n : roots) {
    if (n.lb <= stop_at) open.push(n);
  }
  std::vector<Node> leaves;
  std::vector<Pose3> leaf_poses;
  std::uint32_t best = kNone;
  while (!open.empty()) {
    const Node n = open.top();
    open.pop();
    if (n.lb > stop_at) break;
    if (n.level == 0) {
      if (best == kNone) {
        best = n.lb;
        stop_at = cutoff(best);
      }
      const Pose3 p = leaf_pose(n);
      const bool is_distinct =
          std::all_of(leaf_poses.begin(), leaf_poses.end(),
                      [&](const Pose3& q) { return global3d::distinct(p, q, options_); });
      if (is_distinct) {
        leaves.push_back(n);
        leaf_poses.push_back(p);
        if (static_cast<int>(leaves.size()) >= options_.candidates) break;
      }
      continue;
    }
    if (out.nodes >= options_.max_nodes) {
      out.exhausted = true;
      break;
    }
    children(n, stop_at, &kids);
    for (const Node& k : kids) open.push(k);
  }
  out.search_seconds = global3d::since(t0);
  if (leaves.empty()) {
    out.result.status = LocalizationStatus::kRefused;
    out.seconds = global3d::since(t0);
    return out;
  }
  out.best_leaf = leaf_poses.front();
  out.best_leaf_score = leaves.front().lb * (options_.truncation * options_.truncation) / 255.0;

  // The distinct leaves refined and decided as in 2D (global_decision.hpp).
  GlobalDecision<3> d = refine_and_decide<3>(
      optimizer_, scan, leaf_poses,
      {options_.truncation, options_.explained_distance, options_.accept_fraction,
       options_.ambiguity_margin},
      [&](const Pose3& a, const Pose3& b) { return global3d::distinct(a, b, options_); });
  out.result = std::move(d.result);
  out.ambiguous = d.ambiguous;
  out.alternatives = std::move(d.alternatives);
  out.explained = d.explained;
  out.result.explained = d.explained;
  if (out.result.status == LocalizationStatus::kNotConverged) {
    // Accepted: a refinement that stopped at its iteration limit (a map blurred by its builder's
    // pose error) but explains the scan is the pose; a tracker refines it on the next scan.
    out.result.status = LocalizationStatus::kConverged;
  }
  out.seconds = global3d::since(t0);
  return out;
}

}  // namespace vdtnav
