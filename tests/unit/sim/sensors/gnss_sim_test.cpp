// SPDX-License-Identifier: Apache-2.0
#include "sim/sensors/gnss_sim.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "coxswain/core/angles.hpp"

namespace coxswain::sim::sensors {
namespace {

const core::GeoPoint kOrigin{35.0695, 128.828, 0.0};

TEST(GnssSim, BiasBoundedSlowlyVaryingAndOneWay) {
  GnssSimConfig c;
  c.bias_mean_m = 7.0;
  c.bias_max_m = 9.0;
  c.bias_wander_sigma_m = 1.5;
  c.bias_tau_s = 300.0;
  c.noise_sigma_m = 0.3;
  GnssSim sim(c, kOrigin);
  BoatTruth truth;  // at rest at the origin
  core::NavPoint prev = sim.bias();
  double sum_step2 = 0.0;
  double sum_10s2 = 0.0;
  int n_10s = 0;
  core::NavPoint ten_s_ago = sim.bias();
  double sum_n = 0.0;
  double sum_e = 0.0;
  int n = 0;
  for (core::TimeNs t = 0; t <= core::sec_to_ns(3600.0); t += core::ms_to_ns(200)) {
    ASSERT_TRUE(sim.update(t, truth));
    const core::NavPoint b = sim.bias();
    EXPECT_LE(std::hypot(b.north_m, b.east_m), 9.0 + 1e-9);
    sum_step2 += core::distance_m(b, prev) * core::distance_m(b, prev);
    if (t % core::sec_to_ns(10.0) == 0) {
      sum_10s2 += core::distance_m(b, ten_s_ago) * core::distance_m(b, ten_s_ago);
      ten_s_ago = b;
      ++n_10s;
    }
    prev = b;
    const core::NavPoint measured = sim.frame().to_nav({sim.fix().lat_deg, sim.fix().lon_deg, 0.0});
    // The antenna sits 0.6 m aft of the bow reference.
    sum_n += measured.north_m + 0.6;
    sum_e += measured.east_m;
    ++n;
    ASSERT_TRUE(sim.fix().usable());
  }
  // Slow wander, not noise: a 1.5 m wander with a 5 min correlation time moves ~0.08 m per
  // epoch and ~0.55 m in 10 s (rms), while the white noise moves each fix 0.4 m.
  EXPECT_LT(std::sqrt(sum_step2 / n), 0.12);
  EXPECT_LT(std::sqrt(sum_10s2 / n_10s), 0.8);
  // Every point shifted one way: the mean offset is the configured mean bias.
  const double dir = core::deg_to_rad(c.bias_direction_deg);
  EXPECT_NEAR(sum_n / n, 7.0 * std::cos(dir), 1.5);
  EXPECT_NEAR(sum_e / n, 7.0 * std::sin(dir), 1.5);
}

TEST(GnssSim, FillsTheDecodersFieldsAtItsRate) {
  GnssSimConfig c;
  c.rate_hz = 5.0;
  GnssSim sim(c, kOrigin);
  BoatTruth truth;
  truth.pose.heading_deg = 90.0;
  truth.vel_east_mps = 1.5;
  truth.surge_mps = 1.5;
  int fixes = 0;
  std::uint32_t last_itow = 0;
  for (core::TimeNs t = 0; t < core::sec_to_ns(2.0); t += core::ms_to_ns(10)) {
    if (!sim.update(t, truth)) continue;
    const msg::GnssFix& f = sim.fix();
    if (fixes > 0) {
      EXPECT_EQ(f.itow_ms - last_itow, 200U);
    }
    last_itow = f.itow_ms;
    ++fixes;
    EXPECT_EQ(f.source, msg::GnssSource::kUbxNavPvt);
    EXPECT_EQ(f.fix_type, msg::FixType::k3D);
    EXPECT_TRUE(f.fix_ok);
    EXPECT_EQ(f.rtk, msg::RtkSolution::kNone);
    EXPECT_GE(f.satellites, 4);
    EXPECT_NEAR(f.h_acc_m, std::sqrt(2.0) * c.noise_sigma_m, 1e-9);
    EXPECT_GT(f.v_acc_m, 0.0);
    EXPECT_GT(f.hdop, 0.0);
    EXPECT_TRUE(f.velocity_valid);
    EXPECT_NEAR(f.ground_speed_mps, 1.5, 0.3);
    EXPECT_NEAR(f.course_deg, 90.0, 10.0);
    EXPECT_EQ((f.utc_ns - c.utc_at_zero_ns) % 200000000, 0);
    EXPECT_GT(f.utc_ns, 0);
  }
  EXPECT_EQ(fixes, 10);
}

TEST(GnssSim, RtkFixedNoiseIsCentimetreLevelAfterFloat) {
  GnssSimConfig c;
  c.rtk = RtkMode::kFixed;
  c.rtk_fix_delay_s = 3.0;
  GnssSim sim(c, kOrigin);
  BoatTruth truth;
  truth.pose.position = {12.0, -4.0};
  double sum2 = 0.0;
  int n = 0;
  for (core::TimeNs t = 0; t <= core::sec_to_ns(120.0); t += core::ms_to_ns(200)) {
    ASSERT_TRUE(sim.update(t, truth));
    const msg::GnssFix& f = sim.fix();
    EXPECT_TRUE(f.diff_soln);
    if (t < core::sec_to_ns(3.0)) {
      EXPECT_EQ(f.rtk, msg::RtkSolution::kFloat);
      continue;
    }
    ASSERT_EQ(f.rtk, msg::RtkSolution::kFixed);
    EXPECT_LT(f.h_acc_m, 0.05);
    const core::NavPoint m = sim.frame().to_nav({f.lat_deg, f.lon_deg, 0.0});
    const double dn = m.north_m - (12.0 - 0.6);
    const double de = m.east_m - (-4.0);
    sum2 += dn * dn + de * de;
    ++n;
  }
  const double rms = std::sqrt(sum2 / n);
  EXPECT_GT(rms, 0.005);
  EXPECT_LT(rms, 0.025);  // sqrt(2) * 1 cm
}

TEST(GnssSim, OutagesDropTheFixAndRecover) {
  GnssSimConfig c;
  c.outage_rate_per_min = 6.0;
  c.outage_mean_s = 2.0;
  GnssSim sim(c, kOrigin);
  BoatTruth truth;
  int lost = 0;
  int good = 0;
  int transitions = 0;
  bool was_ok = true;
  for (core::TimeNs t = 0; t <= core::sec_to_ns(600.0); t += core::ms_to_ns(200)) {
    ASSERT_TRUE(sim.update(t, truth));
    const msg::GnssFix& f = sim.fix();
    if (f.fix_ok) {
      ++good;
    } else {
      ++lost;
      EXPECT_EQ(f.fix_type, msg::FixType::kNoFix);
      EXPECT_FALSE(f.usable());
      EXPECT_FALSE(f.velocity_valid);
    }
    if (f.fix_ok != was_ok) ++transitions;
    was_ok = f.fix_ok;
  }
  // About 60 outages of 2 s over 10 minutes: ~20 % of epochs lost.
  EXPECT_GT(transitions, 40);
  EXPECT_GT(lost, good / 10);
  EXPECT_LT(lost, good / 2);
}

TEST(GnssSim, DeterministicForASeed) {
  GnssSimConfig c;
  c.seed = 1234;
  GnssSim a(c, kOrigin);
  GnssSim b(c, kOrigin);
  BoatTruth truth;
  for (core::TimeNs t = 0; t <= core::sec_to_ns(30.0); t += core::ms_to_ns(200)) {
    a.update(t, truth);
    b.update(t, truth);
    ASSERT_EQ(a.fix().lat_deg, b.fix().lat_deg);
    ASSERT_EQ(a.fix().lon_deg, b.fix().lon_deg);
  }
  c.seed = 1235;
  GnssSim d(c, kOrigin);
  d.update(core::sec_to_ns(30.0), truth);
  EXPECT_NE(a.fix().lat_deg, d.fix().lat_deg);
}

}  // namespace
}  // namespace coxswain::sim::sensors
