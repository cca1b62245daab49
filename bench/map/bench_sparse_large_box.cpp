// BM_VdtBuild3DSparseLargeBox: SparseVdtMap3::build of a 200 x 200 x 20 m building at 0.1 m
// (800 M voxels: a floor, outer walls, interior walls every 25 m with doors, 3000 boxes), the
// issue's "a box like CATEC's, but a building" memory test. Counters: peak_rss_mb (the process's
// peak resident memory, input list included), MB (the map), ns_per_cell. It takes about a minute
// and 1.3 GB, so it is registered only with VDTNAV_BENCH_LARGE=1:
//   VDTNAV_BENCH_LARGE=1 build/release/bench/bench_map --benchmark_filter=LargeBox
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "../bench_counters.hpp"
#include "vdtnav/map/sparse_vdt_map.hpp"

namespace vdtnav {
namespace {

std::vector<Eigen::Vector3i> large_building() {
  std::vector<Eigen::Vector3i> occ;
  const auto box = [&](int x0, int x1, int y0, int y1, int z0, int z1) {
    for (int z = z0; z < z1; ++z)
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) occ.emplace_back(x, y, z);
  };
  box(0, 2000, 0, 2000, 0, 2);  // floor, 0.2 m
  box(0, 2000, 0, 2, 0, 60);    // outer walls, 6 m high
  box(0, 2000, 1998, 2000, 0, 60);
  box(0, 2, 0, 2000, 0, 60);
  box(1998, 2000, 0, 2000, 0, 60);
  for (int k = 250; k < 2000; k += 250) {  // interior walls, a 3 m door every 12.5 m
    for (int s = 0; s < 2000; s += 125) {
      box(k, k + 2, s + 30, s + 125, 0, 60);
      box(s + 30, s + 125, k, k + 2, 0, 60);
    }
  }
  std::mt19937 rng(1);
  std::uniform_int_distribution<int> at(10, 1980), side(3, 15);
  for (int i = 0; i < 3000; ++i) {
    const int x = at(rng), y = at(rng), sx = side(rng), sy = side(rng), sz = side(rng);
    box(x, x + sx, y, y + sy, 2, 2 + sz);
  }
  return occ;
}

void BM_VdtBuild3DSparseLargeBox(benchmark::State& state) {
  const std::vector<Eigen::Vector3i> occupied = large_building();
  const Eigen::Vector3i size(2000, 2000, 200);
  const double cells = size.cast<double>().prod();
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    const SparseVdtMap3 map =
        SparseVdtMap3::build(occupied, GridFrame<3>(0.1, Eigen::Vector3d::Zero()), size);
    state.counters["MB"] = static_cast<double>(map.memory_bytes()) * 1e-6;
    state.counters["bricks"] = static_cast<double>(map.bricks().num_bricks);
  }
  timer.set(state, "ns_per_cell", cells);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  state.counters["peak_rss_mb"] = static_cast<double>(usage.ru_maxrss) / 1024.0;  // kB on Linux
  state.counters["occupied"] = static_cast<double>(occupied.size());
}

const bool registered = [] {
  const char* on = std::getenv("VDTNAV_BENCH_LARGE");
  if (on != nullptr && std::string(on) == "1") {
    benchmark::RegisterBenchmark("BM_VdtBuild3DSparseLargeBox", BM_VdtBuild3DSparseLargeBox)
        ->Unit(benchmark::kSecond)
        ->Iterations(1);
  }
  return true;
}();

}  // namespace
}  // namespace vdtnav
