#pragma once
// Counters as plain numbers (Google Benchmark's inverted rate counters print an "s" suffix).

#include <benchmark/benchmark.h>

#include <chrono>

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

}  // namespace vdtnav::bench
