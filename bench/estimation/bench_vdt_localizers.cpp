// One scan's solve (optimization localizer, covariance included) and one EKF update, 1081 beams,
// on the generated floor plan with thin-wall ray-cast scans (range noise 0.02 m).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "../bench_counters.hpp"
#include "vdtnav/estimation/vdt_ekf.hpp"
#include "vdtnav/estimation/vdt_optimizer.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace vdtnav {
namespace {

struct Fixture {
  sim::FloorPlan plan = sim::generate_floor_plan({});
  VdtMap2 map = VdtMap2::build(plan.occupancy);
  std::vector<Pose2> truth;
  std::vector<LaserScan> scans;

  Fixture() {
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, 0.02);
    for (std::size_t k = 0; k + 1 < plan.tour.size(); ++k) {
      const Eigen::Vector2d a = plan.tour[k], b = plan.tour[k + 1];
      const Eigen::Vector2d p = 0.5 * (a + b);
      const Pose2 x(p.x(), p.y(), std::atan2(b.y() - a.y(), b.x() - a.x()));
      LaserScan scan;
      scan.angle_min = -0.75 * M_PI;
      scan.angle_increment = 1.5 * M_PI / 1080;
      for (int i = 0; i < 1081; ++i) {
        const double ang = x[2] + scan.angle(static_cast<std::size_t>(i));
        const double r =
            sim::cast_ray<2>(plan.occupancy, p, Eigen::Vector2d(std::cos(ang), std::sin(ang)), 30.0,
                             sim::RaySurface::kCellCentre);
        scan.ranges.push_back(std::isfinite(r) ? r + noise(rng) : r);
      }
      truth.push_back(x);
      scans.push_back(std::move(scan));
    }
  }
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

void BM_VdtOptSolve2D(benchmark::State& state) {
  const auto& f = fixture();
  const VdtOptimizer opt(f.map);
  std::size_t k = 0;
  int converged = 0, solves = 0;
  double iterations = 0;
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    const ScanPoints pts = scan_points(f.scans[k]);
    const LocalizationResult r =
        opt.solve(pts, f.truth[k] + Pose2(0.05, -0.05, 0.02));  // 5 cm / 0.02 rad off
    benchmark::DoNotOptimize(r);
    converged += r.has_covariance ? 1 : 0;
    iterations += r.iterations;
    ++solves;
    k = (k + 1) % f.scans.size();
  }
  timer.set(state, "ms_per_scan", 1.0, 1e-6);
  state.counters["with_covariance_pct"] = 100.0 * converged / std::max(1, solves);
  state.counters["iterations"] = iterations / std::max(1, solves);
}
BENCHMARK(BM_VdtOptSolve2D)->Unit(benchmark::kMillisecond);

void BM_VdtEkfUpdate2D(benchmark::State& state) {
  const auto& f = fixture();
  VdtEkfLocalizer ekf(f.map);
  std::size_t k = 0;
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    ekf.reset(f.truth[k] + Pose2(0.02, -0.02, 0.01),
              Eigen::Vector3d(4e-4, 4e-4, 1e-4).asDiagonal());
    const LocalizationResult r = ekf.update(OdometryStep{}, f.scans[k]);
    benchmark::DoNotOptimize(r);
    k = (k + 1) % f.scans.size();
  }
  timer.set(state, "ms_per_scan", 1.0, 1e-6);
}
BENCHMARK(BM_VdtEkfUpdate2D)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace vdtnav
