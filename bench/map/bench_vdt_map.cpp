// Lookups of DT_v with its Jacobian (and Hessians) on built maps.
// coherent: scan-like queries in scan order — endpoints of simulated LiDAR scans (2D: 1081 beams
//           over 270 degrees from poses along the generated floor plan's tour; 3D: pan-tilt
//           sweeps in the floor plan extruded to a 3 m storey with floor and ceiling);
// random:   uniformly scattered over the map.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "../bench_counters.hpp"
#include "vdtnav/map/sparse_vdt_map.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/sim/floor_plan.hpp"
#include "vdtnav/sim/ray_casting.hpp"

namespace vdtnav {
namespace {

template <int Dim>
struct Fixture {
  using Vector = typename SpaceTraits<Dim>::Vector;
  VdtMap<Dim> map;
  std::vector<Vector> coherent, random;
  double bytes_per_cell = 0.0;
  SparseVdtMap3 sparse;  ///< 3D: the same occupancy as bricks (default band, 3 voxels)
  double sparse_bytes_per_cell = 0.0;
};

/// The generated floor plan (40 m x 18 m, 0.05 m cells) and scans from its tour.
const Fixture<2>& fixture2() {
  static const Fixture<2> f = [] {
    Fixture<2> f;
    const auto plan = sim::generate_floor_plan({});
    f.map = VdtMap<2>::build(plan.occupancy);
    f.bytes_per_cell = static_cast<double>(f.map.memory_bytes()) / plan.occupancy.num_cells();
    for (std::size_t k = 0; k + 1 < plan.tour.size(); ++k) {
      const Eigen::Vector2d p = 0.5 * (plan.tour[k] + plan.tour[k + 1]);
      const double heading = std::atan2(plan.tour[k + 1].y() - plan.tour[k].y(),
                                        plan.tour[k + 1].x() - plan.tour[k].x());
      for (int b = 0; b < 1081; ++b) {
        const double a = heading - 0.75 * kPi + 1.5 * kPi * b / 1080;
        const Eigen::Vector2d dir(std::cos(a), std::sin(a));
        const double r = sim::cast_ray<2>(plan.occupancy, p, dir, 30.0);
        if (std::isfinite(r)) f.coherent.push_back(p + r * dir);
      }
    }
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> ux(0.0, 40.0), uy(0.0, 18.0);
    for (int i = 0; i < 1 << 16; ++i) f.random.emplace_back(ux(rng), uy(rng));
    return f;
  }();
  return f;
}

/// The floor plan extruded to a storey (0.1 m voxels, 3 m high, floor and ceiling) and pan-tilt
/// sweeps (pan -180..180 degrees, tilt -30..30 degrees) from points of the tour at 0.5 m.
const Fixture<3>& fixture3() {
  static const Fixture<3> f = [] {
    Fixture<3> f;
    sim::FloorPlanOptions o;
    o.resolution = 0.1;
    o.wall_thickness = 0.2;
    const auto plan = sim::generate_floor_plan(o);
    const Eigen::Vector2i n2 = plan.occupancy.size();
    const int nz = 32;
    OccupancyGrid<3> occ(Eigen::Vector3i(n2.x(), n2.y(), nz),
                         GridFrame<3>(0.1, Eigen::Vector3d(0, 0, -0.1)), 0);
    for (int z = 0; z < nz; ++z)
      for (int y = 0; y < n2.y(); ++y)
        for (int x = 0; x < n2.x(); ++x)
          occ(Eigen::Vector3i(x, y, z)) =
              (z == 0 || z == nz - 1 || plan.occupancy(Eigen::Vector2i(x, y))) ? 1 : 0;
    f.map = VdtMap<3>::build(occ);
    f.bytes_per_cell = static_cast<double>(f.map.memory_bytes()) / occ.num_cells();
    f.sparse = SparseVdtMap3::build(occ);
    f.sparse_bytes_per_cell = static_cast<double>(f.sparse.memory_bytes()) / occ.num_cells();
    for (std::size_t k = 0; k + 1 < plan.tour.size() && f.coherent.size() < (1u << 16); k += 3) {
      const Eigen::Vector3d p(plan.tour[k].x(), plan.tour[k].y(), 0.5);
      for (int t = 0; t < 19; ++t) {
        const double tilt = (-30.0 + 60.0 * t / 18) * kPi / 180;
        for (int pan = 0; pan < 300; ++pan) {
          const double a = -kPi + 2 * kPi * pan / 300;
          const Eigen::Vector3d dir(std::cos(tilt) * std::cos(a), std::cos(tilt) * std::sin(a),
                                    std::sin(tilt));
          const double r = sim::cast_ray<3>(occ, p, dir, 40.0);
          if (std::isfinite(r)) f.coherent.push_back(p + r * dir);
        }
      }
    }
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> ux(0.0, 40.0), uy(0.0, 18.0), uz(0.0, 3.0);
    for (int i = 0; i < 1 << 16; ++i) f.random.emplace_back(ux(rng), uy(rng), uz(rng));
    return f;
  }();
  return f;
}

/// The batch form (VdtMap::evaluate over a span of points), as the estimators call it: scans of
/// `batch` consecutive points.
template <int Dim>
void lookup_batch(benchmark::State& state, const VdtField<Dim>& map,
                  const std::vector<typename SpaceTraits<Dim>::Vector>& pts, double bytes_per_cell,
                  std::size_t batch) {
  std::vector<VdtSample<Dim>> out(batch);
  std::size_t i = 0;
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    map.evaluate(pts.data() + i, batch, out.data());
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
    i += batch;
    if (i + batch > pts.size()) i = 0;
  }
  timer.set(state, "ns_per_point", static_cast<double>(batch));
  state.counters["points"] = static_cast<double>(pts.size());
  state.counters["bytes_per_cell"] = bytes_per_cell;
  state.counters["avx2"] = simd_level() == SimdLevel::kAvx2Fma ? 1.0 : 0.0;
}

template <int Dim, bool kHessian>
void lookup(benchmark::State& state, const Fixture<Dim>& f, bool coherent) {
  const auto& pts = coherent ? f.coherent : f.random;
  std::size_t i = 0;
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    if constexpr (kHessian) {
      auto s = f.map.evaluate_with_hessian(pts[i]);
      benchmark::DoNotOptimize(s);
    } else {
      auto s = f.map.evaluate(pts[i]);
      benchmark::DoNotOptimize(s);
    }
    if (++i == pts.size()) i = 0;
  }
  timer.set(state, "ns_per_point", 1.0);
  state.counters["points"] = static_cast<double>(pts.size());
  state.counters["bytes_per_cell"] = f.bytes_per_cell;
}

/// The sparse map on the same points as lookup<3, false> (the dense BM_VdtLookupGradient3D).
void lookup_sparse(benchmark::State& state, const Fixture<3>& f, bool coherent) {
  const auto& pts = coherent ? f.coherent : f.random;
  std::size_t i = 0, fine = 0;
  for (const auto& p : pts) fine += f.sparse.fine_level(p);
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    auto s = f.sparse.evaluate(pts[i]);
    benchmark::DoNotOptimize(s);
    if (++i == pts.size()) i = 0;
  }
  timer.set(state, "ns_per_point", 1.0);
  state.counters["points"] = static_cast<double>(pts.size());
  state.counters["fine_fraction"] = static_cast<double>(fine) / static_cast<double>(pts.size());
  state.counters["bytes_per_cell"] = f.sparse_bytes_per_cell;
}

// Registered by name so that the names stay exactly BM_VdtLookup<...>/<coherent|random>.
const bool kRegistered = [] {
  benchmark::RegisterBenchmark("BM_VdtLookupGradient2D/coherent",
                               [](benchmark::State& s) { lookup<2, false>(s, fixture2(), true); });
  benchmark::RegisterBenchmark("BM_VdtLookupGradient2D/random",
                               [](benchmark::State& s) { lookup<2, false>(s, fixture2(), false); });
  benchmark::RegisterBenchmark("BM_VdtLookupHessian2D/coherent",
                               [](benchmark::State& s) { lookup<2, true>(s, fixture2(), true); });
  benchmark::RegisterBenchmark("BM_VdtLookupGradient3D/coherent",
                               [](benchmark::State& s) { lookup<3, false>(s, fixture3(), true); });
  benchmark::RegisterBenchmark("BM_VdtLookupGradient3D/random",
                               [](benchmark::State& s) { lookup<3, false>(s, fixture3(), false); });
  benchmark::RegisterBenchmark("BM_VdtLookupGradient3DSparse/coherent",
                               [](benchmark::State& s) { lookup_sparse(s, fixture3(), true); });
  benchmark::RegisterBenchmark("BM_VdtLookupGradient3DSparse/random",
                               [](benchmark::State& s) { lookup_sparse(s, fixture3(), false); });
  benchmark::RegisterBenchmark("BM_VdtLookupGradient2D/coherent_batch", [](benchmark::State& s) {
    lookup_batch<2>(s, fixture2().map, fixture2().coherent, fixture2().bytes_per_cell, 1081);
  });
  benchmark::RegisterBenchmark("BM_VdtLookupGradient3D/coherent_batch", [](benchmark::State& s) {
    lookup_batch<3>(s, fixture3().map, fixture3().coherent, fixture3().bytes_per_cell, 1081);
  });
  benchmark::RegisterBenchmark(
      "BM_VdtLookupGradient3DSparse/coherent_batch",
      [](benchmark::State& s) {  // the same scans: the kernels prefetch the next points' bricks
        lookup_batch<3>(s, fixture3().sparse, fixture3().coherent, fixture3().sparse_bytes_per_cell,
                        1081);
      });
  return true;
}();

}  // namespace
}  // namespace vdtnav
