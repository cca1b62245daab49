// Building the exact VDT (feature transform) against OpenCV's exact Euclidean distance transform
// (cv::distanceTransform, DIST_L2, DIST_MASK_PRECISE: distances only) on the same input.
#include <benchmark/benchmark.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <random>

#include "../bench_counters.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/map/vector_distance_transform.hpp"

namespace vdtnav {
namespace {

template <int Dim>
OccupancyGrid<Dim> random_occupancy(int side, double p, unsigned seed = 42) {
  OccupancyGrid<Dim> occ(SpaceTraits<Dim>::Index::Constant(side),
                         GridFrame<Dim>(0.05, SpaceTraits<Dim>::Vector::Zero()), 0);
  std::mt19937 rng(seed);
  std::bernoulli_distribution occupied(p);
  for (auto& v : occ.values()) v = occupied(rng) ? 1 : 0;
  return occ;
}

void BM_VdtBuild2D(benchmark::State& state) {
  const auto occ = random_occupancy<2>(static_cast<int>(state.range(0)), 0.01);
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    auto nearest = nearest_occupied_cells(occ);
    benchmark::DoNotOptimize(nearest.data());
  }
  timer.set(state, "ns_per_cell", static_cast<double>(occ.num_cells()));
}
BENCHMARK(BM_VdtBuild2D)->Arg(4096)->Unit(benchmark::kMillisecond);

void BM_OpenCvDistanceTransform2D(benchmark::State& state) {
  cv::setNumThreads(1);  // one thread, like ours
  const int n = static_cast<int>(state.range(0));
  const auto occ = random_occupancy<2>(n, 0.01);
  // distanceTransform measures distance to the nearest zero pixel: occupied = 0.
  cv::Mat src(n, n, CV_8UC1);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) src.at<std::uint8_t>(y, x) = occ(Eigen::Vector2i(x, y)) ? 0 : 255;
  cv::Mat dist;
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    cv::distanceTransform(src, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
    benchmark::DoNotOptimize(dist.data);
  }
  timer.set(state, "ns_per_cell", static_cast<double>(occ.num_cells()));
}
BENCHMARK(BM_OpenCvDistanceTransform2D)->Arg(4096)->Unit(benchmark::kMillisecond);

void BM_VdtBuild3D(benchmark::State& state) {
  const auto occ = random_occupancy<3>(static_cast<int>(state.range(0)), 0.01);
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    auto nearest = nearest_occupied_cells(occ);
    benchmark::DoNotOptimize(nearest.data());
  }
  timer.set(state, "ns_per_cell", static_cast<double>(occ.num_cells()));
}
BENCHMARK(BM_VdtBuild3D)->Arg(256)->Unit(benchmark::kMillisecond);

// The whole continuous map: feature transform + DT_v samples + prefilter of every component.
void BM_VdtMapBuild2D(benchmark::State& state) {
  const auto occ = random_occupancy<2>(static_cast<int>(state.range(0)), 0.01);
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    auto map = VdtMap<2>::build(occ);
    benchmark::DoNotOptimize(map.field().coefficients().data());
    state.counters["bytes_per_cell"] =
        static_cast<double>(map.memory_bytes()) / static_cast<double>(occ.num_cells());
  }
  timer.set(state, "ns_per_cell", static_cast<double>(occ.num_cells()));
}
BENCHMARK(BM_VdtMapBuild2D)->Arg(4096)->Unit(benchmark::kMillisecond);

void BM_VdtMapBuild3D(benchmark::State& state) {
  const auto occ = random_occupancy<3>(static_cast<int>(state.range(0)), 0.01);
  const bench::PerItemTimer timer;
  for (auto _ : state) {
    auto map = VdtMap<3>::build(occ);
    benchmark::DoNotOptimize(map.field().coefficients().data());
    state.counters["bytes_per_cell"] =
        static_cast<double>(map.memory_bytes()) / static_cast<double>(occ.num_cells());
  }
  timer.set(state, "ns_per_cell", static_cast<double>(occ.num_cells()));
}
BENCHMARK(BM_VdtMapBuild3D)->Arg(256)->Unit(benchmark::kMillisecond);

// The whole 3D map at 1 and 2 threads of the pool (blocks of planes of the exact transform, the
// samples and the prefilter's lines; core/parallel.hpp): ms, ms_1_thread, speedup.
void BM_VdtMapBuild3DThreads(benchmark::State& state) {
  const auto occ = random_occupancy<3>(static_cast<int>(state.range(0)), 0.01);
  bench::thread_scaling(state, static_cast<int>(state.range(1)), [&](std::size_t) {
    auto map = VdtMap<3>::build(occ);
    benchmark::DoNotOptimize(map.field().coefficients().data());
  });
}
BENCHMARK(BM_VdtMapBuild3DThreads)
    ->ArgNames({"side", "pool_threads"})
    ->Args({256, 1})
    ->Args({256, 2})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace vdtnav
