// One scan's solve (optimization localizer, covariance included) and one EKF update, 1081 beams,
// on the generated floor plan with thin-wall ray-cast scans (range noise 0.02 m); and one 6-DOF
// solve of a pan-tilt point-laser cloud (thesis 3.4.4: 5700 points, or every 100th) in a 3D room.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include <Eigen/Geometry>

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

/// One scan's solve with its covariance by the given solver.
void solve_2d(benchmark::State& state, ScanSolver solver) {
  const auto& f = fixture();
  VdtOptimizerOptions o;
  o.solver = solver;
  const VdtOptimizer opt(f.map, o);
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
/// The default dense Levenberg-Marquardt and, for the ratio in the same run, Ceres.
void BM_VdtOptSolve2D(benchmark::State& state) { solve_2d(state, ScanSolver::kDense); }
void BM_VdtOptSolve2DCeres(benchmark::State& state) { solve_2d(state, ScanSolver::kCeres); }
BENCHMARK(BM_VdtOptSolve2D)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VdtOptSolve2DCeres)->Unit(benchmark::kMillisecond);

void BM_VdtEkfUpdate2D(benchmark::State& state) {
  const auto& f = fixture();
  VdtEkfLocalizer ekf(f.map, VdtEkfOptions{});
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

/// An 8 m x 6 m x 3 m room at 0.05 m (0.5 m thick walls, floor and ceiling) with a cabinet, a
/// crate, two pillars, a table and a soffit, every face on a cell-centre plane; pan-tilt sweeps of
/// 95 x 60 = 5700 readings (sigma_r = 0.025 m, the LIDAR-Lite v3's) from robots rolled and
/// pitched a few degrees (3.4.4.2's uneven floor).
struct Fixture3D {
  OccupancyGrid<3> occupancy = room();
  VdtMap3 map = VdtMap3::build(occupancy);
  std::vector<Pose3> truth;
  std::vector<ObservationSet3> clouds;

  static OccupancyGrid<3> room() {
    using B = Eigen::AlignedBox3d;
    using V = Eigen::Vector3d;
    const double res = 0.05;
    const int wall = 10, margin = 1;
    const V extent(8.0, 6.0, 3.0);
    const std::vector<B> solids = {
        B(V(1.0, 4.5, 0.0), V(2.0, 6.0, 1.8)),    B(V(5.5, 0.0, 0.0), V(6.5, 0.8, 1.0)),
        B(V(6.0, 3.0, 0.0), V(6.3, 3.3, 3.0)),    B(V(3.5, 4.8, 0.0), V(3.7, 5.0, 3.0)),
        B(V(4.0, 1.5, 0.65), V(5.0, 2.5, 0.8)),   B(V(4.0, 1.5, 0.0), V(4.15, 1.65, 0.65)),
        B(V(4.85, 1.5, 0.0), V(5.0, 1.65, 0.65)), B(V(4.0, 2.35, 0.0), V(4.15, 2.5, 0.65)),
        B(V(4.85, 2.35, 0.0), V(5.0, 2.5, 0.65)), B(V(0.0, 0.0, 2.6), V(8.0, 0.4, 3.0))};
    Eigen::Vector3i size;
    for (int d = 0; d < 3; ++d)
      size[d] = static_cast<int>(std::lround(extent[d] / res)) + 2 * (margin + wall) - 1;
    OccupancyGrid<3> occ(size, GridFrame<3>(res, V::Constant(-(margin + wall - 0.5) * res)), 0);
    const double eps = 1e-6;
    for (int k = 0; k < size.z(); ++k)
      for (int j = 0; j < size.y(); ++j)
        for (int i = 0; i < size.x(); ++i) {
          const Eigen::Vector3i c(i, j, k);
          const V p = occ.cell_center(c);
          const bool shell = (p.array() > -wall * res + eps).all() &&
                             (p.array() < (extent.array() + wall * res - eps)).all();
          bool solid =
              shell && ((p.array() < eps).any() || (p.array() > extent.array() - eps).any());
          for (const B& b : solids)
            solid |= (p.array() >= b.min().array() - eps).all() &&
                     (p.array() <= b.max().array() + eps).all();
          occ(c) = solid ? 1 : 0;
        }
    return occ;
  }

  Fixture3D() {
    std::mt19937 rng(11);
    std::normal_distribution<double> noise(0.0, 0.025);
    const Eigen::Vector3d origin(0.0, 0.0, 0.4);  // beam origin in the robot frame
    for (const Pose3& x : {pose3_from_xyz_rpy(3.1, 2.9, 0.03, 0.04, -0.03, 0.35),
                           pose3_from_xyz_rpy(2.3, 1.7, 0.05, -0.05, 0.02, -2.2),
                           pose3_from_xyz_rpy(6.9, 4.4, 0.02, 0.03, 0.05, 1.9)}) {
      ObservationSet3 cloud;
      cloud.sigma_range = 0.025;
      std::size_t index = 0;
      for (int a = 0; a < 95; ++a) {
        const double pan = -M_PI + 2.0 * M_PI * (a + 0.5) / 95;
        for (int b = 0; b < 60; ++b, ++index) {
          const double tilt = -0.7 + 1.9 * b / 59;  // positive looks down
          const Eigen::Vector3d u(std::cos(pan) * std::cos(tilt), std::sin(pan) * std::cos(tilt),
                                  -std::sin(tilt));
          const double r = sim::cast_ray<3>(occupancy, x * origin, x.linear() * u, 40.0,
                                            sim::RaySurface::kCellCentre);
          if (std::isfinite(r)) cloud.add(origin, u, r + noise(rng), index);
        }
      }
      truth.push_back(x);
      clouds.push_back(std::move(cloud));
    }
  }
};

const Fixture3D& fixture3d() {
  static const Fixture3D f;
  return f;
}

/// One 6-DOF solve with its covariance, from Table 3.4's scenario B (x, y, z +0.1 m; roll, pitch,
/// yaw +0.05 rad). Argument: points per cloud (5700, or 57 = every 100th).
void solve_3d(benchmark::State& state, ScanSolver solver) {
  const auto& f = fixture3d();
  VdtOptimizerOptions o;
  o.solver = solver;
  const VdtOptimizer3 opt(f.map, o);
  const std::size_t step = 5700 / static_cast<std::size_t>(state.range(0));
  std::vector<ObservationSet3> clouds;
  std::vector<Pose3> guesses;
  for (std::size_t k = 0; k < f.clouds.size(); ++k) {
    clouds.push_back(f.clouds[k].subsampled(step));
    const Eigen::Vector3d t = f.truth[k].translation() + Eigen::Vector3d::Constant(0.1);
    const Eigen::Vector3d rpy = rpy_of(f.truth[k].linear()) + Eigen::Vector3d::Constant(0.05);
    guesses.push_back(pose3_from_xyz_rpy(t.x(), t.y(), t.z(), rpy[0], rpy[1], rpy[2]));
  }
  std::size_t k = 0;
  int with_covariance = 0, solves = 0;
  double iterations = 0, error = 0;
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    const LocalizationResult3 r = opt.solve(clouds[k], guesses[k]);
    benchmark::DoNotOptimize(r);
    with_covariance += r.has_covariance ? 1 : 0;
    iterations += r.iterations;
    error += (r.pose.translation() - f.truth[k].translation()).norm();
    ++solves;
    k = (k + 1) % clouds.size();
  }
  timer.set(state, "ms_per_solve", 1.0, 1e-6);
  state.counters["points"] = static_cast<double>(clouds[0].size());
  state.counters["with_covariance_pct"] = 100.0 * with_covariance / std::max(1, solves);
  state.counters["iterations"] = iterations / std::max(1, solves);
  state.counters["error_mm"] = 1e3 * error / std::max(1, solves);
}
void BM_VdtOptSolve3D(benchmark::State& state) { solve_3d(state, ScanSolver::kDense); }
void BM_VdtOptSolve3DCeres(benchmark::State& state) { solve_3d(state, ScanSolver::kCeres); }
BENCHMARK(BM_VdtOptSolve3D)->Arg(5700)->Arg(57)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VdtOptSolve3DCeres)->Arg(5700)->Arg(57)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace vdtnav
