// SPDX-License-Identifier: Apache-2.0
#include "coxswain/control/actuator_mixer.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "coxswain/core/angles.hpp"

namespace coxswain::control {
namespace {

MixerConfig twin_config() {
  MixerConfig c;
  c.layout = msg::ActuatorLayout::kTwinThrusters;
  c.twin.track_width_m = 0.6;
  c.twin.max_speed_mps = 1.5;
  c.twin.max_yaw_rate_dps = 60.0;
  for (ThrusterConfig* t : {&c.twin.port, &c.twin.starboard}) {
    t->forward_start_us = 1500;  // no deadband so fractions map linearly onto 1500..1900
    t->forward_max_us = 1900;
    t->reverse_start_us = 1500;
    t->reverse_max_us = 1100;
    t->reverse_allowed = true;
    t->deadband_frac = 0.0;
  }
  return c;
}

TEST(ActuatorMixer, DefaultsValidateAndNeutral) {
  const MixerConfig c;
  EXPECT_FALSE(c.validate().has_value());
  EXPECT_FALSE(twin_config().validate().has_value());
  const ActuatorMixer m(c);
  const msg::ActuatorCommand n = m.neutral(123);
  EXPECT_FALSE(n.active);
  EXPECT_EQ(n.stamp_ns, 123);
  EXPECT_EQ(n.pulse_us[0], 1500);
  EXPECT_EQ(n.pulse_us[1], 1500);
  const msg::ActuatorCommand z = m.mix({0.0, 0.0}, 5);
  EXPECT_TRUE(z.active);
  EXPECT_EQ(z.pulse_us[0], 1500);
  EXPECT_EQ(z.pulse_us[1], 1500);
}

TEST(ActuatorMixer, ThrusterSkipsDeadbandAndClamps) {
  const ThrusterConfig t;                                       // 1550..1880 forward, no reverse
  EXPECT_EQ(ActuatorMixer::thruster_pulse_us(t, 0.005), 1500);  // below deadband_frac
  EXPECT_EQ(ActuatorMixer::thruster_pulse_us(t, 0.02), 1557);   // 1550 + 0.02 * 330 = 1556.6
  EXPECT_EQ(ActuatorMixer::thruster_pulse_us(t, 0.5), 1715);
  EXPECT_EQ(ActuatorMixer::thruster_pulse_us(t, 1.0), 1880);
  EXPECT_EQ(ActuatorMixer::thruster_pulse_us(t, 7.0), 1880);
  EXPECT_EQ(ActuatorMixer::thruster_pulse_us(t, -0.5), 1500);  // reverse not allowed
  EXPECT_EQ(ActuatorMixer::thruster_pulse_us(t, std::nan("")), 1500);
  ThrusterConfig r = t;
  r.reverse_allowed = true;
  EXPECT_EQ(ActuatorMixer::thruster_pulse_us(r, -1.0), 1120);
  EXPECT_EQ(ActuatorMixer::thruster_pulse_us(r, -0.5), 1285);
}

TEST(ActuatorMixer, ServoClampsToItsTravel) {
  const ActuatorMixer m;  // 1250..1750 for +-25 deg
  EXPECT_EQ(m.servo_pulse_us(25.0), 1750);
  EXPECT_EQ(m.servo_pulse_us(90.0), 1750);
  EXPECT_EQ(m.servo_pulse_us(-90.0), 1250);
  EXPECT_EQ(m.servo_pulse_us(10.0), 1600);
  MixDetail d;
  const msg::ActuatorCommand c = m.mix({2.0, 0.5}, 0, &d);
  EXPECT_EQ(c.pulse_us[0], 1750);
  EXPECT_TRUE(d.saturated);
  MixerConfig rev;
  rev.servo.sign = -1;
  EXPECT_EQ(ActuatorMixer(rev).servo_pulse_us(10.0), 1400);
}

// Astern, the servo-turned thruster pulls the stern the other way: the same turn demand must
// deflect the servo the other way, or a heading held astern runs away.
TEST(ActuatorMixer, ServoMirrorsAsternSoTheTurnKeepsItsSense) {
  MixerConfig c;
  c.thruster.reverse_allowed = true;
  const ActuatorMixer m(c);
  MixDetail ahead;
  MixDetail astern;
  const msg::ActuatorCommand fwd = m.mix({0.4, 0.5}, 0, &ahead);
  const msg::ActuatorCommand back = m.mix({0.4, -0.5}, 0, &astern);
  EXPECT_EQ(fwd.pulse_us[0], 1600);   // +10 deg: pushes the stern to port, bow to starboard
  EXPECT_EQ(back.pulse_us[0], 1400);  // -10 deg: pulling astern, the same yaw
  EXPECT_DOUBLE_EQ(ahead.channel_frac[0], 0.4);
  EXPECT_DOUBLE_EQ(astern.channel_frac[0], -0.4);
  EXPECT_LT(back.pulse_us[1], 1500);
  // No thrust: nothing to mirror.
  EXPECT_EQ(m.mix({0.4, 0.0}, 0).pulse_us[0], 1600);
}

// The left bias: base + offset truncated to an integer gives port turns one microsecond more
// than starboard turns. Ours rounds the offset symmetrically.
TEST(ActuatorMixer, NoLeftBiasInServoPulses) {
  const ActuatorMixer m;
  int naive_asymmetric = 0;
  for (double deg = 0.05; deg <= 25.0; deg += 0.37) {
    const int right = m.servo_pulse_us(deg) - 1500;
    const int left = 1500 - m.servo_pulse_us(-deg);
    EXPECT_EQ(right, left) << deg;
    const double off = deg / 25.0 * 250.0;
    const auto naive_r = static_cast<int>(1500.0 + off) - 1500;
    const auto naive_l = 1500 - static_cast<int>(1500.0 - off);
    if (naive_r != naive_l) ++naive_asymmetric;
  }
  EXPECT_GT(naive_asymmetric, 30);
}

// The capstone report: v_left = v - omega L_w / 2, v_right = v + omega L_w / 2 (omega
// counter-clockwise). Our turn is clockwise-positive, so a starboard turn speeds up the port
// thruster.
TEST(ActuatorMixer, TwinDifferentialFormula) {
  const MixerConfig c = twin_config();
  const ActuatorMixer m(c);
  MixDetail d;
  const double turn = 0.5;
  const double thrust = 0.5;
  const msg::ActuatorCommand cmd = m.mix({turn, thrust}, 0, &d);
  const double v = thrust * 1.5;
  const double r = core::deg_to_rad(turn * 60.0);
  const double fp = (v + r * 0.3) / 1.5;
  const double fs = (v - r * 0.3) / 1.5;
  EXPECT_NEAR(d.channel_frac[0], fp, 1e-12);
  EXPECT_NEAR(d.channel_frac[1], fs, 1e-12);
  EXPECT_FALSE(d.saturated);
  EXPECT_EQ(cmd.pulse_us[0], static_cast<std::uint16_t>(std::lround(1500 + fp * 400)));
  EXPECT_EQ(cmd.pulse_us[1], static_cast<std::uint16_t>(std::lround(1500 + fs * 400)));
  // Mirror: port turn swaps the sides exactly.
  const msg::ActuatorCommand mir = m.mix({-turn, thrust}, 0);
  EXPECT_EQ(mir.pulse_us[0], cmd.pulse_us[1]);
  EXPECT_EQ(mir.pulse_us[1], cmd.pulse_us[0]);
}

TEST(ActuatorMixer, TwinDesaturationKeepsTheTurn) {
  const ActuatorMixer m(twin_config());
  MixDetail d;
  (void)m.mix({0.5, 1.0}, 0, &d);  // full thrust plus a turn: port would exceed 1
  EXPECT_TRUE(d.saturated);
  EXPECT_NEAR(d.channel_frac[0], 1.0, 1e-12);
  const double diff = 2.0 * core::deg_to_rad(30.0) * 0.3 / 1.5;
  EXPECT_NEAR(d.channel_frac[0] - d.channel_frac[1], diff, 1e-12);

  MixerConfig fwd = twin_config();
  fwd.twin.port.reverse_allowed = false;
  fwd.twin.starboard.reverse_allowed = false;
  (void)ActuatorMixer(fwd).mix({0.5, 0.0}, 0, &d);  // turn in place without reverse
  EXPECT_NEAR(d.channel_frac[1], 0.0, 1e-12);
  EXPECT_NEAR(d.channel_frac[0], diff, 1e-12);
}

TEST(ActuatorMixer, ValidateRejectsBadConfigs) {
  MixerConfig c;
  c.thruster.forward_start_us = 1400;
  EXPECT_TRUE(c.validate().has_value());
  c = {};
  c.servo.sign = 0;
  EXPECT_TRUE(c.validate().has_value());
  c = twin_config();
  c.twin.track_width_m = 0.0;
  EXPECT_TRUE(c.validate().has_value());
}

}  // namespace
}  // namespace coxswain::control
