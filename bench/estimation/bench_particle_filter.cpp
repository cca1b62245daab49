// One update of the AMCL-style particle filter (2000 particles, 60 of 1081 beams) on the generated
// floor plan: prediction, likelihood-field weighting, estimate and resampling.
#include <benchmark/benchmark.h>

#include <cmath>
#include <vector>

#include "../bench_counters.hpp"
#include "vdtnav/estimation/particle_filter.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace vdtnav {
namespace {

struct Fixture {
  OccupancyGrid<2> occupancy;
  Pose2 pose = Pose2::Zero();
  LaserScan scan;
};

/// The generated floor plan and a 1081-beam 270 degree scan from a point of its tour.
const Fixture& fixture() {
  static const Fixture f = [] {
    Fixture f;
    auto plan = sim::generate_floor_plan({});
    const Eigen::Vector2d a = plan.tour[2], b = plan.tour[3];
    f.pose = Pose2(0.5 * (a.x() + b.x()), 0.5 * (a.y() + b.y()),
                   std::atan2(b.y() - a.y(), b.x() - a.x()));
    f.scan.angle_min = -0.75 * kPi;
    f.scan.angle_increment = 1.5 * kPi / 1080;
    f.scan.range_max = 30.0;
    for (int k = 0; k < 1081; ++k) {
      const double angle = f.pose[2] + f.scan.angle(static_cast<std::size_t>(k));
      f.scan.ranges.push_back(sim::cast_ray<2>(plan.occupancy, f.pose.head<2>(),
                                               Eigen::Vector2d(std::cos(angle), std::sin(angle)),
                                               f.scan.range_max));
    }
    f.occupancy = std::move(plan.occupancy);
    return f;
  }();
  return f;
}

void BM_ParticleFilterUpdate2D(benchmark::State& state) {
  const Fixture& f = fixture();
  ParticleFilterOptions options;  // 2000 particles, 60 beams, amcl defaults
  ParticleFilterLocalizer pf(f.occupancy, options);
  pf.reset(f.pose, Eigen::Vector3d(0.1 * 0.1, 0.1 * 0.1, 0.05 * 0.05).asDiagonal());
  OdometryStep odometry;
  // Back and forth by 5 cm so that the robot stays where the scan was taken.
  double sign = 1.0;
  int converged = 0;
  (void)pf.update(odometry, f.scan);  // tabulates the log-likelihood for this range_max
  bench::PerItemTimer timer;
  for (auto _ : state) {
    odometry.delta = Pose2(0.05 * sign, 0.0, 0.0);
    sign = -sign;
    const LocalizationResult r = pf.update(odometry, f.scan);
    converged += r.status == LocalizationStatus::kConverged;
    benchmark::DoNotOptimize(r);
  }
  timer.set(state, "ms_per_scan", 1.0, 1e-6);
  state.counters["particles"] = static_cast<double>(pf.particles().size());
  if (converged != static_cast<int>(state.iterations())) state.SkipWithError("an update failed");
}
BENCHMARK(BM_ParticleFilterUpdate2D)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace vdtnav
