// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/nav_filter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "coxswain/core/angles.hpp"
#include "coxswain/guidance/waypoint_follower.hpp"

namespace coxswain::guidance {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// A boat sailing legs and turns at constant speed, with the sensors the core sees: the IMU at
/// the 50 Hz tick (heading with a magnetometer bias, gyro with a bias, accelerations), GNSS at
/// 5 Hz (a wandering bias plus white noise, hAcc as the simulator reports it).
struct Scenario {
  double speed_mps = 1.5;
  double gnss_sigma_m = 0.4;
  core::NavPoint gnss_bias{4.0, -5.0};
  double mag_bias_deg = 3.0;
  double gyro_bias_dps = 0.5;
  double turn_rate_dps = 15.0;
  double bias_walk_m_per_sqrt_s = 0.08;  // the simulator's wander: 1 m over a 300 s time constant
  std::uint64_t seed = 1;
  // Outputs per tick after the start.
  std::vector<double> nees;
  std::vector<double> error_m;
  std::vector<double> heading_error_deg;
  std::vector<double> bound95_m;  // radius of the 95 % circle of the major axis
};

struct Truth {
  core::NavPoint p;
  double psi_deg = 0.0;
  double rate_dps = 0.0;
};

// Drives a filter through `duration_s`; `hook(t, truth, fix)` may alter the fix (jumps, outages:
// return false to drop it).
template <class Hook>
void sail(NavFilter& f, Scenario& sc, double duration_s, Hook hook) {
  std::mt19937_64 rng(sc.seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  Truth tr;
  const core::TimeNs tick = 20 * core::kNsPerMs;
  bool calibrated = false;
  for (core::TimeNs t = 0; core::ns_to_sec(t) < duration_s; t += tick) {
    const double ts = core::ns_to_sec(t);
    // 10 s waiting on the start point, then legs of 15 s with 6 s turns.
    const bool moving = ts >= 10.0;
    const double phase = std::fmod(ts - 10.0, 21.0);
    tr.rate_dps = moving && phase >= 15.0 ? sc.turn_rate_dps : 0.0;
    const double v = moving ? sc.speed_mps : 0.0;
    tr.psi_deg = core::wrap_deg(tr.psi_deg + tr.rate_dps * 0.02);
    const double psi = tr.psi_deg * kPi / 180.0;
    tr.p.north_m += v * std::cos(psi) * 0.02;
    tr.p.east_m += v * std::sin(psi) * 0.02;
    const double walk = sc.bias_walk_m_per_sqrt_s * std::sqrt(0.02);
    sc.gnss_bias.north_m += walk * n01(rng);
    sc.gnss_bias.east_m += walk * n01(rng);
    const double a_stbd_g = v * tr.rate_dps * kPi / 180.0 / 9.80665;
    f.add_imu(t, core::wrap_deg(tr.psi_deg + sc.mag_bias_deg + 0.5 * n01(rng)), true,
              tr.rate_dps + sc.gyro_bias_dps + 0.2 * n01(rng), 0.01 * n01(rng),
              a_stbd_g + 0.01 * n01(rng), 0.0, 0.0);
    if (t % (200 * core::kNsPerMs) == 0) {
      msg::GnssFix q;
      q.stamp_ns = t;
      q.fix_ok = true;
      q.fix_type = msg::FixType::k3D;
      q.h_acc_m = std::sqrt(2.0) * sc.gnss_sigma_m;
      q.velocity_valid = true;
      q.vel_north_mps = v * std::cos(psi) + 0.05 * n01(rng);
      q.vel_east_mps = v * std::sin(psi) + 0.05 * n01(rng);
      core::NavPoint fix{tr.p.north_m + sc.gnss_bias.north_m + sc.gnss_sigma_m * n01(rng),
                         tr.p.east_m + sc.gnss_bias.east_m + sc.gnss_sigma_m * n01(rng)};
      if (hook(ts, tr, fix)) (void)f.add_fix(t, fix, q);
    }
    if (!calibrated && ts >= 9.0) {
      // 45 fixes on the start point (the truth there is the origin): their mean is the bias.
      const core::NavPoint mean{sc.gnss_bias.north_m + sc.gnss_sigma_m / std::sqrt(45.0) * n01(rng),
                                sc.gnss_bias.east_m + sc.gnss_sigma_m / std::sqrt(45.0) * n01(rng)};
      (void)f.add_bias_measurement(mean, std::sqrt(0.3 * 0.3 + 0.16 / 45.0));
      calibrated = true;
    }
    f.predict_to(t);
    if (!calibrated || !f.has_position()) continue;
    const PositionCovariance c = f.position_covariance();
    const double dn = f.position().north_m - tr.p.north_m;
    const double de = f.position().east_m - tr.p.east_m;
    const double det = c.nn_m2 * c.ee_m2 - c.ne_m2 * c.ne_m2;
    sc.nees.push_back((c.ee_m2 * dn * dn - 2.0 * c.ne_m2 * dn * de + c.nn_m2 * de * de) / det);
    sc.error_m.push_back(std::hypot(dn, de));
    sc.heading_error_deg.push_back(core::wrap_deg(f.heading_deg() - tr.psi_deg));
    sc.bound95_m.push_back(2.4477 * c.sigma_major_m());
  }
}

double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

TEST(NavFilter, PositionErrorStaysInsideItsStatedBoundsOverSeveralSeeds) {
  // Normalised estimation error squared (2 dof): a consistent filter averages 2. One run's
  // errors are time-correlated (the bias wanders slowly), so single runs spread widely and the
  // pooled mean over the seeds is what is bounded.
  double pooled = 0.0;
  std::size_t inside = 0;
  std::size_t ticks = 0;
  const int seeds = 8;
  for (int seed = 1; seed <= seeds; ++seed) {
    NavFilter f;
    Scenario sc;
    sc.seed = static_cast<std::uint64_t>(seed);
    sail(f, sc, 90.0, [](double, const Truth&, core::NavPoint&) { return true; });
    ASSERT_GT(sc.nees.size(), 1000U);
    const double m = mean(sc.nees);
    std::printf("seed %d: mean NEES %.2f, mean error %.2f m, heading error at the end %.1f deg\n",
                seed, m, mean(sc.error_m), sc.heading_error_deg.back());
    pooled += m / seeds;
    EXPECT_LT(m, 8.0) << "seed " << seed << ": the filter is overconfident";
    for (std::size_t i = 0; i < sc.error_m.size(); ++i) inside += sc.error_m[i] <= sc.bound95_m[i];
    ticks += sc.error_m.size();
    EXPECT_LT(mean(sc.error_m), 0.8) << "seed " << seed;
  }
  EXPECT_GT(pooled, 0.7) << "the filter is far too cautious";
  EXPECT_LT(pooled, 4.0) << "the filter is overconfident";
  EXPECT_GE(static_cast<double>(inside) / static_cast<double>(ticks), 0.93);
}

TEST(NavFilter, AFiveMetreGnssJumpIsRefusedAndDoesNotPullTheEstimate) {
  NavFilter f;
  Scenario sc;
  double before = 0.0;
  double worst_after = 0.0;
  sail(f, sc, 40.0, [&](double t, const Truth& tr, core::NavPoint& fix) {
    if (std::abs(t - 30.0) < 1e-6) {
      before = core::distance_m(f.position(), tr.p);
      fix.north_m += 5.0;
    }
    if (t > 30.0 && t < 31.0)
      worst_after = std::max(worst_after, core::distance_m(f.position(), tr.p));
    return true;
  });
  EXPECT_GE(f.counters().fixes_rejected, 1U);
  EXPECT_LT(worst_after, before + 0.5);
}

TEST(NavFilter, AReceiverReportingAPoorSpeedAccuracyHasItsVelocityTrustedLess) {
  const auto velocity_variance = [](double s_acc_mps) {
    NavFilter f;
    msg::GnssFix q;
    q.fix_ok = true;
    q.fix_type = msg::FixType::k3D;
    q.h_acc_m = 1.0;
    q.velocity_valid = true;
    q.vel_north_mps = 1.0;
    q.s_acc_mps = s_acc_mps;
    EXPECT_EQ(f.add_fix(0, {0.0, 0.0}, q), NavUpdate::kUsed);
    return f.covariance()(NavFilter::kVn, NavFilter::kVn);
  };
  const double floor = NavFilterParams{}.gnss_velocity_sigma_mps;
  EXPECT_DOUBLE_EQ(velocity_variance(-1.0), floor * floor);  // unknown: the configured sigma
  EXPECT_DOUBLE_EQ(velocity_variance(0.01), floor * floor);  // never below the floor
  EXPECT_NEAR(velocity_variance(2.0), 2.0, 1e-12);           // (2 / sqrt 2)^2 per axis
}

TEST(NavFilter, AnOutageIsBridgedByDeadReckoningWithAGrowingCovariance) {
  NavFilter f;
  Scenario sc;
  std::vector<double> sigma;
  std::vector<double> error;
  sail(f, sc, 40.0, [&](double t, const Truth& tr, core::NavPoint&) {
    if (t >= 25.0 && t < 29.0) {
      sigma.push_back(f.position_covariance().sigma_major_m());
      error.push_back(core::distance_m(f.position(), tr.p));
      return false;
    }
    return true;
  });
  ASSERT_GT(sigma.size(), 10U);
  for (std::size_t i = 1; i < sigma.size(); ++i) EXPECT_GE(sigma[i], sigma[i - 1]);
  EXPECT_GT(sigma.back(), sigma.front() + 0.1);
  EXPECT_LT(error.back(), 2.4477 * sigma.back());
}

TEST(NavFilter, TheStartCalibrationRemovesAnEightMetreBias) {
  NavFilter f;
  Scenario sc;
  sc.gnss_bias = {-5.0, 6.3};
  sail(f, sc, 30.0, [](double, const Truth&, core::NavPoint&) { return true; });
  EXPECT_NEAR(f.gnss_bias_m().north_m, -5.0, 0.6);
  EXPECT_NEAR(f.gnss_bias_m().east_m, 6.3, 0.6);
  EXPECT_LT(sc.error_m.back(), 1.0);
  EXPECT_LT(f.position_covariance().sigma_major_m(), 0.6);
}

TEST(NavFilter, CourseOverGroundCorrectsAMagnetometerOffsetWhenEnabled) {
  NavFilterParams p;
  p.cog_heading_update = true;
  NavFilter f(p);
  Scenario sc;
  sc.mag_bias_deg = 12.0;
  sail(f, sc, 120.0, [](double, const Truth&, core::NavPoint&) { return true; });
  EXPECT_LT(std::abs(sc.heading_error_deg.back()), 4.0);
  EXPECT_NEAR(f.mag_bias_deg(), 12.0, 4.0);
  EXPECT_FALSE(f.mag_disagrees());
}

TEST(NavFilter, ByDefaultCourseOverGroundLeavesTheHeadingToTheMagnetometer) {
  // A steady current would bias a heading taken from the course for a whole leg.
  NavFilter f;
  Scenario sc;
  sc.mag_bias_deg = 12.0;
  sail(f, sc, 120.0, [](double, const Truth&, core::NavPoint&) { return true; });
  EXPECT_GT(std::abs(sc.heading_error_deg.back()), 8.0);
  EXPECT_EQ(f.counters().cog_used, 0U);
}

TEST(NavFilter, ReportsAMagnetometerThatDisagreesWithCourseOverGround) {
  NavFilter f;
  Scenario sc;
  sc.mag_bias_deg = 30.0;
  sail(f, sc, 120.0, [](double, const Truth&, core::NavPoint&) { return true; });
  EXPECT_TRUE(f.mag_disagrees());
  EXPECT_NEAR(f.mag_cog_mean_deg(), -30.0, 5.0);
}

TEST(NavFilter, TheSameInputsGiveBitIdenticalStates) {
  NavFilter a;
  NavFilter b;
  Scenario sa;
  Scenario sb;
  sail(a, sa, 20.0, [](double, const Truth&, core::NavPoint&) { return true; });
  sail(b, sb, 20.0, [](double, const Truth&, core::NavPoint&) { return true; });
  EXPECT_EQ(std::memcmp(a.state().data(), b.state().data(), sizeof(double) * NavFilter::kStates),
            0);
  EXPECT_EQ(std::memcmp(a.covariance().data(), b.covariance().data(),
                        sizeof(double) * NavFilter::kStates * NavFilter::kStates),
            0);
}

TEST(NavFilter, RefusesAnUnusableFix) {
  NavFilter f;
  msg::GnssFix q;
  q.fix_ok = false;
  EXPECT_EQ(f.add_fix(0, {1.0, 2.0}, q), NavUpdate::kSkipped);
  EXPECT_FALSE(f.has_position());
}

TEST(NavUncertainty, NormalQuantileMatchesTheTables) {
  EXPECT_NEAR(normal_quantile(0.95), 1.644854, 1e-5);
  EXPECT_NEAR(normal_quantile(0.99), 2.326348, 1e-5);
  EXPECT_NEAR(normal_quantile(0.5), 0.0, 1e-9);
  EXPECT_NEAR(normal_quantile(0.01), -2.326348, 1e-5);
}

TEST(NavUncertainty, EllipseAxesFollowTheCovariance) {
  const PositionCovariance c{4.0, 0.0, 1.0};
  double major = 0.0;
  double minor = 0.0;
  double bearing = 0.0;
  c.axes(major, minor, bearing);
  EXPECT_NEAR(major, 2.0, 1e-12);
  EXPECT_NEAR(minor, 1.0, 1e-12);
  EXPECT_NEAR(bearing, 0.0, 1e-9);
  EXPECT_NEAR(c.sigma_along_m(90.0), 1.0, 1e-12);
  const PositionCovariance d{2.5, 1.5, 2.5};  // major axis to the north-east
  d.axes(major, minor, bearing);
  EXPECT_NEAR(bearing, 45.0, 1e-9);
  EXPECT_NEAR(major, 2.0, 1e-12);
}

TEST(NavUncertainty, APointCountsOnlyWhenInsideTheRadiusWithTheStatedConfidence) {
  const PositionCovariance c{0.25, 0.0, 0.25};  // 0.5 m per axis
  const double k = normal_quantile(0.95);
  EXPECT_FALSE(confidently_within({0.0, 0.0}, c, {1.5, 0.0}, 2.0, k));  // 1.5 + 0.82 > 2
  EXPECT_TRUE(confidently_within({0.0, 0.0}, c, {1.1, 0.0}, 2.0, k));
  // Along the line of sight only: an east uncertainty does not matter for a point due north.
  const PositionCovariance thin{0.01, 0.0, 4.0};
  EXPECT_TRUE(confidently_within({0.0, 0.0}, thin, {1.7, 0.0}, 2.0, k));
}

TEST(NavUncertainty, ACrossingIsJudgedOnlyWhenConfidentlyBetweenTheEnds) {
  const core::NavPoint left{0.0, 0.0};
  const core::NavPoint right{0.0, 4.0};
  const PositionCovariance small{0.04, 0.0, 0.04};
  const PositionCovariance big{1.0, 0.0, 1.0};
  EXPECT_TRUE(confident_crossing({0.0, 2.0}, small, left, right, 1.645, 1.0));
  EXPECT_FALSE(confident_crossing({0.0, 0.2}, small, left, right, 1.645, 1.0));
  EXPECT_FALSE(confident_crossing({0.0, 2.0}, big, left, right, 1.645, 1.0));
}

TEST(WaypointFollower, ArrivalByConfidenceWaitsForALargeUncertainty) {
  WaypointFollowerParams p;
  WaypointFollower w(p);
  const core::NavPoint route[] = {{10.0, 0.0}, {20.0, 0.0}};
  ASSERT_TRUE(w.set_route(route));
  const PositionCovariance loose{0.64, 0.0, 0.64};  // 0.8 m: needs distance <= 0.68 m
  EXPECT_EQ(w.update({0.0, 0.0}, 0, &loose).event, WaypointEvent::kNone);
  EXPECT_EQ(w.update({8.8, 0.0}, core::kNsPerMs * 20, &loose).event, WaypointEvent::kNone);
  EXPECT_EQ(w.update({9.4, 0.0}, core::kNsPerMs * 40, &loose).event, WaypointEvent::kArrived);
  const PositionCovariance tight{0.01, 0.0, 0.01};
  EXPECT_EQ(w.update({18.2, 0.0}, core::kNsPerMs * 60, &tight).event, WaypointEvent::kArrived);
}

}  // namespace
}  // namespace coxswain::guidance
