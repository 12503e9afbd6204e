// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/mag_calibration.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "coxswain/core/angles.hpp"

namespace coxswain::guidance {
namespace {

/// A slow turn in place through `turn_deg` of a board whose field is stretched (soft iron) and
/// shifted (hard iron), with sensor noise.
std::vector<std::array<double, 2>> turn(double turn_deg, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.3);
  std::vector<std::array<double, 2>> out;
  for (int i = 0; i < 400; ++i) {
    const double psi = turn_deg * i / 400.0 * core::kPi / 180.0;
    // True field seen by the board: 30 uT toward magnetic north.
    const double x = 30.0 * std::cos(psi);
    const double y = -30.0 * std::sin(psi);
    // Soft iron: 1.3 along x, 0.8 along y, a little cross-coupling; hard iron (12, -7).
    out.push_back({1.3 * x + 0.1 * y + 12.0 + noise(rng), 0.1 * x + 0.8 * y - 7.0 + noise(rng)});
  }
  return out;
}

TEST(MagCalibration, AFullTurnRecoversTheHardIronAndMakesTheHeadingRight) {
  const auto samples = turn(360.0, 1);
  std::string why;
  const auto cal = fit_mag_calibration(samples, why);
  ASSERT_TRUE(cal) << why;
  EXPECT_NEAR(cal->hard_iron_x_ut, 12.0, 0.2);
  EXPECT_NEAR(cal->hard_iron_y_ut, -7.0, 0.2);
  EXPECT_LT(cal->residual_rms_ut, 0.6);
  EXPECT_GT(cal->coverage_deg, 350.0);
  // Uncalibrated, the heading is tens of degrees off; calibrated, within a couple of degrees
  // (the soft-iron map is only known up to a rotation, which the fit keeps near identity).
  double worst = 0.0;
  double worst_raw = 0.0;
  for (int i = 0; i < 400; i += 10) {
    const double truth = core::wrap_deg(360.0 * i / 400.0);
    const auto& s = samples[static_cast<std::size_t>(i)];
    worst = std::max(worst, std::abs(core::wrap_deg(cal->heading_deg(s[0], s[1]) - truth)));
    worst_raw = std::max(
        worst_raw, std::abs(core::wrap_deg(std::atan2(-s[1], s[0]) * 180.0 / core::kPi - truth)));
  }
  EXPECT_GT(worst_raw, 20.0);
  EXPECT_LT(worst, 4.0);
}

TEST(MagCalibration, RefusesAHalfTurn) {
  std::string why;
  EXPECT_FALSE(fit_mag_calibration(turn(180.0, 2), why));
  EXPECT_NE(why.find("covers only"), std::string::npos) << why;
}

TEST(MagCalibration, RefusesTooFewSamples) {
  std::string why;
  const std::vector<std::array<double, 2>> few(10, {1.0, 2.0});
  EXPECT_FALSE(fit_mag_calibration(few, why));
  EXPECT_NE(why.find("too few"), std::string::npos);
}

}  // namespace
}  // namespace coxswain::guidance
