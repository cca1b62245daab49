// Lookups of DT_v with its Jacobian (and Hessians) on a built map.
// coherent: scan-like queries, sorted along rays from a few robot poses (neighbouring queries
// touch neighbouring cells); random: uniformly scattered over the map.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "vdtnav/map/vdt_map.hpp"

namespace vdtnav {
namespace {

template <int Dim>
struct Fixture {
  using Vector = typename SpaceTraits<Dim>::Vector;
  VdtMap<Dim> map;
  std::vector<Vector> coherent, random;

  Fixture() {
    const int side = Dim == 2 ? 1024 : 128;
    OccupancyGrid<Dim> occ(SpaceTraits<Dim>::Index::Constant(side),
                           GridFrame<Dim>(0.05, Vector::Zero()), 0);
    std::mt19937 rng(1);
    std::bernoulli_distribution occupied(0.01);
    for (auto& v : occ.values()) v = occupied(rng) ? 1 : 0;
    map = VdtMap<Dim>::build(occ);
    const double extent = side * 0.05;
    std::uniform_real_distribution<double> uni(0.05 * extent, 0.95 * extent);
    const int n = 1 << 16;
    for (int i = 0; i < n; ++i) {
      Vector p;
      for (int d = 0; d < Dim; ++d) p[d] = uni(rng);
      random.push_back(p);
    }
    // Scans: beams fanning out from a pose, ranges growing smoothly like a LiDAR sweep.
    const int beams = 1081;
    for (int s = 0; static_cast<int>(coherent.size()) < n; ++s) {
      Vector centre;
      for (int d = 0; d < Dim; ++d) centre[d] = uni(rng);
      for (int b = 0; b < beams; ++b) {
        const double a = -2.35 + 4.7 * b / (beams - 1);
        const double r = 0.3 + 0.2 * extent * (1.0 + std::sin(3.0 * a)) / 2.0;
        Vector p = centre;
        p[0] += r * std::cos(a);
        p[1] += r * std::sin(a);
        coherent.push_back(p);
      }
    }
    coherent.resize(static_cast<std::size_t>(n));
  }
};

template <int Dim>
const Fixture<Dim>& fixture() {
  static const Fixture<Dim> f;
  return f;
}

template <int Dim, bool kHessian>
void lookup(benchmark::State& state, bool coherent) {
  const auto& f = fixture<Dim>();
  const auto& pts = coherent ? f.coherent : f.random;
  std::size_t i = 0;
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
  state.counters["ns_per_point"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * 1e-9,
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// Registered by name so that the names stay exactly BM_VdtLookup<...>/<coherent|random>.
const bool kRegistered = [] {
  benchmark::RegisterBenchmark("BM_VdtLookupGradient2D/coherent",
                               [](benchmark::State& s) { lookup<2, false>(s, true); });
  benchmark::RegisterBenchmark("BM_VdtLookupGradient2D/random",
                               [](benchmark::State& s) { lookup<2, false>(s, false); });
  benchmark::RegisterBenchmark("BM_VdtLookupHessian2D/coherent",
                               [](benchmark::State& s) { lookup<2, true>(s, true); });
  benchmark::RegisterBenchmark("BM_VdtLookupGradient3D/coherent",
                               [](benchmark::State& s) { lookup<3, false>(s, true); });
  benchmark::RegisterBenchmark("BM_VdtLookupGradient3D/random",
                               [](benchmark::State& s) { lookup<3, false>(s, false); });
  return true;
}();

}  // namespace
}  // namespace vdtnav
