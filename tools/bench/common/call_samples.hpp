// SPDX-License-Identifier: Apache-2.0
#pragma once
// Per-call timings for the benchmarks that report a median and a p99, and a p99 robust to the
// machine: on a shared virtual machine an interrupt or a neighbour lands in about one window
// of 20 us in a hundred and adds some 40 us to it (tools/bench/machine_noise_bench.cpp
// measures this), so the p99 of any call longer than that is the machine's, whatever the call
// costs. Each call is also filed under its input (a recorded scan, a step of a replayed
// sequence); an input's cost is the least of its timings, since the machine's delays are not
// the same in every pass, but an expensive input is expensive in all of them. The p99 over the
// inputs of that least time is the "input p99".
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace coxswain::bench {

class CallSamples {
 public:
  /// `inputs`: how many distinct inputs the calls cycle through (0: no input p99).
  explicit CallSamples(std::size_t inputs)
      : best_us_(inputs, std::numeric_limits<double>::infinity()), seen_(inputs, 0) {
    samples_us_.reserve(std::size_t{1} << 20U);
  }

  void add(std::size_t input, double us) {
    if (samples_us_.size() < samples_us_.capacity()) samples_us_.push_back(us);
    if (input < best_us_.size()) {
      best_us_[input] = std::min(best_us_[input], us);
      ++seen_[input];
    }
  }

  /// p50_us, p99_us and max_us of every call; input_p50_us and input_p99_us when every input was
  /// timed at least `min_passes` times (the fewest is input_passes).
  /// The counters' names start with `prefix`.
  void report(benchmark::State& state, const std::string& prefix = "",
              std::size_t min_passes = 3) const {
    if (!samples_us_.empty()) {
      std::vector<double> all = samples_us_;
      std::sort(all.begin(), all.end());
      state.counters[prefix + "p50_us"] = quantile(all, 0.50);
      state.counters[prefix + "p99_us"] = quantile(all, 0.99);
      state.counters[prefix + "max_us"] = all.back();
    }
    if (best_us_.empty()) return;
    const std::size_t passes = *std::min_element(seen_.begin(), seen_.end());
    state.counters[prefix + "input_passes"] = static_cast<double>(passes);
    if (passes < min_passes) return;
    std::vector<double> best = best_us_;
    std::sort(best.begin(), best.end());
    state.counters[prefix + "input_p50_us"] = quantile(best, 0.50);
    state.counters[prefix + "input_p99_us"] = quantile(best, 0.99);
  }

 private:
  static double quantile(const std::vector<double>& sorted, double q) {
    return sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))];
  }

  std::vector<double> samples_us_;
  std::vector<double> best_us_;
  std::vector<std::size_t> seen_;
};

}  // namespace coxswain::bench
