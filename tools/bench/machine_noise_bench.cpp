// SPDX-License-Identifier: Apache-2.0
// The machine's own tail: a fixed piece of arithmetic (the same instructions every call, no
// memory traffic) of about 10, 20 and 40 us, timed call by call like the other benchmarks. Its
// median is the work; how far its p99 lies above the median is what interrupts, the hypervisor
// and the neighbours add to any call of that length on this machine, whatever the code.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdint>

#include "common/call_samples.hpp"

namespace coxswain::bench {
namespace {

using Clock = std::chrono::steady_clock;

// A dependent chain of multiply-adds: its time is its length, on any core of this kind.
double fixed_work(std::int64_t steps) {
  double x = 1.0;
  for (std::int64_t i = 0; i < steps; ++i) x = x * 1.0000001 + 1e-9;
  return x;
}

// Steps per microsecond, from the fastest of several 2 ms runs.
double steps_per_us() {
  constexpr std::int64_t kSteps = 1'000'000;
  double best_us = 1e18;
  for (int k = 0; k < 5; ++k) {
    const auto t0 = Clock::now();
    benchmark::DoNotOptimize(fixed_work(kSteps));
    const auto t1 = Clock::now();
    best_us = std::min(best_us, std::chrono::duration<double, std::micro>(t1 - t0).count());
  }
  return static_cast<double>(kSteps) / best_us;
}

void BM_FixedWork(benchmark::State& state) {
  static const double rate = steps_per_us();
  const auto steps = static_cast<std::int64_t>(rate * static_cast<double>(state.range(0)));
  CallSamples samples(0);
  for (auto _ : state) {
    const auto t0 = Clock::now();
    benchmark::DoNotOptimize(fixed_work(steps));
    const auto t1 = Clock::now();
    samples.add(0, std::chrono::duration<double, std::micro>(t1 - t0).count());
  }
  samples.report(state);
}
BENCHMARK(BM_FixedWork)->ArgName("us")->Arg(10)->Arg(20)->Arg(40)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace coxswain::bench
