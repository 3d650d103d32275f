#include "framework/util/parallel.h"

#include "framework/util/cpus.h"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <thread>

namespace arcs {

void ParallelFor(std::int64_t n, const std::function<void(std::int64_t, std::int64_t)>& body,
                 std::int64_t grain) {
  if (n <= 0) return;
  if (grain < 1) grain = 1;
  if (n <= grain || MaxThreads() <= 1) {
    body(0, n);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::int64_t>(0, n, grain),
                    [&](const tbb::blocked_range<std::int64_t>& r) { body(r.begin(), r.end()); });
}

void ParallelInvoke(const std::function<void()>& a, const std::function<void()>& b) {
  if (MaxThreads() <= 1) {
    a();
    b();
    return;
  }
  tbb::parallel_invoke(a, b);
}

int MaxThreads() {
  return static_cast<int>(
      tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
}

struct ThreadLimit::Impl {
  explicit Impl(int t) : control(tbb::global_control::max_allowed_parallelism, t) {}
  tbb::global_control control;
};

ThreadLimit::ThreadLimit(int threads) {
  if (threads <= 0) threads = AvailableCpus().cpus;  // the CPU allocation (affinity, Slurm), not the machine
  impl_ = std::make_unique<Impl>(threads);
}

ThreadLimit::~ThreadLimit() = default;

}  // namespace arcs
