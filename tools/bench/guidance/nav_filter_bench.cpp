// SPDX-License-Identifier: Apache-2.0
// One navigation-filter step as the tick runs it (target <= 5 us): an IMU sample (prediction over
// one 20 ms tick and the magnetometer update), and every tenth tick a GNSS fix (position,
// velocity and course-over-ground updates); plus the fix step alone.
#include <benchmark/benchmark.h>

#include <cmath>

#include "coxswain/guidance/nav_filter.hpp"

namespace {

using coxswain::core::kNsPerMs;
using coxswain::core::TimeNs;
using coxswain::guidance::NavFilter;

coxswain::msg::GnssFix fix_quality() {
  coxswain::msg::GnssFix q;
  q.fix_ok = true;
  q.fix_type = coxswain::msg::FixType::k3D;
  q.h_acc_m = 0.56;
  q.velocity_valid = true;
  q.vel_north_mps = 1.5;
  q.vel_east_mps = 0.1;
  return q;
}

void BM_NavFilterTick(benchmark::State& state) {
  NavFilter f;
  const coxswain::msg::GnssFix q = fix_quality();
  TimeNs t = 0;
  f.add_imu(t, 3.0, true, 0.5, 0.0, 0.0, 0.0, 0.0);
  (void)f.add_fix(t, {0.0, 0.0}, q);
  (void)f.add_bias_measurement({0.0, 0.0}, 0.3);
  int k = 0;
  for (auto _ : state) {
    t += 20 * kNsPerMs;
    const double ts = static_cast<double>(t) * 1e-9;
    f.add_imu(t, 3.0 + std::sin(ts), true, 0.5, 0.01, 0.02, 1.0, 0.5);
    if (++k % 10 == 0) {
      benchmark::DoNotOptimize(f.add_fix(t, {1.5 * ts, 0.1 * ts}, q));
    }
    f.predict_to(t);
    benchmark::DoNotOptimize(f.position());
  }
}
BENCHMARK(BM_NavFilterTick);

void BM_NavFilterFix(benchmark::State& state) {
  NavFilter f;
  const coxswain::msg::GnssFix q = fix_quality();
  TimeNs t = 0;
  f.add_imu(t, 3.0, true, 0.5, 0.0, 0.0, 0.0, 0.0);
  (void)f.add_fix(t, {0.0, 0.0}, q);
  for (auto _ : state) {
    t += 200 * kNsPerMs;
    const double ts = static_cast<double>(t) * 1e-9;
    benchmark::DoNotOptimize(f.add_fix(t, {1.5 * ts, 0.1 * ts}, q));
  }
}
BENCHMARK(BM_NavFilterFix);

}  // namespace
