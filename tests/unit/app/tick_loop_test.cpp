// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/tick_loop.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace coxswain::app {
namespace {

// The loop under virtual time: sleeping jumps the clock to the deadline, and a tick's "work"
// advances it by a chosen duration, so deadlines and overruns are checked exactly.
class VirtualTime {
 public:
  core::ManualClock clock{1'000'000'000};
  TickLoop::SleepUntil sleeper() {
    return [this](core::TimeNs deadline_ns) { clock.set_ns(deadline_ns); };
  }
};

TEST(TickLoop, DeadlinesAreAbsolute) {
  VirtualTime vt;
  TickLoop loop(vt.clock, vt.sleeper(), {50.0, core::kNsPerSec});
  EXPECT_EQ(loop.period_ns(), 20 * core::kNsPerMs);
  std::vector<core::TimeNs> deadlines;
  loop.run([&](const TickInfo& t) {
    deadlines.push_back(t.deadline_ns);
    vt.clock.advance_ns(3 * core::kNsPerMs +
                        static_cast<core::TimeNs>(t.index % 3) * core::kNsPerMs);
    return t.index < 9;
  });
  ASSERT_EQ(deadlines.size(), 10U);
  for (std::size_t i = 0; i < deadlines.size(); ++i) {
    // Work of varying length never shifts the grid.
    EXPECT_EQ(deadlines[i], 1'000'000'000 + static_cast<core::TimeNs>(i) * 20 * core::kNsPerMs);
  }
  EXPECT_EQ(loop.total_overruns(), 0U);
  EXPECT_EQ(loop.total_ticks(), 10U);
}

TEST(TickLoop, OverrunIsCountedAndMissedDeadlinesSkipped) {
  VirtualTime vt;
  TickLoop loop(vt.clock, vt.sleeper(), {50.0, 10 * core::kNsPerSec});
  std::vector<core::TimeNs> deadlines;
  std::vector<TickWindowStats> windows;
  loop.run(
      [&](const TickInfo& t) {
        deadlines.push_back(t.deadline_ns);
        // Tick 2 takes 65 ms: it swallows the deadlines at +60 and +80 ms.
        vt.clock.advance_ns(t.index == 2 ? 65 * core::kNsPerMs : core::kNsPerMs);
        return t.index < 4;
      },
      [&](const TickWindowStats& s) { windows.push_back(s); });
  const core::TimeNs t0 = 1'000'000'000;
  ASSERT_EQ(deadlines.size(), 5U);
  EXPECT_EQ(deadlines[2], t0 + 40 * core::kNsPerMs);
  EXPECT_EQ(deadlines[3], t0 + 120 * core::kNsPerMs);  // realigned to the grid, no burst
  EXPECT_EQ(loop.total_overruns(), 1U);
}

TEST(TickLoop, StatsWindowReportsDurations) {
  VirtualTime vt;
  TickLoop loop(vt.clock, vt.sleeper(), {100.0, 500 * core::kNsPerMs});
  std::vector<TickWindowStats> windows;
  loop.run(
      [&](const TickInfo& t) {
        vt.clock.advance_ns(t.index == 10 ? 8 * core::kNsPerMs : 2 * core::kNsPerMs);
        return t.index < 120;
      },
      [&](const TickWindowStats& s) { windows.push_back(s); });
  ASSERT_GE(windows.size(), 2U);
  EXPECT_EQ(windows[0].ticks, 51U);  // ticks 0..50: the tick that ends past 500 ms closes it
  EXPECT_EQ(windows[0].min_ns, 2 * core::kNsPerMs);
  EXPECT_EQ(windows[0].max_ns, 8 * core::kNsPerMs);
  EXPECT_EQ(windows[0].p99_ns, 8 * core::kNsPerMs);
  EXPECT_EQ(windows[0].overruns, 0U);
  EXPECT_EQ(windows[1].max_ns, 2 * core::kNsPerMs);  // the window was reset
}

TEST(TickLoop, StopRequestEndsTheLoop) {
  VirtualTime vt;
  TickLoop loop(vt.clock, vt.sleeper(), {50.0, core::kNsPerSec});
  loop.run([&](const TickInfo& t) {
    if (t.index == 5) loop.request_stop();
    return true;
  });
  EXPECT_EQ(loop.total_ticks(), 6U);
}

TEST(TickLoop, RealClockKeepsRate) {
  const core::SteadyClock clock;
  TickLoop loop(clock, &TickLoop::sleep_until_steady, {200.0, core::kNsPerSec});
  core::TimeNs first = 0;
  core::TimeNs last = 0;
  loop.run([&](const TickInfo& t) {
    if (t.index == 0) first = t.deadline_ns;
    last = t.deadline_ns;
    EXPECT_GE(t.now_ns, t.deadline_ns);  // never early
    return t.index < 20;
  });
  // A loaded machine may overrun and skip deadlines, but they always stay on the grid.
  EXPECT_EQ((last - first) % loop.period_ns(), 0);
  EXPECT_GE(last - first, 20 * loop.period_ns());
}

}  // namespace
}  // namespace coxswain::app
