// Parallel loops over index ranges (TBB underneath).
//
// Determinism rule: a loop body writes only to per-index outputs (or to
// per-block outputs combined afterwards in block order), so results do not
// depend on the number of threads. The number of threads is set per run with
// ThreadLimit (a scoped tbb::global_control).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>

namespace arcs {

// Calls body(begin, end) on disjoint sub-ranges covering [0, n). `grain` is
// the minimal sub-range length.
void ParallelFor(std::int64_t n, const std::function<void(std::int64_t, std::int64_t)>& body,
                 std::int64_t grain = 1024);

// Runs a() and b(), side by side when more than one thread is allowed (either
// may itself call ParallelFor: a thread that finishes its own job helps with
// the other's loops), and returns when both have. They must not write what
// the other reads.
void ParallelInvoke(const std::function<void()>& a, const std::function<void()>& b);

// Number of worker threads currently allowed.
int MaxThreads();

// While alive, limits TBB to `threads` workers (0 = hardware concurrency).
class ThreadLimit {
 public:
  explicit ThreadLimit(int threads);
  ~ThreadLimit();
  ThreadLimit(const ThreadLimit&) = delete;
  ThreadLimit& operator=(const ThreadLimit&) = delete;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace arcs
