// Deterministic, platform-independent random numbers.
//
// std::uniform_real_distribution and friends differ between standard
// libraries, so arcs draws its own: SplitMix64 for seeding and counter-based
// streams (a value per index, independent of thread count), xoshiro256** for
// sequential streams.
#pragma once

#include <cmath>
#include <cstdint>
#include <string_view>

namespace arcs {

inline std::uint64_t SplitMix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// Mixes a seed with a stream index: deterministic per (seed, index).
inline std::uint64_t HashSeed(std::uint64_t seed, std::uint64_t index) {
  return SplitMix64(SplitMix64(seed) ^ (index * 0xD1B54A32D192ED03ull));
}

// 64-bit FNV-1a of a string (stable across platforms; used for case ids and
// named RNG streams).
inline std::uint64_t Fnv1a64(std::string_view s) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : s) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

// xoshiro256** generator with portable uniform / normal draws.
class Rng {
 public:
  explicit Rng(std::uint64_t seed = 1) { Seed(seed); }
  void Seed(std::uint64_t seed) {
    std::uint64_t x = seed;
    for (auto& s : s_) {
      x = SplitMix64(x);
      s = x;
    }
    has_spare_ = false;
  }
  std::uint64_t NextU64() {
    const std::uint64_t result = Rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = Rotl(s_[3], 45);
    return result;
  }
  // Uniform in [0, 1).
  double Uniform() { return static_cast<double>(NextU64() >> 11) * 0x1.0p-53; }
  double Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform(); }
  // Uniform integer in [0, n).
  std::uint64_t UniformInt(std::uint64_t n) {
    // Lemire's nearly-divisionless method is overkill here; modulo bias is
    // negligible for n << 2^64 but we reject to be exact.
    const std::uint64_t limit = UINT64_MAX - UINT64_MAX % n;
    std::uint64_t x;
    do {
      x = NextU64();
    } while (x >= limit);
    return x % n;
  }
  // Standard normal (Marsaglia polar method).
  double Normal() {
    if (has_spare_) {
      has_spare_ = false;
      return spare_;
    }
    double u, v, s;
    do {
      u = 2.0 * Uniform() - 1.0;
      v = 2.0 * Uniform() - 1.0;
      s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    const double m = std::sqrt(-2.0 * std::log(s) / s);
    spare_ = v * m;
    has_spare_ = true;
    return u * m;
  }

 private:
  static std::uint64_t Rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::uint64_t s_[4];
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace arcs
