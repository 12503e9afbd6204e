// SPDX-License-Identifier: Apache-2.0
#include "coxswain/core/angles.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace coxswain::core {
namespace {

TEST(WrapDeg, RangeIsHalfOpenAtMinus180) {
  EXPECT_DOUBLE_EQ(wrap_deg(180.0), 180.0);
  EXPECT_DOUBLE_EQ(wrap_deg(-180.0), 180.0);
  EXPECT_DOUBLE_EQ(wrap_deg(540.0), 180.0);
  EXPECT_DOUBLE_EQ(wrap_deg(-540.0), 180.0);
  EXPECT_DOUBLE_EQ(wrap_deg(190.0), -170.0);
  EXPECT_DOUBLE_EQ(wrap_deg(-190.0), 170.0);
  EXPECT_DOUBLE_EQ(wrap_deg(0.0), 0.0);
  EXPECT_DOUBLE_EQ(wrap_deg(359.5), -0.5);
  EXPECT_DOUBLE_EQ(wrap_deg(720.25), 0.25);
}

TEST(WrapDeg, EveryOutputInRange) {
  for (double a = -2000.0; a <= 2000.0; a += 0.37) {
    const double w = wrap_deg(a);
    EXPECT_GT(w, -180.0) << a;
    EXPECT_LE(w, 180.0) << a;
    EXPECT_NEAR(std::remainder(w - a, 360.0), 0.0, 1e-9) << a;
  }
}

TEST(WrapDeg, NonFinitePassesThrough) {
  EXPECT_TRUE(std::isnan(wrap_deg(std::numeric_limits<double>::quiet_NaN())));
}

TEST(WrapRad, RangeIsHalfOpenAtMinusPi) {
  EXPECT_DOUBLE_EQ(wrap_rad(kPi), kPi);
  EXPECT_DOUBLE_EQ(wrap_rad(-kPi), kPi);
  EXPECT_NEAR(wrap_rad(3.0 * kPi / 2.0), -kPi / 2.0, 1e-12);
}

TEST(WrapDeg360, RangeIsZeroTo360) {
  EXPECT_DOUBLE_EQ(wrap_deg_360(-90.0), 270.0);
  EXPECT_DOUBLE_EQ(wrap_deg_360(360.0), 0.0);
  EXPECT_LT(wrap_deg_360(-1e-18), 360.0);
}

TEST(AngleDiff, ShortestSignedTurn) {
  EXPECT_DOUBLE_EQ(angle_diff_deg(-170.0, 170.0), 20.0);  // turn 20 to starboard across south
  EXPECT_DOUBLE_EQ(angle_diff_deg(170.0, -170.0), -20.0);
  EXPECT_DOUBLE_EQ(angle_diff_deg(10.0, 350.0), 20.0);
}

// The documents' moving average of headings averaged 179 and -179 to 0 (pointing the wrong way).
TEST(CircularMean, AveragesAcrossTheSeam) {
  CircularMean m;
  m.add(179.0);
  m.add(-179.0);
  EXPECT_NEAR(std::abs(m.mean_deg()), 180.0, 1e-9);
  EXPECT_NEAR(m.concentration(), std::cos(deg_to_rad(1.0)), 1e-12);
}

TEST(CircularMean, WeightedAndEmpty) {
  CircularMean m;
  EXPECT_TRUE(m.empty());
  EXPECT_DOUBLE_EQ(m.mean_deg(), 0.0);
  m.add(10.0, 3.0);
  m.add(40.0, 0.0);  // zero weight ignored
  m.add(-20.0, 1.0);
  EXPECT_NEAR(m.mean_deg(), 2.6307, 0.001);  // atan2(3 sin 10 - sin 20, 3 cos 10 + cos 20)
}

}  // namespace
}  // namespace coxswain::core
