#pragma once
// Counters as plain numbers (Google Benchmark's inverted rate counters print an "s" suffix).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstddef>

#include "vdtnav/core/parallel.hpp"

namespace vdtnav::bench {

/// Times the whole benchmark loop; set() divides by iterations x items.
class PerItemTimer {
 public:
  PerItemTimer() : start_(std::chrono::steady_clock::now()) {}
  /// Sets counter `name` = nanoseconds per item (or milliseconds when `scale` = 1e-6).
  void set(benchmark::State& state, const char* name, double items_per_iteration,
           double scale = 1.0) const {
    const double ns =
        std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start_).count();
    const double n = static_cast<double>(state.iterations()) * items_per_iteration;
    state.counters[name] = n > 0 ? scale * ns / n : 0.0;
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

/// \brief Thread scaling in one run (register with ->Apply(pool_threads_1_and_2)):
/// each iteration k calls f(k) with the pool at `threads` threads, wall-timed (the benchmark's
/// time), and, when threads > 1, f(k) again at one thread (the same input: f's results are the
/// same for any thread count); counters ms (at `threads`), ms_1_thread and
/// speedup, the ratio of their sums (interleaved, so that a shared machine's load weighs on both
/// alike). The pool is left at one thread, as bench_main.cpp sets it.
template <typename F>
void thread_scaling(benchmark::State& state, int threads, F&& f) {
  using Clock = std::chrono::steady_clock;
  double many = 0.0, one = 0.0;
  std::size_t k = 0;
  for (auto _ : state) {
    set_threads(threads);
    const auto t0 = Clock::now();
    f(k);
    const double s = std::chrono::duration<double>(Clock::now() - t0).count();
    state.SetIterationTime(s);
    many += s;
    if (threads > 1) {
      set_threads(1);
      const auto t1 = Clock::now();
      f(k);
      one += std::chrono::duration<double>(Clock::now() - t1).count();
    }
    ++k;
  }
  set_threads(1);
  if (threads == 1) one = many;
  const double n = std::max<double>(1.0, static_cast<double>(state.iterations()));
  state.counters["ms"] = 1e3 * many / n;
  state.counters["ms_1_thread"] = 1e3 * one / n;
  state.counters["speedup"] = many > 0.0 ? one / many : 0.0;
}

/// The runs of a thread_scaling() benchmark: /pool_threads:1 and /pool_threads:2, manual time.
inline void pool_threads_1_and_2(benchmark::internal::Benchmark* b) {
  b->ArgName("pool_threads")->Arg(1)->Arg(2)->UseManualTime();
}

}  // namespace vdtnav::bench
