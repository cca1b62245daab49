#!/usr/bin/env bash
# The test suite: a Release build with -Wall -Wextra -Wpedantic -Werror and all tests, the tests
# again under AddressSanitizer + UndefinedBehaviorSanitizer, and the benchmarks in smoke mode.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs="$(nproc)"

echo "== [1/3] Release build (-Werror) and tests"
scripts/setup.sh release
ctest --test-dir build/release --output-on-failure -j "$jobs"

echo "== [2/3] ASan + UBSan build and tests"
scripts/setup.sh asan
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build/asan --output-on-failure -j "$jobs"

echo "== [3/3] Benchmarks, smoke mode (one short run each; numbers are not meaningful here)"
for b in build/release/bench/bench_*; do
  [ -x "$b" ] || continue
  "$b" --benchmark_min_time=0.01 --benchmark_format=console
done
echo "== all tests passed"
