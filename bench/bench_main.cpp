// The benchmark programs' main: the pool at one thread (the targets are per core; the thread
// scaling benchmarks set their own counts, bench_counters.hpp), then Google Benchmark's own.
#include <benchmark/benchmark.h>

#include "vdtnav/core/parallel.hpp"

int main(int argc, char** argv) {
  vdtnav::set_threads(1);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
