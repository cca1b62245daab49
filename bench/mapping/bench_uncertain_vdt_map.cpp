// Uncertain VDT maps (thesis ch. 5): one fit of Experiment 2 (the generated floor plan's corridor,
// 270 degree LiDAR, Table 5.2's noise, control points at 0.25 m) with and without the covariance
// marginals, and a query (DT_v, its gradient and its variance) at the true boundary.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "../bench_counters.hpp"
#include "vdtnav/mapping/uncertain_vdt_map.hpp"
#include "vdtnav/sim/mapping_run.hpp"

namespace vdtnav {
namespace {

const sim::MappingRun& experiment2() {
  static const sim::MappingRun run = [] {
    const sim::MappingScene scene = sim::generated_corridor(1);
    sim::LidarOptions lidar;  // 270 degrees at 0.25 degrees
    lidar.range_max = 10.0;
    return sim::simulate_mapping_run(scene.world, scene.poses, lidar,
                                     sim::MappingNoise::table_5_2(), 1000);
  }();
  return run;
}

/// s_per_fit: the fit alone; cov_s_per_fit: the covariance marginals that follow it.
void BM_UncertainMapFit(benchmark::State& state) {
  const sim::MappingRun& run = experiment2();
  mapping::UncertainMapOptions o;
  o.spacing = 0.25;
  double fit_s = 0.0, cov_s = 0.0;
  int control_points = 0;
  for (auto _ : state) {
    const mapping::UncertainVdtMap map = mapping::UncertainVdtMap::fit(run.scans, o);
    fit_s += map.summary().fit_seconds;
    cov_s += map.summary().covariance_seconds;
    control_points = map.summary().control_points;
    benchmark::DoNotOptimize(map.summary().final_cost);
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["s_per_fit"] = fit_s / n;
  state.counters["cov_s_per_fit"] = cov_s / n;
  state.counters["control_points"] = control_points;
  state.counters["scans"] = static_cast<double>(run.scans.size());
}
// One fit takes seconds: a single iteration even at the default minimum time.
BENCHMARK(BM_UncertainMapFit)->Name("BM_UncertainMapFit/experiment2")->Unit(benchmark::kSecond);

/// ns_per_point: evaluate() at the true boundary points, value + gradient + 2 x 2 variance.
void BM_UncertainMapQuery(benchmark::State& state) {
  const sim::MappingRun& run = experiment2();
  static const mapping::UncertainVdtMap map = [&] {
    mapping::UncertainMapOptions o;
    o.spacing = 0.25;
    return mapping::UncertainVdtMap::fit(run.scans, o);
  }();
  std::vector<Eigen::Vector2d> points;
  for (std::size_t k = 0; k < run.true_boundary.size(); k += 7) {
    points.push_back(run.true_boundary[k]);
  }
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    double sum = 0.0;
    for (const auto& p : points) {
      const mapping::UncertainMapSample s = map.evaluate(p);
      sum += s.value.x() + s.jacobian(0, 0) + s.covariance(0, 0);
    }
    benchmark::DoNotOptimize(sum);
  }
  timer.set(state, "ns_per_point", static_cast<double>(points.size()));
  state.counters["points"] = static_cast<double>(points.size());
}
BENCHMARK(BM_UncertainMapQuery);

}  // namespace
}  // namespace vdtnav
