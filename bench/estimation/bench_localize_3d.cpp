// BM_Localize3DScan/<points>: one update of the sequential 3D localizer (vdt-opt-6dof,
// VdtOptimizationLocalizer3) on a simulated VLP-16 scan of the generated 3D room (0.05 m voxels),
// thinned to <points> readings, from a prediction 3 cm / 0.01 rad off: the per-scan cost of
// tracking (issue: <= 10 ms per scan at 2000 points). Counters: ms_per_scan, points, error_mm.
// BM_Localize3DScanMultiStart/pool_threads:<n>: `vdtnav localize3d --multi-start`'s solve (the
// axis starts, then the attitude grid, n = 2) of the same scans thinned to 2000 readings, from a
// guess 0.3 rad off about every axis, at 1 and 2 threads of the pool; counters ms, ms_1_thread,
// speedup (bench_counters.hpp) and error_mm.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "../bench_counters.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/estimation/multi_start.hpp"
#include "vdtnav/estimation/recovering_localizer3d.hpp"
#include "vdtnav/sim/lidar3d_simulator.hpp"
#include "vdtnav/sim/room3d.hpp"

namespace vdtnav {
namespace {

struct Fixture {
  sim::Room3d room = sim::generate_room3d({});
  VdtMap3 map = VdtMap3::build(room.occupancy);
  std::vector<Pose3> truth;
  std::vector<ObservationSet3> scans;  // full scans; thinned per benchmark argument

  Fixture() {
    std::mt19937 rng(1);
    const sim::Lidar3dSpec vlp16;
    for (int k = 0; k < 8; ++k) {
      const Pose3 x =
          pose3_from_xyz_rpy(1.5 + 0.7 * k, 2.5 + 0.2 * (k % 3), 1.2, 0.02, -0.01, 0.3 * k);
      const sim::Lidar3dScan s = sim::simulate_lidar3d_scan(room.occupancy, x, vlp16, rng);
      ObservationSet3 obs = sim::lidar3d_observations(s, vlp16);
      truth.push_back(x);
      scans.push_back(std::move(obs));
    }
  }
};

void BM_Localize3DScan(benchmark::State& state) {
  static const Fixture f;
  const std::size_t points = static_cast<std::size_t>(state.range(0));
  std::vector<ObservationSet3> scans;
  for (const ObservationSet3& s : f.scans)
    scans.push_back(s.subsampled(std::max<std::size_t>(1, s.size() / points)));
  // The tracker with lost detection, as vdtnav localize3d runs it; the exact-map options (a
  // generated room: no robust loss, no map-error correlation).
  RecoveringLocalizer3 loc(f.map, VdtLocalizer3Options{});
  Matrix6d p = Matrix6d::Zero();
  p.diagonal() << 1e-3, 1e-3, 1e-3, 1e-4, 1e-4, 1e-4;
  Vector6d off;
  off << 0.03, -0.03, 0.03, 0.01, -0.01, 0.01;
  OdometryStep3 still;
  still.dt = 0.1;
  std::size_t k = 0;
  double error = 0.0;
  int n = 0;
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    loc.reset(oplus(f.truth[k], off), p);  // a pose and a matrix copied: not worth pausing for
    const LocalizationResult3 r = loc.update(still, scans[k]);
    benchmark::DoNotOptimize(r);
    error += (r.pose.translation() - f.truth[k].translation()).norm();
    ++n;
    k = (k + 1) % scans.size();
  }
  timer.set(state, "ms_per_scan", 1.0, 1e-6);
  state.counters["points"] = static_cast<double>(scans[0].size());
  state.counters["error_mm"] = 1e3 * error / std::max(1, n);
}
BENCHMARK(BM_Localize3DScan)->Arg(2000)->Unit(benchmark::kMillisecond);

void BM_Localize3DScanMultiStart(benchmark::State& state) {
  static const Fixture f;
  std::vector<ObservationSet3> scans;
  for (const ObservationSet3& s : f.scans)
    scans.push_back(s.subsampled(std::max<std::size_t>(1, s.size() / 2000)));
  const VdtLocalizer3Options o = vdt_localizer3_defaults();
  const VdtOptimizer3 optimizer(f.map, o.optimizer);
  MultiStartOptions ms = o.multi_start;
  ms.enabled = true;
  ms.attitude_grid = 2;  // --multi-start
  Vector6d off = Vector6d::Zero();
  off.tail<3>() << 0.3, -0.3, 0.3;
  double error = 0.0;
  int n = 0;
  bench::thread_scaling(state, static_cast<int>(state.range(0)), [&](std::size_t k) {
    const std::size_t i = k % scans.size();
    const LocalizationResult3 r =
        solve_multi_start(optimizer, scans[i], oplus(f.truth[i], off), ms);
    benchmark::DoNotOptimize(r);
    error += (r.pose.translation() - f.truth[i].translation()).norm();
    ++n;
  });
  state.counters["error_mm"] = 1e3 * error / std::max(1, n);
}
BENCHMARK(BM_Localize3DScanMultiStart)
    ->Apply(bench::pool_threads_1_and_2)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace vdtnav
