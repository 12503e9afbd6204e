// SPDX-License-Identifier: Apache-2.0
#pragma once
// The simulator's one pseudo-random source: SplitMix64 (Steele, Lea, Flood 2014), with our own
// uniform and normal draws, so a seed gives the same numbers on every standard library (the
// std::*_distribution classes are implementation-defined). Plain value type, not thread-safe.
#include <cmath>
#include <cstdint>
#include <numbers>

namespace coxswain::sim {

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}

  /// Next raw 64-bit value.
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
  /// Standard normal by Box-Muller (the second value is dropped to keep the state simple).
  double normal() {
    const double u1 = 1.0 - uniform();  // (0, 1]
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
  }
  /// A new independent stream (for one disturbance or one generator stage).
  Rng split() { return Rng(next_u64()); }

 private:
  std::uint64_t state_;
};

}  // namespace coxswain::sim
