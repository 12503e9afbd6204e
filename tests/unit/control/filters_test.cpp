// SPDX-License-Identifier: Apache-2.0
#include "coxswain/control/filters.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <deque>

#include "coxswain/core/angles.hpp"

namespace coxswain::control {
namespace {

constexpr core::TimeNs kTick = core::ms_to_ns(100);

// The documents' filter applied to headings: an arithmetic mean of the last n values.
double naive_moving_average(std::deque<double>& window, double x, std::size_t n) {
  window.push_back(x);
  if (window.size() > n) window.pop_front();
  double s = 0.0;
  for (double v : window) s += v;
  return s / static_cast<double>(window.size());
}

TEST(AngleMovingAverage, HeadingAcrossSouthStaysSouthWhereNaiveAverageSaysNorth) {
  std::deque<double> naive_window;
  AngleMovingAverage ours(4);
  double naive = 0.0;
  double mean = 0.0;
  for (double h : {179.0, -179.0, 179.0, -179.0}) {
    naive = naive_moving_average(naive_window, h, 4);
    mean = ours.update(h);
  }
  EXPECT_NEAR(naive, 0.0, 1e-9);  // the defect: due south averaged to due north
  EXPECT_NEAR(std::abs(mean), 180.0, 1e-9);
  EXPECT_GT(ours.concentration(), 0.99);
}

TEST(AngleMovingAverage, WindowDropsOldSamples) {
  AngleMovingAverage f(3);
  for (int i = 0; i < 3; ++i) f.update(10.0);
  for (int i = 0; i < 3; ++i) f.update(40.0);
  EXPECT_NEAR(f.update(40.0), 40.0, 1e-9);
  AngleMovingAverage g(2);
  g.update(350.0);
  EXPECT_NEAR(g.update(20.0), 5.0, 1e-9);  // 350 and 20 straddle north
}

TEST(AngleMovingAverage, IgnoresNonFinite) {
  AngleMovingAverage f(3);
  f.update(90.0);
  EXPECT_NEAR(f.update(std::nan("")), 90.0, 1e-9);
}

TEST(AngleLowPass, ConvergesAcrossTheWrapTheShortWay) {
  AngleLowPass f(AngleLowPassParams{0.5});
  f.update(170.0, 0);
  double prev = 170.0;
  core::TimeNs t = 0;
  for (int i = 0; i < 50; ++i) {
    t += kTick;
    const double y = f.update(-170.0, t);
    // Every output lies on the short arc 170 -> 180 -> -170, never through 0.
    EXPECT_GE(std::abs(y), 169.999) << i;
    EXPECT_GE(core::angle_diff_deg(y, prev), -1e-9);  // moves clockwise only
    prev = y;
  }
  EXPECT_NEAR(core::angle_diff_deg(prev, -170.0), 0.0, 0.01);
}

TEST(LowPass, FirstOrderStepResponse) {
  LowPass f(LowPassParams{1.0});
  EXPECT_DOUBLE_EQ(f.update(0.0, 0), 0.0);
  double y = 0.0;
  for (int i = 1; i <= 10; ++i) y = f.update(1.0, i * kTick);
  // Discrete a = 0.1/1.1 per step: 1 - (1/1.1)^10.
  EXPECT_NEAR(y, 1.0 - std::pow(1.0 / 1.1, 10), 1e-12);
}

TEST(LowPass, RepeatedStampDoesNotMove) {
  LowPass f(LowPassParams{0.5});
  f.update(0.0, 100);
  EXPECT_DOUBLE_EQ(f.update(5.0, 100), 0.0);
}

TEST(MovingAverage, PlainMeanOfWindow) {
  MovingAverage m(3);
  EXPECT_DOUBLE_EQ(m.update(3.0), 3.0);
  EXPECT_DOUBLE_EQ(m.update(6.0), 4.5);
  EXPECT_DOUBLE_EQ(m.update(9.0), 6.0);
  EXPECT_DOUBLE_EQ(m.update(12.0), 9.0);
  EXPECT_EQ(m.size(), 3U);
  MovingAverage big(1000);  // clamped to capacity
  for (int i = 0; i < 200; ++i) big.update(1.0);
  EXPECT_EQ(big.size(), kMaxWindow);
}

TEST(RateLimiter, SeparateRiseAndFall) {
  RateLimiter r(RateLimiterParams{1.0, 2.0});
  EXPECT_FALSE(r.validate().has_value());
  r.reset(0.0);
  r.update(10.0, 0);  // first stamp: no time elapsed, no movement
  EXPECT_DOUBLE_EQ(r.value(), 0.0);
  EXPECT_NEAR(r.update(10.0, core::sec_to_ns(0.5)), 0.5, 1e-12);
  EXPECT_NEAR(r.update(-10.0, core::sec_to_ns(1.0)), -0.5, 1e-12);
  EXPECT_TRUE(RateLimiter(RateLimiterParams{0.0, 1.0}).validate().has_value());
}

}  // namespace
}  // namespace coxswain::control
