// BM_GlobalLocalization/pool_threads:<n>: one global localization (branch and bound, then the
// refinement of the best leaves; estimation/global_localization.hpp) of a simulated 270-degree
// scan from a random free pose of the generated floor plan (0.1 m cells), at 1 and 2 threads of
// the pool; counters ms, ms_1_thread and speedup (bench_counters.hpp), nodes per search, and
// found (the share of searches accepted within 0.3 m / 0.1 rad of the truth).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "../bench_counters.hpp"
#include "vdtnav/estimation/global_localization.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace vdtnav {
namespace {

struct Fixture {
  sim::FloorPlan plan = sim::generate_floor_plan({});
  VdtMap2 map = VdtMap2::build(plan.occupancy);
  std::vector<Pose2> truth;
  std::vector<ScanPoints> scans;

  Fixture() {
    std::mt19937 rng(5);
    const OccupancyGrid<2>& grid = plan.occupancy;
    std::uniform_int_distribution<int> x(0, grid.size().x() - 1), y(0, grid.size().y() - 1);
    std::uniform_real_distribution<double> yaw(-kPi, kPi);
    std::normal_distribution<double> noise(0.0, 0.01);
    while (truth.size() < 6) {
      const Eigen::Vector2i i(x(rng), y(rng));
      if (grid(i) || map.value(grid.cell_center(i)).norm() < 0.4) continue;
      const Pose2 pose(grid.cell_center(i).x(), grid.cell_center(i).y(), yaw(rng));
      ScanPoints s;
      s.sigma_range = 0.01;
      for (int b = 0; b < 541; ++b) {
        const double a = -0.75 * kPi + 1.5 * kPi * b / 540.0;
        const Eigen::Vector2d u(std::cos(pose[2] + a), std::sin(pose[2] + a));
        const double r =
            sim::cast_ray<2>(grid, pose.head<2>(), u, 30.0, sim::RaySurface::kCellCentre);
        if (!std::isfinite(r) || r < 0.1) continue;
        s.add(Eigen::Vector2d::Zero(), Eigen::Vector2d(std::cos(a), std::sin(a)), r + noise(rng),
              static_cast<std::size_t>(b));
      }
      truth.push_back(pose);
      scans.push_back(std::move(s));
    }
  }
};

void BM_GlobalLocalization(benchmark::State& state) {
  static const Fixture f;
  const GlobalLocalizer loc(f.map, f.plan.occupancy);
  std::size_t nodes = 0, found = 0, searches = 0;
  bench::thread_scaling(state, static_cast<int>(state.range(0)), [&](std::size_t k) {
    const std::size_t i = k % f.scans.size();
    const GlobalLocalizationResult r = loc.localize(f.scans[i]);
    benchmark::DoNotOptimize(r);
    nodes += r.nodes;
    found += r.result.status == LocalizationStatus::kConverged &&
             (r.result.pose.head<2>() - f.truth[i].head<2>()).norm() < 0.3 &&
             std::abs(wrap_angle(r.result.pose[2] - f.truth[i][2])) < 0.1;
    ++searches;
  });
  state.counters["nodes"] = static_cast<double>(nodes) / static_cast<double>(searches);
  state.counters["found"] = static_cast<double>(found) / static_cast<double>(searches);
}
BENCHMARK(BM_GlobalLocalization)->Apply(bench::pool_threads_1_and_2)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace vdtnav
