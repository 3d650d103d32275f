// The run context handed to every algorithm and stage: seeded randomness,
// logging, progress and cancellation. Algorithms never print directly.
#pragma once

#include "framework/error.h"
#include "framework/util/rng.h"

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

namespace arcs {

enum class LogLevel { kDebug, kInfo, kWarning, kError };

class Context {
 public:
  using LogFn = std::function<void(LogLevel, const std::string&)>;
  using ProgressFn = std::function<void(double fraction, const std::string& what)>;

  Context() = default;
  explicit Context(std::uint64_t seed) : seed_(seed) {}

  std::uint64_t seed() const { return seed_; }
  void set_seed(std::uint64_t s) { seed_ = s; }

  // A generator for a named stream: the same (seed, name) always gives the
  // same sequence, so stages do not perturb each other's randomness.
  Rng MakeRng(std::string_view stream) const { return Rng(HashSeed(seed_, Fnv1a64(stream))); }
  // A seed for counter-based (per-index) draws on a named stream.
  std::uint64_t StreamSeed(std::string_view stream) const {
    return HashSeed(seed_, Fnv1a64(stream));
  }

  void set_log(LogFn fn) { log_ = std::move(fn); }
  void set_progress(ProgressFn fn) { progress_ = std::move(fn); }
  void set_stop_flag(const std::atomic<bool>* flag) { stop_ = flag; }

  void Log(LogLevel level, const std::string& msg) const {
    if (log_) log_(level, msg);
  }
  void Info(const std::string& msg) const { Log(LogLevel::kInfo, msg); }
  void Warn(const std::string& msg) const { Log(LogLevel::kWarning, msg); }
  void Progress(double fraction, const std::string& what) const {
    if (progress_) progress_(fraction, what);
  }
  bool StopRequested() const { return stop_ && stop_->load(std::memory_order_relaxed); }
  // Throws Cancelled if a stop was requested; call between units of work.
  void CheckStop() const {
    if (StopRequested()) throw Cancelled();
  }

 private:
  std::uint64_t seed_ = 1;
  LogFn log_;
  ProgressFn progress_;
  const std::atomic<bool>* stop_ = nullptr;
};

}  // namespace arcs
