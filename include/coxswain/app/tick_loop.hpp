// SPDX-License-Identifier: Apache-2.0
#pragma once
// The fixed-rate tick: absolute deadlines on the steady clock (start + k * period), so jitter in
// one tick never shifts the next; a tick that ends after the next deadline is an overrun, and whole
// periods it swallowed are skipped rather than run back to back.
#include <array>
#include <atomic>
#include <cstdint>
#include <functional>

#include "coxswain/core/clock.hpp"

namespace coxswain::app {

/// Tick-duration statistics over one reporting window.
struct TickWindowStats {
  std::uint64_t ticks = 0;
  std::uint64_t overruns = 0;       // ticks that ended after the next deadline (this window)
  std::uint64_t skipped_ticks = 0;  // deadlines dropped to catch up (this window)
  core::TimeNs min_ns = 0;
  core::TimeNs mean_ns = 0;
  core::TimeNs p99_ns = 0;
  core::TimeNs max_ns = 0;
  core::TimeNs max_lateness_ns = 0;  // how late a tick started after its deadline
};

struct TickInfo {
  std::uint64_t index = 0;       // counts ticks run since start
  core::TimeNs deadline_ns = 0;  // when this tick was due
  core::TimeNs now_ns = 0;       // when it actually started
};

/// Runs `tick` at a fixed rate until it returns false or `request_stop()` is called.
/// Thread-safety: `run` on one thread; `request_stop` and `totals` from any thread.
class TickLoop {
 public:
  /// Blocks until the clock reaches `deadline_ns` (absolute, on the same clock).
  using SleepUntil = std::function<void(core::TimeNs deadline_ns)>;
  using TickFn = std::function<bool(const TickInfo&)>;
  using StatsFn = std::function<void(const TickWindowStats&)>;

  struct Params {
    double rate_hz = 50.0;
    core::TimeNs stats_period_ns = 10 * core::kNsPerSec;
  };

  TickLoop(const core::Clock& clock, SleepUntil sleep_until, Params params);

  /// Runs the loop on the calling thread. `on_stats` (optional) is called once per stats period.
  void run(const TickFn& tick, const StatsFn& on_stats = {});
  void request_stop() { stop_.store(true, std::memory_order_release); }
  [[nodiscard]] bool stop_requested() const { return stop_.load(std::memory_order_acquire); }

  [[nodiscard]] core::TimeNs period_ns() const { return period_ns_; }
  [[nodiscard]] std::uint64_t total_ticks() const { return total_ticks_.load(); }
  [[nodiscard]] std::uint64_t total_overruns() const { return total_overruns_.load(); }

  /// Sleeps on CLOCK_MONOTONIC (the steady clock) until an absolute deadline.
  static void sleep_until_steady(core::TimeNs deadline_ns);

 private:
  static constexpr std::size_t kWindow = 4096;  // durations kept for the percentile

  void record(core::TimeNs duration_ns, core::TimeNs lateness_ns);
  TickWindowStats take_window();

  const core::Clock& clock_;
  SleepUntil sleep_until_;
  core::TimeNs period_ns_;
  core::TimeNs stats_period_ns_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> total_ticks_{0};
  std::atomic<std::uint64_t> total_overruns_{0};

  std::array<core::TimeNs, kWindow> durations_{};
  std::size_t duration_count_ = 0;
  TickWindowStats window_;
  core::TimeNs duration_sum_ns_ = 0;
};

}  // namespace coxswain::app
