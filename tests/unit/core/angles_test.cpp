// SPDX-License-Identifier: Apache-2.0
#include "coxswain/core/angles.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

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

// The short cuts one turn out give exactly what the fmod route gives, the sign of zero
// included (replays are compared bit for bit).
double wrap_deg_by_fmod(double a) {
  double r = std::fmod(a, 360.0);
  if (r <= -180.0) r += 360.0;
  if (r > 180.0) r -= 360.0;
  return r;
}
double wrap_deg_360_by_fmod(double a) {
  double r = std::fmod(a, 360.0);
  if (r < 0.0) r += 360.0;
  if (r >= 360.0) r -= 360.0;
  return r;
}

TEST(WrapDeg, ShortCutsAgreeBitForBitWithFmod) {
  std::vector<double> values{-720.0, -540.0, -360.0, -180.0, 0.0,    -0.0,    180.0,   360.0,
                             540.0,  720.0,  -1e-18, 1e-18,  359.99, -359.99, 539.999, -539.999};
  for (double base : {-720.0, -540.0, -360.0, -180.0, 0.0, 180.0, 360.0, 540.0, 720.0}) {
    for (int k = -3; k <= 3; ++k) values.push_back(std::nextafter(base, base + k) + k * 1e-13);
  }
  for (int i = 0; i < 20000; ++i) values.push_back(-800.0 + 0.08 * i + 1e-7 * (i % 7));
  for (double a : values) {
    const double w = wrap_deg(a);
    const double f = wrap_deg_by_fmod(a);
    EXPECT_EQ(w, f) << a;
    EXPECT_EQ(std::signbit(w), std::signbit(f)) << a;
    const double w360 = wrap_deg_360(a);
    const double f360 = wrap_deg_360_by_fmod(a);
    EXPECT_EQ(w360, f360) << a;
    EXPECT_EQ(std::signbit(w360), std::signbit(f360)) << a;
  }
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
