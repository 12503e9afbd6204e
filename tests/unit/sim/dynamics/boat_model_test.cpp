// SPDX-License-Identifier: Apache-2.0
// The boat model against hand-computed cases.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>

#include "sim/dynamics/boat_model.hpp"

namespace coxswain::sim::dynamics {
namespace {

config::BoatConfig servo_boat() { return config::BoatConfig{}; }  // the defaults = boat.yaml

config::BoatConfig twin_boat() {
  config::BoatConfig b;
  b.actuators.layout = msg::ActuatorLayout::kTwinThrusters;
  return b;
}

void run(BoatModel& m, double seconds) {
  const int n = static_cast<int>(std::lround(seconds / m.dt_s()));
  for (int i = 0; i < n; ++i) m.step();
}

TEST(Params, OtterScaledToTheShippedHullMatchesTheDocumentedDefaults) {
  const DynamicsParams p = otter_scaled(1.2);
  const DynamicsParams d;
  EXPECT_NEAR(p.scale, 0.6, 1e-12);
  EXPECT_NEAR(p.m11_kg, d.m11_kg, 0.01);
  EXPECT_NEAR(p.m22_kg, d.m22_kg, 0.01);
  EXPECT_NEAR(p.m66_kgm2, d.m66_kgm2, 0.001);
  EXPECT_NEAR(p.d_u, d.d_u, 0.001);
  EXPECT_NEAR(p.d_uu, d.d_uu, 0.001);
  EXPECT_NEAR(p.d_v, d.d_v, 0.01);
  EXPECT_NEAR(p.d_vv, d.d_vv, 0.01);
  EXPECT_NEAR(p.d_r, d.d_r, 0.001);
  EXPECT_NEAR(p.d_rr, d.d_rr, 0.01);
  EXPECT_NEAR(p.thrust_fwd_max_n, d.thrust_fwd_max_n, 0.01);
  EXPECT_NEAR(p.thrust_rev_max_n, d.thrust_rev_max_n, 0.01);
  // Full-scale check: at lambda = 1 the Otter's own numbers come back.
  const DynamicsParams otter = otter_scaled(2.0);
  EXPECT_DOUBLE_EQ(otter.m11_kg, 85.5);
  EXPECT_NEAR(otter.d_r, 41.4, 1e-9);
  // Top speed at full thrust is the Otter's 3.09 m/s: drag(3.09) = bollard thrust.
  EXPECT_NEAR(otter.d_u * 3.09 + otter.d_uu * 3.09 * 3.09, otter.thrust_fwd_max_n, 1e-9);
}

TEST(Thrust, PulseToThrustHasDeadbandSquareLawAndAsymmetricReverse) {
  const config::ThrusterConfig esc;  // 1100..1900, deadband 1450..1550
  EXPECT_EQ(thrust_from_pulse(esc, 1500, 50.0, 30.0), 0.0);
  EXPECT_EQ(thrust_from_pulse(esc, 1550, 50.0, 30.0), 0.0);
  EXPECT_EQ(thrust_from_pulse(esc, 1450, 50.0, 30.0), 0.0);
  // Half way from forward_start (1550) to max (1900): a quarter of the thrust.
  EXPECT_DOUBLE_EQ(thrust_from_pulse(esc, 1725, 50.0, 30.0), 12.5);
  EXPECT_DOUBLE_EQ(thrust_from_pulse(esc, 1900, 50.0, 30.0), 50.0);
  EXPECT_DOUBLE_EQ(thrust_from_pulse(esc, 2000, 50.0, 30.0), 50.0);
  EXPECT_DOUBLE_EQ(thrust_from_pulse(esc, 1275, 50.0, 30.0), -7.5);
  config::ThrusterConfig no_reverse = esc;
  no_reverse.reverse_allowed = false;
  EXPECT_EQ(thrust_from_pulse(no_reverse, 1100, 50.0, 30.0), 0.0);
}

TEST(Servo, SlewsAtItsRateAndIgnoresChangesInsideTheDeadband) {
  config::ServoConfig cfg;  // 180 deg/s, 25 deg at 1900, deadband 4 us
  ServoModel servo(cfg);
  servo.command(1900);
  for (int i = 0; i < 5; ++i) servo.step(0.01);
  EXPECT_NEAR(servo.angle_deg(), 9.0, 1e-9);  // 180 deg/s x 0.05 s
  for (int i = 0; i < 20; ++i) servo.step(0.01);
  EXPECT_NEAR(servo.angle_deg(), 25.0, 1e-9);
  servo.command(1897);  // 3 us: inside the deadband, the servo stays
  servo.step(0.1);
  EXPECT_NEAR(servo.angle_deg(), 25.0, 1e-9);
  servo.command(1300);  // half of the port range
  servo.step(1.0);
  EXPECT_NEAR(servo.angle_deg(), -12.5, 1e-9);
  cfg.reversed = true;
  EXPECT_DOUBLE_EQ(servo_target_deg(cfg, 1900), -25.0);
}

TEST(BoatModel, StraightLineTerminalSpeedIsTheRootOfThrustEqualsDrag) {
  const config::BoatConfig boat = servo_boat();
  const DynamicsParams p = otter_scaled(boat.hull.length_m);
  BoatModel m(boat, p, {}, 1);
  m.reset({{0.0, 0.0}, 30.0});
  m.set_pulses({1500, 1725});
  run(m, 60.0);
  const double thrust = 0.25 * p.thrust_fwd_max_n;
  // thrust = d_u u + d_uu u^2  ->  u = (-d_u + sqrt(d_u^2 + 4 d_uu thrust)) / (2 d_uu)
  const double u = (-p.d_u + std::sqrt(p.d_u * p.d_u + 4.0 * p.d_uu * thrust)) / (2.0 * p.d_uu);
  const TruthState t = m.truth();
  EXPECT_NEAR(t.u_mps, u, 1e-6);
  EXPECT_NEAR(t.v_mps, 0.0, 1e-9);
  EXPECT_NEAR(t.pose.heading_deg, 30.0, 1e-9);
  // Moving along the heading: north/east velocity in the ratio of cos/sin 30 deg.
  EXPECT_NEAR(t.vel_east_mps / t.vel_north_mps, std::tan(30.0 * M_PI / 180.0), 1e-9);
  EXPECT_NEAR(t.thrust_n[1], thrust, 1e-6);
  EXPECT_NEAR(t.accel_forward_mps2, 0.0, 1e-6);
}

TEST(BoatModel, FullThrustReachesTheScaledOtterTopSpeed) {
  const config::BoatConfig boat = servo_boat();
  BoatModel m(boat, otter_scaled(boat.hull.length_m), {}, 1);
  m.set_pulses({1500, 1900});
  run(m, 60.0);
  EXPECT_NEAR(m.truth().u_mps, 3.09 * std::sqrt(0.6), 1e-6);
}

TEST(BoatModel, ThrustFollowsAFirstOrderLag) {
  const config::BoatConfig boat = servo_boat();
  const DynamicsParams p = otter_scaled(boat.hull.length_m);
  BoatModel m(boat, p, {}, 1);
  m.set_pulses({1500, 1900});
  run(m, p.thrust_time_constant_s);
  // Discrete lag: 1 - exp(-T/tau) after the steps covering one time constant.
  const int n = static_cast<int>(std::lround(p.thrust_time_constant_s / m.dt_s()));
  const double expected =
      p.thrust_fwd_max_n * (1.0 - std::exp(-n * m.dt_s() / p.thrust_time_constant_s));
  EXPECT_NEAR(m.truth().thrust_n[1], expected, 1e-9);
  EXPECT_NEAR(expected / p.thrust_fwd_max_n, 0.632, 0.01);
}

TEST(BoatModel, ServoToStarboardTurnsTheBowToStarboardAtTheExpectedRate) {
  const config::BoatConfig boat = servo_boat();
  const DynamicsParams p = otter_scaled(boat.hull.length_m);
  BoatModel m(boat, p, {}, 1);
  m.set_pulses({1900, 1725});
  run(m, 30.0);
  const TruthState t = m.truth();
  // Hand estimate ignoring the sway coupling: the yaw moment (L/2) T sin(25 deg) balanced by
  // yaw damping d_r r + d_rr r^2. The coupled boat turns in the same direction, the same order.
  const double thrust = 0.25 * p.thrust_fwd_max_n;
  const double moment = 0.5 * boat.hull.length_m * thrust * std::sin(25.0 * M_PI / 180.0);
  const double r_est =
      (-p.d_r + std::sqrt(p.d_r * p.d_r + 4.0 * p.d_rr * moment)) / (2.0 * p.d_rr) * 180.0 / M_PI;
  EXPECT_GT(t.yaw_rate_dps, 0.5 * r_est);
  EXPECT_LT(t.yaw_rate_dps, 2.0 * r_est);
  // Steady: the rate no longer changes.
  const double r1 = t.yaw_rate_dps;
  run(m, 1.0);
  EXPECT_NEAR(m.truth().yaw_rate_dps, r1, 1e-3);
  // The stern is pushed to port: the hull skids outward... the CG slides to port in the turn.
  EXPECT_LT(t.v_mps, 0.0);
  // Mirror command, mirror turn.
  BoatModel mirror(boat, p, {}, 1);
  mirror.set_pulses({1100, 1725});
  run(mirror, 31.0);
  EXPECT_NEAR(mirror.truth().yaw_rate_dps, -m.truth().yaw_rate_dps, 1e-9);
}

TEST(BoatModel, TwinThrustersTurnTowardTheWeakerSide) {
  const config::BoatConfig boat = twin_boat();
  BoatModel m(boat, otter_scaled(boat.hull.length_m), {}, 1);
  m.set_pulses({1800, 1650});  // port stronger: bow to starboard
  run(m, 20.0);
  EXPECT_GT(m.truth().yaw_rate_dps, 1.0);
  BoatModel straight(boat, otter_scaled(boat.hull.length_m), {}, 1);
  straight.set_pulses({1725, 1725});
  run(straight, 60.0);
  // Two thrusters of half the thrust each: the same terminal speed as one at the same pulse.
  const DynamicsParams p = otter_scaled(boat.hull.length_m);
  const double thrust = 0.25 * p.thrust_fwd_max_n;
  const double u = (-p.d_u + std::sqrt(p.d_u * p.d_u + 4.0 * p.d_uu * thrust)) / (2.0 * p.d_uu);
  EXPECT_NEAR(straight.truth().u_mps, u, 1e-6);
  EXPECT_NEAR(straight.truth().yaw_rate_dps, 0.0, 1e-12);
}

TEST(BoatModel, DriftUnderCurrentEqualsTheCurrent) {
  const config::BoatConfig boat = servo_boat();
  Environment env;
  env.current_speed_mps = 0.4;
  env.current_toward_deg = 90.0;  // flowing east
  BoatModel m(boat, otter_scaled(boat.hull.length_m), env, 1);
  m.reset({{0.0, 0.0}, 0.0});
  EXPECT_NEAR(m.truth().vel_east_mps, 0.0, 1e-12);  // starts at rest over ground
  run(m, 60.0);
  const TruthState t = m.truth();
  EXPECT_NEAR(t.vel_north_mps, 0.0, 1e-6);
  EXPECT_NEAR(t.vel_east_mps, 0.4, 1e-6);
  // After the transient the boat moves exactly with the water: 10 s more = 4 m east.
  const double e0 = t.pose.position.east_m;
  run(m, 10.0);
  EXPECT_NEAR(m.truth().pose.position.east_m - e0, 4.0, 1e-5);
}

TEST(BoatModel, WindPushesTheBoatDownwind) {
  const config::BoatConfig boat = servo_boat();
  Environment env;
  env.wind_speed_mps = 8.0;
  env.wind_from_deg = 0.0;  // from the north: blows south
  BoatModel m(boat, otter_scaled(boat.hull.length_m), env, 1);
  m.reset({{0.0, 0.0}, 90.0});  // beam on to the wind
  run(m, 20.0);
  EXPECT_LT(m.truth().pose.position.north_m, -1.0);
}

TEST(BoatModel, SameSeedSameStatesBitForBitWithGustsAndWaves) {
  const config::BoatConfig boat = servo_boat();
  Environment env;
  env.wind_speed_mps = 3.0;
  env.gust_std_mps = 1.0;
  env.wave_force_n = 3.0;
  auto final_state = [&](std::uint64_t seed) {
    BoatModel m(boat, otter_scaled(boat.hull.length_m), env, seed);
    m.set_pulses({1600, 1700});
    run(m, 20.0);
    return m.state();
  };
  const BoatState a = final_state(5);
  const BoatState b = final_state(5);
  const BoatState c = final_state(6);
  EXPECT_EQ(a.north_m, b.north_m);
  EXPECT_EQ(a.east_m, b.east_m);
  EXPECT_EQ(a.psi_rad, b.psi_rad);
  EXPECT_EQ(a.r_radps, b.r_radps);
  EXPECT_NE(a.north_m, c.north_m);
}

TEST(BoatModel, PoseIsTheBowReferenceAheadOfTheCentreOfGravity) {
  const config::BoatConfig boat = servo_boat();  // 1.2 m, bow overhang 0.1 m
  BoatModel m(boat, otter_scaled(boat.hull.length_m), {}, 1);
  m.reset({{10.0, 5.0}, 90.0});
  const TruthState t = m.truth();
  EXPECT_NEAR(t.pose.position.north_m, 10.0, 1e-12);
  EXPECT_NEAR(t.pose.position.east_m, 5.0, 1e-12);
  EXPECT_NEAR(t.cg.east_m, 5.0 - 0.5, 1e-12);  // mid-hull is 0.5 m behind the origin
}

// A point on the hull moves at the velocity velocity_at gives it: in a steady turn the bow, the
// centre of gravity and a point 0.6 m aft each move by their own velocity between two steps
// (central difference), which differ by the yaw rate's swing.
TEST(BoatModel, VelocityAtAHullPointIsTheDerivativeOfItsPosition) {
  const config::BoatConfig boat = servo_boat();
  BoatModel m(boat, otter_scaled(boat.hull.length_m), {}, 1);
  m.reset({{0.0, 0.0}, 0.0});
  m.set_pulses({1100, 1800});  // hard over, good thrust
  run(m, 8.0);
  const std::array<core::BodyPoint, 3> arms{{{0.0, 0.0}, {-0.5, 0.0}, {-0.6, 0.2}}};
  const TruthState before = m.truth();
  m.step();
  const TruthState now = m.truth();
  m.step();
  const TruthState after = m.truth();
  ASSERT_GT(std::abs(now.yaw_rate_dps), 10.0);
  const double dt = 2.0 * m.dt_s();
  double largest_swing_mps = 0.0;
  for (const core::BodyPoint arm : arms) {
    const core::NavPoint a = core::body_to_nav(before.pose, arm);
    const core::NavPoint b = core::body_to_nav(after.pose, arm);
    const core::NavPoint v = velocity_at(now, core::body_to_nav(now.pose, arm));
    EXPECT_NEAR(v.north_m, (b.north_m - a.north_m) / dt, 2e-3);
    EXPECT_NEAR(v.east_m, (b.east_m - a.east_m) / dt, 2e-3);
    largest_swing_mps = std::max(
        largest_swing_mps, std::hypot(v.north_m - now.vel_north_mps, v.east_m - now.vel_east_mps));
  }
  EXPECT_GT(largest_swing_mps, 0.05);  // the arms matter at this rate
}

}  // namespace
}  // namespace coxswain::sim::dynamics
