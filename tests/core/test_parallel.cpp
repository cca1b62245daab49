// The thread pool (core/parallel.hpp): every index once, on more than one thread, nesting and
// concurrent callers served in the caller, the lowest index's exception, the thread count.
#include "vdtnav/core/parallel.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "../thread_count.hpp"

namespace vdtnav {
namespace {

TEST(Parallel, EveryIndexRunsOnceForAnyThreadCount) {
  for (const int t : {1, 2, 3, 5}) {
    const test::ThreadCount count(t);
    ASSERT_EQ(threads(), t);
    for (const std::size_t n : {0u, 1u, 2u, 7u, 1000u}) {
      std::vector<std::atomic<int>> runs(n);
      parallel_for(n, [&](std::size_t i) { runs[i].fetch_add(1); });
      for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(runs[i].load(), 1) << t << " " << n << " " << i;
    }
    // Ranges: consecutive, at most `grain` long, covering [0, n) once.
    std::vector<std::atomic<int>> cover(1001);
    parallel_for_ranges(cover.size(), 64, [&](std::size_t b, std::size_t e) {
      EXPECT_LT(b, e);
      EXPECT_LE(e - b, 64u);
      EXPECT_TRUE(b % 64 == 0);
      for (std::size_t i = b; i < e; ++i) cover[i].fetch_add(1);
    });
    for (const auto& c : cover) ASSERT_EQ(c.load(), 1);
  }
}

TEST(Parallel, TwoThreadsRunTwoCallsAtOnce) {
  // Calls 0 and 1 each wait until both have started: only two threads running at once finish
  // (one thread would wait out the deadline on the first).
  const test::ThreadCount count(2);
  std::atomic<int> started{0};
  std::atomic<bool> met{true};
  std::set<std::thread::id> ids;
  std::mutex m;
  parallel_for(2, [&](std::size_t) {
    started.fetch_add(1);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (started.load() < 2) {
      if (std::chrono::steady_clock::now() > deadline) {
        met = false;
        break;
      }
      std::this_thread::yield();
    }
    const std::lock_guard<std::mutex> lock(m);
    ids.insert(std::this_thread::get_id());
  });
  EXPECT_TRUE(met.load());
  EXPECT_EQ(ids.size(), 2u);
}

TEST(Parallel, NestedAndConcurrentCallsRunInTheirCaller) {
  const test::ThreadCount count(3);
  std::vector<std::atomic<int>> runs(8 * 50);
  std::atomic<bool> same_thread{true};
  parallel_for(8, [&](std::size_t i) {
    const std::thread::id outer = std::this_thread::get_id();
    parallel_for(50, [&](std::size_t j) {
      if (std::this_thread::get_id() != outer) same_thread = false;
      runs[i * 50 + j].fetch_add(1);
    });
  });
  EXPECT_TRUE(same_thread.load());
  for (const auto& r : runs) ASSERT_EQ(r.load(), 1);
  // Two threads of the user's calling at once: both complete, every index once.
  std::vector<std::atomic<int>> a(5000), b(5000);
  std::thread other([&] { parallel_for(a.size(), [&](std::size_t i) { a[i].fetch_add(1); }); });
  parallel_for(b.size(), [&](std::size_t i) { b[i].fetch_add(1); });
  other.join();
  for (std::size_t i = 0; i < a.size(); ++i) ASSERT_TRUE(a[i].load() == 1 && b[i].load() == 1);
}

TEST(Parallel, RethrowsTheLowestIndexsExceptionAfterEveryCall) {
  for (const int t : {1, 2, 4}) {
    const test::ThreadCount count(t);
    std::vector<std::atomic<int>> runs(100);
    try {
      parallel_for(runs.size(), [&](std::size_t i) {
        runs[i].fetch_add(1);
        if (i == 37 || i == 61 || i == 90) throw std::runtime_error(std::to_string(i));
      });
      ADD_FAILURE() << "no exception with " << t << " threads";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "37") << t << " threads";
    }
    // With threads, every call ran before the rethrow; in one thread the loop stops at the throw.
    for (std::size_t i = 0; i < (t > 1 ? runs.size() : 38u); ++i) EXPECT_EQ(runs[i].load(), 1);
    // The pool is usable afterwards.
    std::atomic<int> sum{0};
    parallel_for(10, [&](std::size_t i) { sum += static_cast<int>(i); });
    EXPECT_EQ(sum.load(), 45);
  }
}

TEST(Parallel, TheDefaultIsTheEnvironmentsOrTheMachinesCoresAndNegativesAreRefused) {
  const char* before = std::getenv("VDTNAV_THREADS");
  const std::string saved = before != nullptr ? before : "";
  ::unsetenv("VDTNAV_THREADS");
  {
    const test::ThreadCount count(0);
    EXPECT_EQ(threads(), hardware_threads());
    EXPECT_GE(threads(), 1);
  }
  ::setenv("VDTNAV_THREADS", "3", 1);
  {
    const test::ThreadCount count(0);
    EXPECT_EQ(threads(), 3);
  }
  for (const char* bad : {"0", "-2", "two", "3x", ""}) {  // not a count: the machine's cores
    ::setenv("VDTNAV_THREADS", bad, 1);
    EXPECT_EQ(default_threads(), hardware_threads()) << "'" << bad << "'";
  }
  if (before != nullptr) {
    ::setenv("VDTNAV_THREADS", saved.c_str(), 1);
  } else {
    ::unsetenv("VDTNAV_THREADS");
  }
  set_threads(0);
  EXPECT_THROW(set_threads(-1), ConfigError);
  EXPECT_THROW(ThreadPool(0), ConfigError);
  EXPECT_EQ(threads(), default_threads());  // a refused count changes nothing
}

}  // namespace
}  // namespace vdtnav
