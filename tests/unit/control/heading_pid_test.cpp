// SPDX-License-Identifier: Apache-2.0
#include "coxswain/control/heading_pid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "coxswain/core/angles.hpp"

namespace coxswain::control {
namespace {

constexpr double kDt = 0.05;
const core::TimeNs kTickNs = core::sec_to_ns(kDt);

// Yaw plant: first-order yaw rate toward K u (deg/s), so a saturated command limits the turn rate.
struct YawPlant {
  double heading_deg = 0.0;
  double rate_dps = 0.0;
  double gain_dps = 25.0;
  double tau_s = 0.8;
  double bias_dps = 0.0;  // steady yaw disturbance (asymmetric hull or thrust)
  void step(double u) {
    rate_dps += kDt * (gain_dps * u + bias_dps - rate_dps) / tau_s;
    heading_deg = core::wrap_deg(heading_deg + kDt * rate_dps);
  }
};

// The PID as commonly written: no integral limit, no back-calculation, derivative on error.
struct NaivePid {
  HeadingPidParams p;
  double integral = 0.0;
  double last_e = 0.0;
  bool first = true;
  double update(double desired, double heading) {
    const double e = core::angle_diff_deg(desired, heading);
    integral += p.ki_per_deg_s * e * kDt;
    const double d = first ? 0.0 : p.kd_per_dps * (e - last_e) / kDt;
    first = false;
    last_e = e;
    return std::clamp(p.kp_per_deg * e + integral + d, -p.output_limit, p.output_limit);
  }
};

HeadingPidParams windup_params() {
  HeadingPidParams p;
  p.kp_per_deg = 1.0 / 30.0;
  p.ki_per_deg_s = 0.01;
  p.kd_per_dps = 0.02;
  p.integral_limit = 0.3;
  return p;
}

// Overshoot (deg past the target) after a 150 deg step; the actuator saturates for seconds.
template <typename Step>
double overshoot_after_big_turn(Step&& controller_step) {
  YawPlant plant;
  const double desired = 150.0;
  double max_past = 0.0;
  for (int i = 0; i < 600; ++i) {
    const double u = controller_step(desired, plant, i);
    plant.step(u);
    max_past = std::max(max_past, core::angle_diff_deg(plant.heading_deg, desired));
  }
  return max_past;
}

TEST(HeadingPid, AntiWindupRecoversWhereNaiveOvershoots) {
  NaivePid naive{windup_params()};
  const double naive_overshoot = overshoot_after_big_turn(
      [&](double d, const YawPlant& pl, int) { return naive.update(d, pl.heading_deg); });

  HeadingPid pid(windup_params());
  const double our_overshoot = overshoot_after_big_turn([&](double d, const YawPlant& pl, int i) {
    return pid.update({d, pl.heading_deg, i * kTickNs, pl.rate_dps});
  });
  HeadingPidParams pd_params = windup_params();
  pd_params.ki_per_deg_s = 0.0;
  HeadingPid pd(pd_params);
  const double pd_overshoot = overshoot_after_big_turn([&](double d, const YawPlant& pl, int i) {
    return pd.update({d, pl.heading_deg, i * kTickNs, pl.rate_dps});
  });
  EXPECT_GT(naive_overshoot, 20.0);              // the stored-up integral carries the boat far past
  EXPECT_LT(our_overshoot, pd_overshoot + 2.0);  // about what P and D alone give
  EXPECT_LT(std::abs(pid.terms().i), windup_params().integral_limit + 1e-12);
}

// Saturated for a long time with a small error (a steady disturbance the actuator cannot beat):
// back-calculation keeps the integral near zero, so the command reverses as soon as the error does.
TEST(HeadingPid, BackCalculationLetsTheCommandReverseAtOnce) {
  HeadingPidParams p = windup_params();
  p.output_limit = 0.2;
  p.kd_per_dps = 0.0;
  HeadingPid pid(p);
  NaivePid naive{p};
  int i = 0;
  for (; i < 600; ++i) {  // 30 s at psi_e = +8 deg, output pinned at the limit
    EXPECT_DOUBLE_EQ(pid.update({8.0, 0.0, i * kTickNs, 0.0}), 0.2);
    (void)naive.update(8.0, 0.0);
  }
  EXPECT_LT(std::abs(pid.terms().i), 0.05);
  EXPECT_GT(naive.integral, 2.0);
  // The boat overshoots to psi_e = -3 deg: ours steers back, the naive one keeps turning.
  EXPECT_LT(pid.update({-3.0, 0.0, i * kTickNs, 0.0}), 0.0);
  EXPECT_GT(naive.update(-3.0, 0.0), 0.0);
}

// A hull that pulls to port (the field "left bias"): P alone leaves a steady error, the integral
// removes it.
TEST(HeadingPid, IntegralRemovesASteadyPortPull) {
  HeadingPidParams pd_params = windup_params();
  pd_params.ki_per_deg_s = 0.0;
  for (const bool with_integral : {false, true}) {
    HeadingPid pid(with_integral ? windup_params() : pd_params);
    YawPlant plant;
    plant.bias_dps = -3.0;
    plant.heading_deg = -40.0;
    for (int i = 0; i < 2400; ++i) {
      plant.step(pid.update({20.0, plant.heading_deg, i * kTickNs, {}}));
    }
    if (with_integral) {
      EXPECT_NEAR(plant.heading_deg, 20.0, 0.2);
    } else {
      EXPECT_LT(plant.heading_deg, 18.0);  // 3 dps / (25 dps / 30 deg) = 3.6 deg short
    }
  }
}

TEST(HeadingPid, NoDerivativeKickOnSetpointStep) {
  HeadingPidParams p;
  p.ki_per_deg_s = 0.0;
  p.kd_per_dps = 0.05;
  HeadingPid pid(p);
  pid.update({10.0, 10.0, 0, 0.0});
  // psi_d jumps by 20 deg (waypoint switch) while the boat is not turning: only P acts.
  const double u = pid.update({30.0, 10.0, kTickNs, 0.0});
  EXPECT_NEAR(u, p.kp_per_deg * 20.0, 1e-12);
  EXPECT_DOUBLE_EQ(pid.terms().d, 0.0);
}

TEST(HeadingPid, DerivativeUsesGyroWhenGivenElseHeadingDifference) {
  HeadingPidParams p;
  p.kp_per_deg = 0.0;
  p.ki_per_deg_s = 0.0;
  p.kd_per_dps = 0.01;
  p.derivative_tau_s = 0.0;
  HeadingPid gyro(p);
  gyro.update({0.0, 0.0, 0, 10.0});
  EXPECT_NEAR(gyro.update({0.0, 0.0, kTickNs, 10.0}), -0.1, 1e-12);  // turning right: brake

  HeadingPid diff(p);
  diff.update({0.0, 179.0, 0, {}});
  // 179 -> -179 is +2 deg in 0.05 s = +40 deg/s, not -7160.
  EXPECT_NEAR(diff.update({0.0, -179.0, kTickNs, {}}), -0.4, 1e-9);
}

TEST(HeadingPid, OutputLimitAndDtFromStamps) {
  HeadingPidParams p;
  p.output_limit = 0.6;
  p.kd_per_dps = 0.0;
  HeadingPid pid(p);
  EXPECT_DOUBLE_EQ(pid.update({90.0, 0.0, 0, {}}), 0.6);
  EXPECT_TRUE(pid.terms().saturated);
  HeadingPid a(p);
  HeadingPid b(p);
  a.update({5.0, 0.0, 0, {}});
  b.update({5.0, 0.0, 0, {}});
  a.update({5.0, 0.0, core::sec_to_ns(0.1), {}});
  b.update({5.0, 0.0, core::sec_to_ns(0.3), {}});
  EXPECT_NEAR(b.terms().i, 3.0 * a.terms().i, 1e-12);
  HeadingPid gap(p);
  gap.update({5.0, 0.0, 0, {}});
  gap.update({5.0, 0.0, core::sec_to_ns(5.0), {}});  // dropout longer than max_dt_s
  EXPECT_DOUBLE_EQ(gap.terms().i, 0.0);
}

// No left bias: mirrored situations give exactly mirrored commands.
TEST(HeadingPid, MirrorSymmetric) {
  for (double e = -175.0; e <= 175.0; e += 5.0) {
    HeadingPid right;
    HeadingPid left;
    double ur = 0.0;
    double ul = 0.0;
    for (int i = 0; i < 5; ++i) {
      ur = right.update({e, 0.0, i * kTickNs, 1.0});
      ul = left.update({-e, 0.0, i * kTickNs, -1.0});
    }
    EXPECT_DOUBLE_EQ(ur, -ul) << e;
  }
}

// Desired heading dead astern with compass noise: the shortest-turn sign flips every sample.
TEST(HeadingPid, NoSideToSideFlippingNearOneEighty) {
  HeadingPid pid;
  int naive_flips = 0;
  int our_flips = 0;
  double last_naive = 0.0;
  double last_ours = 0.0;
  for (int i = 0; i < 40; ++i) {
    const double heading = (i % 2 == 0) ? 1.0 : -1.5;  // desired 180 (well, -180 + noise)
    const double naive = core::angle_diff_deg(180.0, heading) > 0.0 ? 1.0 : -1.0;
    const double ours = pid.update({180.0, heading, i * kTickNs, 0.0});
    if (i > 0 && naive != last_naive) ++naive_flips;
    if (i > 0 && std::signbit(ours) != std::signbit(last_ours)) ++our_flips;
    last_naive = naive;
    last_ours = ours;
  }
  EXPECT_GT(naive_flips, 30);
  EXPECT_EQ(our_flips, 0);
  // Away from 180 the shortest turn is used again.
  EXPECT_LT(pid.update({-90.0, 0.0, 41 * kTickNs, 0.0}), 0.0);
  EXPECT_GT(pid.update({90.0, 0.0, 42 * kTickNs, 0.0}), 0.0);
}

TEST(HeadingPid, Validate) {
  HeadingPidParams p;
  EXPECT_FALSE(p.validate().has_value());
  p.output_limit = 1.5;
  EXPECT_TRUE(p.validate().has_value());
  p = {};
  p.kp_per_deg = -1.0;
  EXPECT_TRUE(p.validate().has_value());
}

}  // namespace
}  // namespace coxswain::control
