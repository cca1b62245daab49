#pragma once
// The pool's thread count for the length of a scope (core/parallel.hpp), then the default again:
// the tests that compare thread counts leave the process as they found it.
#include "vdtnav/core/parallel.hpp"

namespace vdtnav::test {

class ThreadCount {
 public:
  explicit ThreadCount(int n) { set_threads(n); }
  ThreadCount(const ThreadCount&) = delete;
  ThreadCount& operator=(const ThreadCount&) = delete;
  ~ThreadCount() { set_threads(0); }
};

}  // namespace vdtnav::test
