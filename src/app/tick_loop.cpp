// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/tick_loop.hpp"

#include <time.h>

#include <algorithm>
#include <cerrno>
#include <cmath>

namespace coxswain::app {

TickLoop::TickLoop(const core::Clock& clock, SleepUntil sleep_until, Params params)
    : clock_(clock),
      sleep_until_(std::move(sleep_until)),
      period_ns_(std::max<core::TimeNs>(
          1, static_cast<core::TimeNs>(std::llround(1e9 / std::max(params.rate_hz, 1e-3))))),
      stats_period_ns_(std::max<core::TimeNs>(params.stats_period_ns, period_ns_)) {}

void TickLoop::sleep_until_steady(core::TimeNs deadline_ns) {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(deadline_ns / core::kNsPerSec);
  ts.tv_nsec = static_cast<long>(deadline_ns % core::kNsPerSec);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

void TickLoop::record(core::TimeNs duration_ns, core::TimeNs lateness_ns) {
  if (duration_count_ < kWindow) durations_[duration_count_++] = duration_ns;
  if (window_.ticks == 0 || duration_ns < window_.min_ns) window_.min_ns = duration_ns;
  window_.max_ns = std::max(window_.max_ns, duration_ns);
  window_.max_lateness_ns = std::max(window_.max_lateness_ns, lateness_ns);
  duration_sum_ns_ += duration_ns;
  ++window_.ticks;
}

TickWindowStats TickLoop::take_window() {
  TickWindowStats out = window_;
  if (out.ticks > 0) {
    out.mean_ns = duration_sum_ns_ / static_cast<core::TimeNs>(out.ticks);
    const std::size_t n = duration_count_;
    const std::size_t rank = std::min(n - 1, (n * 99) / 100);
    std::nth_element(durations_.begin(), durations_.begin() + static_cast<std::ptrdiff_t>(rank),
                     durations_.begin() + static_cast<std::ptrdiff_t>(n));
    out.p99_ns = durations_[rank];
  }
  window_ = TickWindowStats{};
  duration_sum_ns_ = 0;
  duration_count_ = 0;
  return out;
}

void TickLoop::run(const TickFn& tick, const StatsFn& on_stats) {
  const core::TimeNs start_ns = clock_.now_ns();
  core::TimeNs deadline_ns = start_ns;
  core::TimeNs next_stats_ns = start_ns + stats_period_ns_;
  std::uint64_t index = 0;
  while (!stop_requested()) {
    sleep_until_(deadline_ns);
    const core::TimeNs begin_ns = clock_.now_ns();
    const bool keep_going = tick(TickInfo{index, deadline_ns, begin_ns});
    const core::TimeNs end_ns = clock_.now_ns();
    record(end_ns - begin_ns, std::max<core::TimeNs>(0, begin_ns - deadline_ns));
    ++index;
    total_ticks_.fetch_add(1, std::memory_order_relaxed);

    deadline_ns += period_ns_;
    if (end_ns > deadline_ns) {
      // Overrun: the next deadline has already passed. Skip every deadline that is fully behind
      // us so the loop realigns to the grid instead of bursting to catch up.
      ++window_.overruns;
      total_overruns_.fetch_add(1, std::memory_order_relaxed);
      const core::TimeNs behind = end_ns - deadline_ns;
      const core::TimeNs skip = behind / period_ns_ + 1;
      window_.skipped_ticks += static_cast<std::uint64_t>(skip);
      deadline_ns += skip * period_ns_;
    }
    if (end_ns >= next_stats_ns) {
      const TickWindowStats stats = take_window();
      if (on_stats) on_stats(stats);
      next_stats_ns += stats_period_ns_ * ((end_ns - next_stats_ns) / stats_period_ns_ + 1);
    }
    if (!keep_going) break;
  }
}

}  // namespace coxswain::app
