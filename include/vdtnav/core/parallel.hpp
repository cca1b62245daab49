#pragma once
/// \file
/// \brief The one small pool of worker threads for work that is independent: the exact
/// transform's blocks of rows, the sparse map's tiles, the 3D multi-start's starts and attitude
/// grid, the global search's roots, greedy descents and refinements.
///
/// parallel_for(n, f) calls f(i) once for every i in [0, n) on up to threads() threads (the
/// caller is one of them) and returns when every call has returned. The callers write the result
/// of each i to a place of its own and combine them in index order afterwards, so that what they
/// compute is the same for any thread count (each use has a test that says so). A parallel_for
/// reached from inside another one, or while another thread's is running, runs its calls in the
/// caller, one after the other: no nesting, no deadlock. An exception thrown by f is rethrown by
/// parallel_for after every call has returned (the one of the lowest index).
///
/// The count is process-wide, as OpenMP's and TBB's: set_threads(n) (`threads:` in the localizer
/// settings, `--threads` on the command line, vdtnav.set_threads() in Python), by default the
/// environment's VDTNAV_THREADS or else the machine's cores (std::thread::hardware_concurrency()).

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

#include "vdtnav/core/error.hpp"

namespace vdtnav {

/// \brief A fixed set of worker threads that run parallel_for calls (see the file comment).
class ThreadPool {
 public:
  /// \param threads the threads of a parallel_for, the caller included (threads - 1 workers).
  /// \throws ConfigError when threads < 1.
  explicit ThreadPool(int threads) : size_(threads) {
    VDTNAV_CHECK(threads >= 1, "ThreadPool: the thread count must be >= 1");
    workers_.reserve(static_cast<std::size_t>(threads - 1));
    for (int w = 1; w < threads; ++w) workers_.emplace_back([this] { work_loop(); });
  }
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;
  ~ThreadPool() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : workers_) t.join();
  }

  /// \return the threads a parallel_for uses, the caller included.
  [[nodiscard]] int size() const noexcept { return size_; }

  /// \brief f(i) for every i in [0, n), then returns (see the file comment).
  void parallel_for(std::size_t n, const std::function<void(std::size_t)>& f) {
    if (n == 0) return;
    std::unique_lock<std::mutex> busy(busy_, std::try_to_lock);
    if (workers_.empty() || n == 1 || inside() || !busy.owns_lock()) {
      for (std::size_t i = 0; i < n; ++i) f(i);
      return;
    }
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      job_ = &f;
      n_ = n;
      next_.store(0, std::memory_order_relaxed);
      error_ = nullptr;
      error_index_ = n;
      generation_.fetch_add(1, std::memory_order_release);
    }
    wake_.notify_all();
    inside() = true;
    run(f, n);
    inside() = false;
    // Every index is claimed. Only the workers that joined are waited for: one the scheduler has
    // not run yet (the other core busy with another process) never joins, and nothing waits for
    // it to wake. A short spin first (a joined worker's last call is usually under way).
    for (int spin = 0; spin < kSpins && running_.load(std::memory_order_acquire) != 0; ++spin) {
      std::this_thread::yield();
    }
    std::exception_ptr error;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      job_ = nullptr;  // no worker joins from now on
      done_.wait(lock, [this] { return running_.load(std::memory_order_acquire) == 0; });
      error = std::exchange(error_, nullptr);
    }
    if (error) std::rethrow_exception(error);
  }

 private:
  /// Whether this thread is running calls of a parallel_for (a worker, or a caller inside one).
  static bool& inside() {
    thread_local bool flag = false;
    return flag;
  }

  /// Claims indices until none is left; records the exception of the lowest index.
  void run(const std::function<void(std::size_t)>& f, std::size_t n) {
    for (std::size_t i = next_.fetch_add(1); i < n; i = next_.fetch_add(1)) {
      try {
        f(i);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (i < error_index_) {
          error_index_ = i;
          error_ = std::current_exception();
        }
      }
    }
  }

  /// A worker: joins each new job that still has calls to claim and runs them. After one, it
  /// spins a little for the next (a search's batches follow each other within microseconds)
  /// before it waits on the condition variable.
  void work_loop() {
    inside() = true;
    std::uint64_t seen = 0;
    for (;;) {
      for (int spin = 0; spin < kSpins && generation_.load(std::memory_order_acquire) == seen;
           ++spin) {
        std::this_thread::yield();
      }
      const std::function<void(std::size_t)>* job = nullptr;
      std::size_t n = 0;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock,
                   [&] { return stop_ || generation_.load(std::memory_order_acquire) != seen; });
        if (stop_) return;
        seen = generation_.load(std::memory_order_acquire);
        if (job_ == nullptr || next_.load(std::memory_order_relaxed) >= n_) continue;  // done
        job = job_;
        n = n_;
        running_.fetch_add(1, std::memory_order_acq_rel);
      }
      run(*job, n);
      if (running_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
        const std::lock_guard<std::mutex> lock(mutex_);
        done_.notify_one();
      }
    }
  }

  static constexpr int kSpins = 200;  // yields, a few tens of microseconds
  int size_;
  std::vector<std::thread> workers_;
  std::mutex busy_;  // held by the caller of the running parallel_for
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  const std::function<void(std::size_t)>* job_ = nullptr;
  std::size_t n_ = 0;
  std::atomic<std::size_t> next_{0};
  std::atomic<int> running_{0};  // workers that joined the current job and are not done
  std::atomic<std::uint64_t> generation_{0};
  bool stop_ = false;
  std::exception_ptr error_;
  std::size_t error_index_ = 0;
};

namespace detail {
struct PoolSlot {
  std::mutex mutex;
  std::shared_ptr<ThreadPool> pool;  // created at the first use, replaced by set_threads()
};
inline PoolSlot& pool_slot() {
  static PoolSlot slot;
  return slot;
}
}  // namespace detail

/// \return the machine's cores (std::thread::hardware_concurrency(), at least 1).
[[nodiscard]] inline int hardware_threads() {
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

/// \return the default count: the environment variable VDTNAV_THREADS when it holds an integer
/// in [1, 4096] (as OMP_NUM_THREADS: for programs without a --threads flag, the examples, a ROS
/// node), else hardware_threads().
[[nodiscard]] inline int default_threads() {
  if (const char* env = std::getenv("VDTNAV_THREADS")) {
    char* end = nullptr;
    const long n = std::strtol(env, &end, 10);
    if (end != env && *end == '\0' && n >= 1 && n <= 4096) return static_cast<int>(n);
  }
  return hardware_threads();
}

/// \brief Sets the threads of every later parallel_for, the caller included; 0: the default
/// (default_threads(): VDTNAV_THREADS, else the machine's cores). A parallel_for already running
/// keeps its threads.
/// \throws ConfigError when n < 0.
inline void set_threads(int n) {
  VDTNAV_CHECK(n >= 0, "set_threads: the thread count must be >= 0 (0: the machine's cores)");
  auto pool = std::make_shared<ThreadPool>(n == 0 ? default_threads() : n);
  detail::PoolSlot& slot = detail::pool_slot();
  const std::lock_guard<std::mutex> lock(slot.mutex);
  slot.pool.swap(pool);  // the old pool is joined when its last parallel_for returns
}

/// \return the shared pool (created with default_threads() at the first call).
[[nodiscard]] inline std::shared_ptr<ThreadPool> thread_pool() {
  detail::PoolSlot& slot = detail::pool_slot();
  const std::lock_guard<std::mutex> lock(slot.mutex);
  if (!slot.pool) slot.pool = std::make_shared<ThreadPool>(default_threads());
  return slot.pool;
}

/// \return the threads a parallel_for uses now, the caller included.
[[nodiscard]] inline int threads() { return thread_pool()->size(); }

/// \brief f(i) for every i in [0, n) on the shared pool (see the file comment).
template <typename F>
void parallel_for(std::size_t n, F&& f) {
  if (n <= 1) {
    if (n == 1) f(std::size_t{0});
    return;
  }
  const std::function<void(std::size_t)> job = [&f](std::size_t i) { f(i); };
  thread_pool()->parallel_for(n, job);
}

/// \brief f(begin, end) over [0, n) cut into consecutive ranges of `grain` indices (the last one
/// shorter), on the shared pool: for loops whose iterations are too small to be a call each.
template <typename F>
void parallel_for_ranges(std::size_t n, std::size_t grain, F&& f) {
  grain = std::max<std::size_t>(grain, 1);
  parallel_for((n + grain - 1) / grain,
               [&f, n, grain](std::size_t k) { f(k * grain, std::min(n, (k + 1) * grain)); });
}

}  // namespace vdtnav
