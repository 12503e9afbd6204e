// SPDX-License-Identifier: Apache-2.0
#pragma once
// The simulator's one pseudo-random generator: SplitMix64 (Steele, Lea, Flood 2014) for the bits,
// our own uniform, normal and exponential draws on top, so a seed gives the same numbers with
// every standard library and compiler (the std::*_distribution classes are
// implementation-defined). Every random choice in the simulator (course generator, disturbances,
// sensors, emulators) draws from one of these, seeded from the run's seed by `derive_seed` or
// `split`. Plain value type, not thread-safe: one generator per user.
#include <cmath>
#include <cstdint>

namespace coxswain::sim {

class Rng {
 public:
  explicit Rng(std::uint64_t seed = 0) : state_(seed) {}

  /// Next 64 random bits.
  std::uint64_t next_u64() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30U)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27U)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31U);
  }
  /// Uniform in [0, 1) with 53 random bits.
  double uniform() { return static_cast<double>(next_u64() >> 11U) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n); n > 0. (Modulo bias < 2^-40 for the small n used here.)
  std::uint64_t below(std::uint64_t n) { return next_u64() % n; }
  /// True with probability p.
  bool chance(double p) { return p > 0.0 && uniform() < p; }
  /// Standard normal (Marsaglia's polar form of Box-Muller: no sin/cos; the second value of each
  /// pair is kept for the next call).
  double normal() {
    if (have_spare_) {
      have_spare_ = false;
      return spare_;
    }
    double u = 0.0;
    double v = 0.0;
    double s = 0.0;
    do {
      u = 2.0 * uniform() - 1.0;
      v = 2.0 * uniform() - 1.0;
      s = u * u + v * v;
    } while (s >= 1.0 || s == 0.0);
    const double f = std::sqrt(-2.0 * std::log(s) / s);
    spare_ = v * f;
    have_spare_ = true;
    return u * f;
  }
  double normal(double sigma) { return sigma * normal(); }
  /// Exponential with the given mean (waiting times of Poisson events).
  double exponential(double mean) {
    double u = uniform();
    while (u <= 0.0) u = uniform();
    return -mean * std::log(u);
  }
  /// A new independent stream (for one disturbance or one generator stage).
  Rng split() { return Rng(next_u64()); }

 private:
  std::uint64_t state_;
  double spare_ = 0.0;
  bool have_spare_ = false;
};

/// A seed for sub-generator `stream` derived from a master seed (so users do not share draws).
[[nodiscard]] inline std::uint64_t derive_seed(std::uint64_t seed, std::uint64_t stream) {
  Rng r(seed ^ (0xD1B54A32D192ED03ULL * (stream + 1)));
  return r.next_u64();
}

}  // namespace coxswain::sim
