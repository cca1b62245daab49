#include "vdtnav/estimation/multi_start.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <mutex>
#include <random>
#include <utility>

#include "scan_scores.hpp"
#include "vdtnav/core/parallel.hpp"

namespace vdtnav {

double explained_fraction(const VdtSensorModel3& model, const ObservationSet<3>& observations,
                          const Pose3& pose, double distance) {
  return detail::explained_fraction_at(model, observations, pose.linear(), pose.translation(),
                                       distance);
}

double truncated_vcd(const VdtSensorModel3& model, const ObservationSet<3>& observations,
                     const Pose3& pose, double tau) {
  return detail::truncated_vcd_at(model, observations, pose.linear(), pose.translation(), tau);
}

LocalizationResult3 solve_multi_start(const VdtOptimizer3& optimizer,
                                      const ObservationSet<3>& observations, const Pose3& guess,
                                      const MultiStartOptions& o) {
  const VdtSensorModel3& model = optimizer.sensor_model();
  const auto usable = [](const LocalizationResult3& x) {
    return x.status == LocalizationStatus::kConverged ||
           x.status == LocalizationStatus::kNotConverged;
  };
  const bool try_all = observations.size() < o.all_starts_below;
  const auto good_enough = [&](const LocalizationResult3& x) {
    return !try_all && usable(x) &&
           explained_fraction(model, observations, x.pose, o.explained_distance) >=
               o.accept_fraction;
  };
  // A solve that stopped at its iteration limit is continued from where it stopped, once: far
  // from the guess the fine solve can need more than one budget of steps (CATEC, scenario C).
  const auto solve = [&](const Pose3& start) {
    LocalizationResult3 r = optimizer.solve(observations, start);
    if (r.status != LocalizationStatus::kNotConverged) return r;
    LocalizationResult3 more = optimizer.solve(observations, r.pose);
    more.iterations += r.iterations;
    return usable(more) ? more : r;
  };
  LocalizationResult3 best = o.enabled ? solve(guess) : optimizer.solve(observations, guess);
  if (!o.enabled || good_enough(best)) return best;
  double best_score = usable(best) ? truncated_vcd(model, observations, best.pose, o.truncation)
                                   : std::numeric_limits<double>::infinity();
  int iterations = best.iterations;
  // Keeps a solution if it scores lower. \return true if it was kept.
  const auto keep = [&](LocalizationResult3 r) {
    iterations += r.iterations;
    if (!usable(r)) return false;
    const double score = truncated_vcd(model, observations, r.pose, o.truncation);
    if (score >= best_score && usable(best)) return false;
    best = std::move(r);
    best_score = score;
    return true;
  };
  const auto try_start = [&](const Pose3& start) { return keep(solve(start)); };
  // Solves from the starts on the pool's threads, each start's solution kept or not in the
  // starts' order as soon as those before it are (so the threads never wait for a round), up to
  // the first kept solution that is good enough; starts after it not yet begun are skipped, the
  // solves under way dropped uncounted: the result of any thread count is the result of one.
  // \return whether it stopped so.
  const auto try_starts = [&](const std::vector<Pose3>& starts) {
    const std::size_t n = starts.size();
    std::vector<LocalizationResult3> solved(n);
    std::vector<std::uint8_t> ready(n, 0);
    std::size_t next = 0;     // the first start not yet kept or dropped
    std::size_t stop_at = n;  // the start that stopped the search (n: none)
    std::mutex order;
    parallel_for(n, [&](std::size_t i) {
      {
        const std::lock_guard<std::mutex> lock(order);
        if (i > stop_at) return;
      }
      LocalizationResult3 r = solve(starts[i]);
      const std::lock_guard<std::mutex> lock(order);
      solved[i] = std::move(r);
      ready[i] = 1;
      while (next < n && stop_at == n && ready[next] != 0) {
        if (keep(std::move(solved[next])) && good_enough(best)) stop_at = next;
        ++next;
      }
    });
    return stop_at < n;
  };
  // The estimated axes of the left perturbation (dt, dtheta): all six, or x, y, z, yaw.
  const bool four_dof = optimizer.options().four_dof;
  std::vector<Pose3> axis_starts;
  for (int axis = 0; axis < 6; ++axis) {
    if (four_dof && (axis == 3 || axis == 4)) continue;
    for (const double sign : {1.0, -1.0}) {
      Vector6d delta = Vector6d::Zero();
      delta[axis] = sign * (axis < 3 ? o.offset_translation : o.offset_rotation);
      axis_starts.push_back(oplus(guess, delta));
    }
  }
  if (try_starts(axis_starts)) {
    best.iterations = iterations;
    return best;
  }
  // Sparse sets: hops from the best solution so far, uniform in +-offset per axis, each solve
  // kept when it lowers the score. A fixed seed keeps the result a function of the input.
  if (try_all && o.hops > 0) {
    std::mt19937 rng(o.hop_seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int h = 0; h < o.hops; ++h) {
      Vector6d delta = Vector6d::Zero();
      for (int axis = 0; axis < 6; ++axis) {
        if (four_dof && (axis == 3 || axis == 4)) continue;
        delta[axis] = u(rng) * (axis < 3 ? o.offset_translation : o.offset_rotation);
      }
      (void)try_start(oplus(usable(best) ? best.pose : guess, delta));
    }
  }
  if (o.attitude_grid > 0 && !good_enough(best)) {
    // Attitude grid, screened on a subsample: solve there from each attitude, keep the best few
    // by their subsample score, solve those with every reading (try_start keeps the best overall).
    const std::size_t step = std::max<std::size_t>(1, observations.size() / o.screen_readings);
    const ObservationSet<3> sub = observations.subsampled(step);
    std::vector<Pose3> grid;
    const int n = o.attitude_grid;
    for (int i = four_dof ? 0 : -n; i <= (four_dof ? 0 : n); ++i) {
      for (int j = four_dof ? 0 : -n; j <= (four_dof ? 0 : n); ++j) {
        for (int k = -n; k <= n; ++k) {
          if (i == 0 && j == 0 && k == 0) continue;
          Vector6d delta = Vector6d::Zero();
          delta.tail<3>() = o.attitude_grid_step * Eigen::Vector3d(i, j, k);
          grid.push_back(oplus(guess, delta));
        }
      }
    }
    // Every attitude at once on the pool's threads, then screened in the grid's order.
    std::vector<LocalizationResult3> solved(grid.size());
    std::vector<double> scores(grid.size());
    parallel_for(grid.size(), [&](std::size_t g) {
      solved[g] = optimizer.solve(sub, grid[g]);
      if (usable(solved[g])) scores[g] = truncated_vcd(model, sub, solved[g].pose, o.truncation);
    });
    std::vector<std::pair<double, Pose3>> screened;
    for (std::size_t g = 0; g < grid.size(); ++g) {
      iterations += solved[g].iterations;
      if (usable(solved[g])) screened.emplace_back(scores[g], solved[g].pose);
    }
    const std::size_t kept = std::min<std::size_t>(
        screened.size(), static_cast<std::size_t>(std::max(o.screen_keep, 0)));
    std::partial_sort(screened.begin(), screened.begin() + static_cast<std::ptrdiff_t>(kept),
                      screened.end(),
                      [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<Pose3> finalists;
    for (std::size_t c = 0; c < kept; ++c) finalists.push_back(screened[c].second);
    (void)try_starts(finalists);
  }
  best.iterations = iterations;
  return best;
}

}  // namespace vdtnav
