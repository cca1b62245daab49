#include "vdtnav/sim/route_planner.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <queue>
#include <random>
#include <string>
#include <utility>

#include "vdtnav/core/error.hpp"
#include "vdtnav/map/vector_distance_transform.hpp"

namespace vdtnav::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kComfort = 1.0;       // metres beyond the clearance where the cost stops rising
constexpr double kNearPenalty = 3.0;   // step cost factor at exactly the clearance is 1 + this
constexpr double kSpread = 0.8;        // waypoint candidates: >= this fraction of the farthest
constexpr double kCentreTravel = 1.0;  // metres a waypoint may climb the UDT
constexpr double kSmoothHalfWindow = 0.4;  // metres either side in the moving average

/// The 8-connected grid graph of traversable cells with clearance-weighted step costs.
class Graph {
 public:
  Graph(const OccupancyGrid<2>& map, double clearance)
      : nx_(map.size()[0]),
        ny_(map.size()[1]),
        res_(map.resolution()),
        udt_(unsigned_distance_transform(nearest_occupied_cells(map))) {
    const std::size_t n = map.num_cells();
    traversable_.assign(n, 0);
    factor_.assign(n, 1.0);
    for (std::size_t c = 0; c < n; ++c) {
      const double d = udt_[c];
      if (map[c] != 0 || !(d >= clearance)) continue;
      traversable_[c] = 1;
      // Cost rises linearly from 1 (kComfort beyond the clearance) to 1 + kNearPenalty.
      factor_[c] = 1.0 + kNearPenalty * std::max(0.0, 1.0 - (d - clearance) / kComfort);
    }
  }

  [[nodiscard]] int size() const { return nx_ * ny_; }
  [[nodiscard]] bool traversable(int c) const { return traversable_[c] != 0; }
  [[nodiscard]] double udt(int c) const { return udt_[static_cast<std::size_t>(c)]; }
  [[nodiscard]] Eigen::Vector2i cell(int c) const { return {c % nx_, c / nx_}; }
  [[nodiscard]] double resolution() const { return res_; }

  /// Calls f(neighbour, step cost) for every traversable 8-neighbour of c; a diagonal step needs
  /// both cells it passes between to be traversable too.
  template <typename F>
  void for_each_neighbour(int c, F&& f) const {
    const int x = c % nx_, y = c / nx_;
    static constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
    static constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
    for (int k = 0; k < 8; ++k) {
      const int xn = x + kDx[k], yn = y + kDy[k];
      if (xn < 0 || yn < 0 || xn >= nx_ || yn >= ny_) continue;
      const int nb = xn + nx_ * yn;
      if (!traversable_[nb]) continue;
      const bool diagonal = k >= 4;
      if (diagonal && (!traversable_[xn + nx_ * y] || !traversable_[x + nx_ * yn])) continue;
      const double len = diagonal ? res_ * std::sqrt(2.0) : res_;
      f(nb, len * 0.5 * (factor_[c] + factor_[nb]));
    }
  }

  /// A lower bound of the cost from a to b (octile distance; every factor is >= 1).
  [[nodiscard]] double heuristic(int a, int b) const {
    const int dx = std::abs(a % nx_ - b % nx_), dy = std::abs(a / nx_ - b / nx_);
    return res_ * (std::max(dx, dy) + (std::sqrt(2.0) - 1.0) * std::min(dx, dy));
  }

 private:
  int nx_, ny_;
  double res_;
  Grid<float, 2> udt_;
  std::vector<char> traversable_;
  std::vector<double> factor_;
};

using QueueEntry = std::pair<double, int>;
using MinQueue = std::priority_queue<QueueEntry, std::vector<QueueEntry>, std::greater<>>;

/// Cells of the largest connected traversable region (ascending indices).
std::vector<int> largest_region(const Graph& g) {
  std::vector<int> label(static_cast<std::size_t>(g.size()), -1);
  std::vector<int> best, current, stack;
  int next_label = 0;
  for (int s = 0; s < g.size(); ++s) {
    if (!g.traversable(s) || label[s] >= 0) continue;
    current.clear();
    stack.assign(1, s);
    label[s] = next_label;
    while (!stack.empty()) {
      const int c = stack.back();
      stack.pop_back();
      current.push_back(c);
      g.for_each_neighbour(c, [&](int nb, double) {
        if (label[nb] < 0) {
          label[nb] = next_label;
          stack.push_back(nb);
        }
      });
    }
    ++next_label;
    if (current.size() > best.size()) best.swap(current);
  }
  std::sort(best.begin(), best.end());
  return best;
}

/// Geodesic (clearance-weighted) cost from `source` to every cell (+inf where unreachable).
std::vector<double> dijkstra(const Graph& g, int source) {
  std::vector<double> dist(static_cast<std::size_t>(g.size()), kInf);
  MinQueue queue;
  dist[source] = 0.0;
  queue.push({0.0, source});
  while (!queue.empty()) {
    // Plain variables, not a structured binding: a lambda may capture those only from C++20.
    const double d = queue.top().first;
    const int c = queue.top().second;
    queue.pop();
    if (d > dist[c]) continue;
    g.for_each_neighbour(c, [&](int nb, double cost) {
      if (d + cost < dist[nb]) {
        dist[nb] = d + cost;
        queue.push({dist[nb], nb});
      }
    });
  }
  return dist;
}

/// A* from a to b; the cells of the cheapest path, a and b included (empty if unreachable).
std::vector<int> a_star(const Graph& g, int a, int b) {
  std::vector<double> cost(static_cast<std::size_t>(g.size()), kInf);
  std::vector<int> parent(static_cast<std::size_t>(g.size()), -1);
  std::vector<char> closed(static_cast<std::size_t>(g.size()), 0);
  MinQueue queue;
  cost[a] = 0.0;
  queue.push({g.heuristic(a, b), a});
  while (!queue.empty()) {
    const int c = queue.top().second;
    queue.pop();
    if (closed[c]) continue;
    closed[c] = 1;
    if (c == b) break;
    g.for_each_neighbour(c, [&](int nb, double step) {
      if (closed[nb] || cost[c] + step >= cost[nb]) return;
      cost[nb] = cost[c] + step;
      parent[nb] = c;
      queue.push({cost[nb] + g.heuristic(nb, b), nb});
    });
  }
  if (!closed[b]) return {};
  std::vector<int> cells;
  for (int c = b; c != -1; c = parent[c]) cells.push_back(c);
  std::reverse(cells.begin(), cells.end());
  return cells;
}

/// Climbs the UDT from c (steepest ascent over neighbours) for at most kCentreTravel metres.
int centre(const Graph& g, int c) {
  const int max_steps = static_cast<int>(kCentreTravel / g.resolution());
  for (int k = 0; k < max_steps; ++k) {
    int best = c;
    g.for_each_neighbour(c, [&](int nb, double) {
      if (g.udt(nb) > g.udt(best)) best = nb;
    });
    if (best == c) break;
    c = best;
  }
  return c;
}

/// The leg's cell centres smoothed by a moving average, as far as each point keeps the clearance.
std::vector<Eigen::Vector2d> smooth_leg(const OccupancyGrid<2>& map, const Graph& g,
                                        const std::vector<int>& cells) {
  const auto n = static_cast<int>(cells.size());
  std::vector<Eigen::Vector2d> raw(cells.size());
  for (int k = 0; k < n; ++k) raw[k] = map.cell_center(g.cell(cells[k]));
  const int half = std::max(1, static_cast<int>(std::lround(kSmoothHalfWindow / g.resolution())));
  std::vector<Eigen::Vector2d> out(raw);
  for (int k = 1; k + 1 < n; ++k) {
    const int h = std::min({half, k, n - 1 - k});  // symmetric window, ends stay fixed
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (int j = k - h; j <= k + h; ++j) sum += raw[j];
    const Eigen::Vector2d smoothed = sum / (2 * h + 1);
    // As much of the smoothing as keeps the point in a traversable cell (the raw cell centre is).
    for (double t : {1.0, 0.5, 0.25}) {
      const Eigen::Vector2d p = raw[k] + t * (smoothed - raw[k]);
      const Eigen::Vector2i c = map.cell_of(p);
      if (map.contains(c) && g.traversable(static_cast<int>(map.linear_index(c)))) {
        out[k] = p;
        break;
      }
    }
  }
  return out;
}

}  // namespace

std::vector<Eigen::Vector2d> plan_tour(const OccupancyGrid<2>& map, int waypoints, double clearance,
                                       std::uint32_t seed) {
  VDTNAV_CHECK(waypoints >= 2, "plan_tour: waypoints must be >= 2");
  VDTNAV_CHECK(std::isfinite(clearance) && clearance >= 0.0, "plan_tour: clearance must be >= 0");
  const Graph g(map, clearance);
  const std::vector<int> region = largest_region(g);
  if (region.size() < 2)
    throw ConfigError("plan_tour: no two connected free cells have " + std::to_string(clearance) +
                      " m clearance from obstacles");

  // Randomised geodesic farthest-point sampling.
  std::mt19937_64 rng(seed);
  const auto pick = [&rng](const std::vector<int>& from) {
    return from[std::uniform_int_distribution<std::size_t>(0, from.size() - 1)(rng)];
  };
  std::vector<int> chosen{centre(g, pick(region))};
  std::vector<std::vector<double>> fields{dijkstra(g, chosen[0])};
  std::vector<double> nearest = fields[0];  // cost to the nearest waypoint so far
  while (static_cast<int>(chosen.size()) < waypoints) {
    double farthest = 0.0;
    for (int c : region) farthest = std::max(farthest, nearest[c]);
    if (!(farthest > 0.0)) break;
    std::vector<int> candidates;
    for (int c : region)
      if (nearest[c] >= kSpread * farthest) candidates.push_back(c);
    const int c = centre(g, pick(candidates));
    if (std::find(chosen.begin(), chosen.end(), c) != chosen.end()) break;
    chosen.push_back(c);
    fields.push_back(dijkstra(g, c));
    for (int r : region) nearest[r] = std::min(nearest[r], fields.back()[r]);
  }
  if (chosen.size() < 2)
    throw ConfigError("plan_tour: the largest region with " + std::to_string(clearance) +
                      " m clearance is too small for two waypoints");

  // Nearest-neighbour order from the first waypoint.
  std::vector<std::size_t> order{0};
  std::vector<char> visited(chosen.size(), 0);
  visited[0] = 1;
  while (order.size() < chosen.size()) {
    const std::vector<double>& from = fields[order.back()];
    std::size_t next = 0;
    double best = kInf;
    for (std::size_t k = 0; k < chosen.size(); ++k) {
      if (!visited[k] && from[chosen[k]] < best) {
        best = from[chosen[k]];
        next = k;
      }
    }
    visited[next] = 1;
    order.push_back(next);
  }

  // A* legs, smoothed and concatenated.
  std::vector<Eigen::Vector2d> tour;
  for (std::size_t k = 0; k + 1 < order.size(); ++k) {
    const std::vector<int> cells = a_star(g, chosen[order[k]], chosen[order[k + 1]]);
    VDTNAV_ASSERT(!cells.empty());  // all waypoints lie in one connected region
    const std::vector<Eigen::Vector2d> leg = smooth_leg(map, g, cells);
    tour.insert(tour.end(), leg.begin() + (tour.empty() ? 0 : 1), leg.end());
  }
  return tour;
}

}  // namespace vdtnav::sim
