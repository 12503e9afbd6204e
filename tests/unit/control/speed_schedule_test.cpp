// SPDX-License-Identifier: Apache-2.0
#include "coxswain/control/speed_schedule.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace coxswain::control {
namespace {

constexpr core::TimeNs kScheduleTick = core::ms_to_ns(100);

TEST(SpeedSchedule, LinearBetweenSlowAndFast) {
  const SpeedSchedule s;  // 0.3 at 2 m, 1.0 at 12 m
  EXPECT_DOUBLE_EQ(s.scheduled(0.5), 0.3);
  EXPECT_DOUBLE_EQ(s.scheduled(2.0), 0.3);
  EXPECT_NEAR(s.scheduled(7.0), 0.65, 1e-12);
  EXPECT_DOUBLE_EQ(s.scheduled(100.0), 1.0);
}

// The KABOAT 2022 report, 5.1.2: just before a waypoint the thrust is near minimum; after the
// switch the next waypoint is 40 m away. A bare schedule jumps to full thrust at once (the lurch);
// ours ramps.
TEST(SpeedSchedule, NoLurchAfterWaypointSwitch) {
  SpeedScheduleParams p;
  p.rise_per_s = 0.2;
  SpeedSchedule s(p);
  s.reset(0.3);
  core::TimeNs t = 0;
  for (int i = 0; i < 20; ++i) s.update(1.5, t += kScheduleTick);  // arriving
  const double before = s.update(1.5, t += kScheduleTick);
  EXPECT_NEAR(before, 0.3, 1e-12);

  const double naive_after = s.scheduled(40.0);  // what the unlimited schedule commands
  EXPECT_NEAR(naive_after - before, 0.7, 1e-12);

  double prev = before;
  int steps = 0;
  double y = before;
  while (y < 1.0 - 1e-12 && steps < 1000) {
    y = s.update(40.0, t += kScheduleTick);
    EXPECT_LE(y - prev, p.rise_per_s * 0.1 + 1e-12) << "step " << steps;
    prev = y;
    ++steps;
  }
  EXPECT_EQ(steps, 35);  // 0.7 at 0.02 per tick
}

TEST(SpeedSchedule, SlowsDownAtTheFallRate) {
  SpeedScheduleParams p;
  p.fall_per_s = 0.5;
  SpeedSchedule s(p);
  s.reset(1.0);
  s.update(50.0, 0);
  EXPECT_NEAR(s.update(0.0, kScheduleTick), 0.95, 1e-12);
}

TEST(SpeedSchedule, Validate) {
  SpeedScheduleParams p;
  EXPECT_FALSE(p.validate().has_value());
  p.fast_distance_m = p.slow_distance_m;
  EXPECT_TRUE(p.validate().has_value());
  p = {};
  p.min_thrust_frac = 0.9;
  p.max_thrust_frac = 0.5;
  EXPECT_TRUE(p.validate().has_value());
}

}  // namespace
}  // namespace coxswain::control
