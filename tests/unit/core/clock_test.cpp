// SPDX-License-Identifier: Apache-2.0
#include "coxswain/core/clock.hpp"

#include <gtest/gtest.h>

namespace coxswain::core {
namespace {

TEST(SteadyClock, NeverGoesBackwards) {
  const SteadyClock clock;
  TimeNs last = clock.now_ns();
  for (int i = 0; i < 1000; ++i) {
    const TimeNs now = clock.now_ns();
    EXPECT_GE(now, last);
    last = now;
  }
}

TEST(ManualClock, AdvancesOnlyForward) {
  ManualClock clock(5 * kNsPerSec);
  EXPECT_EQ(clock.now_ns(), 5 * kNsPerSec);
  clock.advance_ns(20 * kNsPerMs);
  EXPECT_EQ(clock.now_ns(), 5 * kNsPerSec + 20 * kNsPerMs);
  clock.set_ns(kNsPerSec);  // earlier: ignored
  EXPECT_EQ(clock.now_ns(), 5 * kNsPerSec + 20 * kNsPerMs);
  clock.advance_ns(-1);
  EXPECT_EQ(clock.now_ns(), 5 * kNsPerSec + 20 * kNsPerMs);
  clock.set_ns(7 * kNsPerSec);
  EXPECT_EQ(clock.now_ns(), 7 * kNsPerSec);
}

TEST(TimeConversions, RoundTrip) {
  EXPECT_EQ(sec_to_ns(1.5), 1'500'000'000);
  EXPECT_DOUBLE_EQ(ns_to_sec(250 * kNsPerMs), 0.25);
  EXPECT_EQ(ms_to_ns(300), 300'000'000);
}

}  // namespace
}  // namespace coxswain::core
