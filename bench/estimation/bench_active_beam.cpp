// Goal selection of the rotating single beam (thesis (4.1)): every segment's hypothetical readings
// sphere traced in the map and its predicted covariance, on the generated floor plan from poses
// along its tour. /8: Table 4.1's sensor (360 degrees, 0.5-3 m); /23: Table 4.3's (270 degrees,
// 0.5-30 m).
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "../bench_counters.hpp"
#include "vdtnav/estimation/active_beam.hpp"
#include "vdtnav/sim/floor_plan.hpp"

namespace vdtnav {
namespace {

void BM_ActiveSelect(benchmark::State& state) {
  static const sim::FloorPlan plan = sim::generate_floor_plan({});
  static const VdtMap2 map = VdtMap2::build(plan.occupancy);
  const RotatingBeamOptions beam =
      state.range(0) == 8 ? RotatingBeamOptions::table_4_1() : RotatingBeamOptions::table_4_3();
  const ActiveBeamSelector sel(map, beam);
  std::vector<Pose2> poses;
  for (std::size_t k = 0; k + 1 < plan.tour.size(); ++k) {
    const Eigen::Vector2d a = plan.tour[k], b = plan.tour[k + 1];
    const Eigen::Vector2d p = 0.5 * (a + b);
    poses.emplace_back(p.x(), p.y(), std::atan2(b.y() - a.y(), b.x() - a.x()));
  }
  const Eigen::Matrix3d p = Eigen::Vector3d(0.05 * 0.05, 0.05 * 0.05, 0.02 * 0.02).asDiagonal();
  std::size_t k = 0;
  int chosen = 0;
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    const BeamSelection s =
        sel.select(poses[k++ % poses.size()], p, chosen, BeamStrategy::kActiveTrace);
    chosen = s.segment;
    benchmark::DoNotOptimize(chosen);
  }
  timer.set(state, "ms_per_selection", 1.0, 1e-6);
  state.counters["segments"] = beam.segments;
}
BENCHMARK(BM_ActiveSelect)->Arg(8)->Arg(23);

}  // namespace
}  // namespace vdtnav
