// Uncertain VDT maps (thesis ch. 5): one fit of Experiment 2 (the generated floor plan's corridor,
// 270 degree LiDAR, Table 5.2's noise, control points at 0.25 m) with and without the covariance
// marginals, and a query (DT_v, its gradient and its variance) at the true boundary; the same on
// the Intel lab (the last third of the corrected log at the study's stated pose noise, what
// `vdtnav map --uncertain` fits), with the process's peak memory.
#include <sys/resource.h>

#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "../bench_counters.hpp"
#include "vdtnav/io/carmen_log.hpp"
#include "vdtnav/io/log_odometry.hpp"
#include "vdtnav/io/odometry_table.hpp"
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

/// The Intel lab's map scans: the last third of the corrected log, pose sigma 0.05 m / 0.01 rad,
/// range sigma 0.02 m (the study's, and `vdtnav map --uncertain`'s defaults). Empty without data.
const std::vector<mapping::MapScan>& intel_scans() {
  static const std::vector<mapping::MapScan> scans = [] {
    std::vector<mapping::MapScan> out;
    const std::string dir = std::string(VDTNAV_DATA_DIR) + "/intel-lab/";
    if (!std::filesystem::exists(dir + "intel.gfs.log.gz")) return out;
    const CarmenLog gfs = load_carmen_log(dir + "intel.gfs.log.gz");
    const std::string table = dir + "intel_910_odom_vs_corrected.txt";
    const JoinedLogs logs = join_odometry_table(gfs, load_odometry_table(table), table);
    const std::size_t n = logs.corrected.lasers.size();
    for (std::size_t i = n - n / 3; i < n; ++i) {
      LaserScan laser = logs.corrected.lasers[i].scan;
      laser.sigma_range = 0.02;
      mapping::MapScan s;
      s.pose = logs.corrected.lasers[i].pose;
      s.pose_covariance = Eigen::Vector3d(0.05 * 0.05, 0.05 * 0.05, 0.01 * 0.01).asDiagonal();
      s.points = scan_points(laser);
      out.push_back(std::move(s));
    }
    return out;
  }();
  return scans;
}

double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // kilobytes on Linux
}

/// s_per_fit, cov_s_per_fit on one thread; peak_mb: the process's peak resident memory after the
/// fit (run it alone: --benchmark_filter=BM_UncertainMapFit/intel).
void BM_UncertainMapFitIntel(benchmark::State& state) {
  const auto& scans = intel_scans();
  if (scans.empty()) {
    state.SkipWithError("Intel lab data not found");
    return;
  }
  mapping::UncertainMapOptions o;
  o.spacing = 0.0;  // from the data, as vdtnav map --uncertain
  o.threads = 1;
  double fit_s = 0.0, cov_s = 0.0;
  for (auto _ : state) {
    const mapping::UncertainVdtMap map = mapping::UncertainVdtMap::fit(scans, o);
    fit_s += map.summary().fit_seconds;
    cov_s += map.summary().covariance_seconds;
    state.counters["control_points"] = map.summary().control_points;
    state.counters["spacing_m"] = map.summary().spacing;
    benchmark::DoNotOptimize(map.summary().final_cost);
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["s_per_fit"] = fit_s / n;
  state.counters["cov_s_per_fit"] = cov_s / n;
  state.counters["peak_mb"] = peak_rss_mb();
  state.counters["scans"] = static_cast<double>(scans.size());
}
BENCHMARK(BM_UncertainMapFitIntel)
    ->Name("BM_UncertainMapFit/intel")
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

/// ns_per_point: evaluate() on the Intel map at its observed points (value, gradient, variance).
void BM_UncertainMapQueryIntel(benchmark::State& state) {
  const auto& scans = intel_scans();
  if (scans.empty()) {
    state.SkipWithError("Intel lab data not found");
    return;
  }
  static const auto map = [&] {
    mapping::UncertainMapOptions o;
    o.spacing = 0.0;
    return std::make_unique<mapping::UncertainVdtMap>(mapping::UncertainVdtMap::fit(scans, o));
  }();
  std::vector<Eigen::Vector2d> points;
  const auto& obs = map->observed_points();
  for (std::size_t k = 0; k < obs.size(); k += 13) points.push_back(obs[k]);
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    double sum = 0.0;
    for (const auto& p : points) {
      const mapping::UncertainMapSample s = map->evaluate(p);
      sum += s.value.x() + s.jacobian(0, 0) + s.covariance(0, 0);
    }
    benchmark::DoNotOptimize(sum);
  }
  timer.set(state, "ns_per_point", static_cast<double>(points.size()));
  state.counters["points"] = static_cast<double>(points.size());
}
BENCHMARK(BM_UncertainMapQueryIntel)->Name("BM_UncertainMapQuery/intel");

}  // namespace
}  // namespace vdtnav
