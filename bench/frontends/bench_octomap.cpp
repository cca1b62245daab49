// The 3D build on a real map: the CATEC hangar OctoMap (DLL dataset, 0.05 m voxels) loaded
// through vdtnav::octomap at the tree's resolution, no margin (the box of the occupied leaves).
//   BM_VdtBuild3DOctomap:    the exact transform alone (nearest_occupied_cells), the quantity the
//                            "3D build <= 25 ns/voxel" target and BM_VdtBuild3D measure;
//   BM_VdtMapBuild3DOctomap: the whole VdtMap3::build (surface cells, transform, DT_v samples and
//                            the spline prefilter of every component), as BM_VdtMapBuild3D.
//   BM_VdtBuild3DSparse/pool_threads:<n>: SparseVdtMap3::build from the list of occupied voxels
//                            (default band, 3 voxels), no dense grid, at 1 and 2 threads of the
//                            pool (ms, ms_1_thread, speedup: bench_counters.hpp); bytes_per_cell
//                            is the sparse map's memory per voxel of the box
//                            (BM_VdtMapBuild3DOctomap's is the dense map's).
// ns_per_cell is the build time per voxel of the grid.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "../bench_counters.hpp"
#include "vdtnav/map/sparse_vdt_map.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/map/vector_distance_transform.hpp"
#include "vdtnav/octomap/octree_map.hpp"

namespace vdtnav {
namespace {

struct Catec {
  OctreeOccupancy occ;
  std::string error;  ///< why the benchmarks cannot run, empty when they can
};

const Catec& catec() {
  static const Catec c = [] {
    Catec c;
    const std::string path = std::string(VDTNAV_DATA_DIR) + "/3d/dll-catec/catec.bt";
    if (!std::filesystem::exists(path)) {
      c.error = "CATEC OctoMap not found at " + path;
      return c;
    }
    try {
      c.occ = load_octree_occupancy(path, {});
    } catch (const Error& e) {
      c.error = e.what();
    }
    return c;
  }();
  return c;
}

void set_map_counters(benchmark::State& state, const OctreeOccupancy& occ) {
  state.counters["voxels"] = static_cast<double>(occ.occupancy.num_cells());
  state.counters["occupied"] = static_cast<double>(occ.num_occupied);
}

void BM_VdtBuild3DOctomap(benchmark::State& state) {
  const Catec& c = catec();
  if (!c.error.empty()) {
    state.SkipWithError(c.error.c_str());
    return;
  }
  const OccupancyGrid<3>& occ = c.occ.occupancy;
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    auto nearest = nearest_occupied_cells(occ);
    benchmark::DoNotOptimize(nearest.data());
  }
  timer.set(state, "ns_per_cell", static_cast<double>(occ.num_cells()));
  set_map_counters(state, c.occ);
}
BENCHMARK(BM_VdtBuild3DOctomap)->Unit(benchmark::kMillisecond);

void BM_VdtMapBuild3DOctomap(benchmark::State& state) {
  const Catec& c = catec();
  if (!c.error.empty()) {
    state.SkipWithError(c.error.c_str());
    return;
  }
  const OccupancyGrid<3>& occ = c.occ.occupancy;
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    auto map = VdtMap3::build(occ);
    benchmark::DoNotOptimize(map.field().coefficients().data());
    state.counters["bytes_per_cell"] =
        static_cast<double>(map.memory_bytes()) / static_cast<double>(occ.num_cells());
  }
  timer.set(state, "ns_per_cell", static_cast<double>(occ.num_cells()));
  set_map_counters(state, c.occ);
}
BENCHMARK(BM_VdtMapBuild3DOctomap)->Unit(benchmark::kMillisecond);

void BM_VdtBuild3DSparse(benchmark::State& state) {
  const Catec& c = catec();
  if (!c.error.empty()) {
    state.SkipWithError(c.error.c_str());
    return;
  }
  const OccupancyGrid<3>& occ = c.occ.occupancy;
  std::vector<Eigen::Vector3i> occupied;
  for (std::size_t k = 0; k < occ.num_cells(); ++k) {
    if (occ[k] != 0) occupied.push_back(occ.index_of(static_cast<std::ptrdiff_t>(k)));
  }
  SparseVdtMap3 map;
  bench::thread_scaling(state, static_cast<int>(state.range(0)), [&](std::size_t) {
    map = SparseVdtMap3::build(occupied, occ.frame(), occ.size());
    benchmark::DoNotOptimize(map.bricks().coefficients);
  });
  state.counters["bytes_per_cell"] =
      static_cast<double>(map.memory_bytes()) / static_cast<double>(occ.num_cells());
  state.counters["bricks"] = static_cast<double>(map.bricks().num_bricks);
  state.counters["MB"] = static_cast<double>(map.memory_bytes()) * 1e-6;
  state.counters["ns_per_cell"] = 1e6 * state.counters["ms"] / static_cast<double>(occ.num_cells());
  set_map_counters(state, c.occ);
}
BENCHMARK(BM_VdtBuild3DSparse)->Apply(bench::pool_threads_1_and_2)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace vdtnav
