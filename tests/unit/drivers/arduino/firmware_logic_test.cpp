// SPDX-License-Identifier: Apache-2.0
// Firmware decision core: boot hold, failsafe timing edges, RC loss, mode switch, e-stop,
// clamping, sequence handling, millis() wrap, and an exhaustive decision table.
#include "coxswain/drivers/arduino/firmware_logic.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

namespace coxswain::drivers::arduino {
namespace {

constexpr SwitchInputs kRun{false, false};
constexpr SwitchInputs kStop{true, false};

LogicConfig no_boot_hold() {
  LogicConfig c;
  c.boot_neutral_ms = 0;
  return c;
}

SetOutputs armed(std::uint16_t a, std::uint16_t b, std::uint8_t led = 1) {
  return SetOutputs{{a, b}, led, kFlagArm};
}

void feed_rc(FirmwareLogic& l, std::uint32_t now_ms, std::uint16_t steer, std::uint16_t throttle,
             std::uint16_t mode_sw) {
  l.on_rc_pulse(now_ms, 0, steer);
  l.on_rc_pulse(now_ms, 1, throttle);
  l.on_rc_pulse(now_ms, 2, mode_sw);
}

TEST(ArduinoLogic, ConfigValidation) {
  LogicConfig c;
  EXPECT_EQ(c.validate(), nullptr);
  c.min_us[1] = 1600;
  EXPECT_NE(c.validate(), nullptr);
  c = LogicConfig{};
  c.max_us[0] = 2600;
  EXPECT_NE(c.validate(), nullptr);
  c = LogicConfig{};
  c.failsafe_ms = 0;
  EXPECT_NE(c.validate(), nullptr);
  c = LogicConfig{};
  c.mode_manual_below_us = 1800;
  EXPECT_NE(c.validate(), nullptr);
  c = LogicConfig{};
  c.rc_valid_min_us = 2300;
  EXPECT_NE(c.validate(), nullptr);
}

TEST(ArduinoLogic, BootHoldEndsExactlyAtConfiguredTime) {
  FirmwareLogic l{LogicConfig{}};
  l.reset(1000);
  for (std::uint32_t t = 1000; t < 4100; t += 50) {
    feed_rc(l, t, 1500, 1500, 2000);
    (void)l.on_set_outputs(t, static_cast<std::uint16_t>(t), armed(1800, 1800));
    const LogicOutputs o = l.step(t, kRun);
    if (t < 4000) {
      EXPECT_EQ(o.source, OutputSource::kBootHold) << t;
      EXPECT_TRUE(o.boot_hold);
      EXPECT_EQ(o.pulse_us[1], 1500);
    } else {
      EXPECT_EQ(o.source, OutputSource::kHost) << t;
      EXPECT_EQ(o.pulse_us[1], 1800);
    }
  }
  // Just below / at the edge.
  FirmwareLogic m{LogicConfig{}};
  m.reset(0);
  feed_rc(m, 2999, 1500, 1500, 2000);
  (void)m.on_set_outputs(2999, 1, armed(1800, 1800));
  EXPECT_TRUE(m.step(2999, kRun).boot_hold);
  EXPECT_FALSE(m.step(3000, kRun).boot_hold);
}

TEST(ArduinoLogic, FailsafeEdgeAtExactlyTimeout) {
  FirmwareLogic l{no_boot_hold()};
  l.reset(0);
  EXPECT_TRUE(l.step(0, kRun).failsafe);  // no command yet
  ASSERT_TRUE(l.on_set_outputs(100, 1, armed(1700, 1300)));
  for (std::uint32_t t = 100; t <= 500; ++t) {
    if (t % 50 == 0) feed_rc(l, t, 1500, 1500, 1900);
    const LogicOutputs o = l.step(t, kRun);
    const bool fresh = t < 400;  // 300 ms after the command at t=100
    EXPECT_EQ(o.failsafe, !fresh) << t;
    EXPECT_EQ(o.source, fresh ? OutputSource::kHost : OutputSource::kFailsafe) << t;
    EXPECT_EQ(o.pulse_us[0], fresh ? 1700 : 1500) << t;
    EXPECT_EQ(o.pulse_us[1], fresh ? 1300 : 1500) << t;
    EXPECT_EQ(o.armed, fresh);
  }
  EXPECT_EQ(l.counters().failsafe_events, 1U);
  // A new command restores host control immediately.
  ASSERT_TRUE(l.on_set_outputs(501, 2, armed(1600, 1600)));
  EXPECT_EQ(l.step(501, kRun).source, OutputSource::kHost);
}

TEST(ArduinoLogic, ConfigurableFailsafeAndNeutral) {
  LogicConfig c = no_boot_hold();
  c.failsafe_ms = 50;
  c.neutral_us[0] = 1520;
  c.neutral_us[1] = 1480;
  FirmwareLogic l{c};
  l.reset(0);
  feed_rc(l, 0, 1500, 1500, 2000);
  ASSERT_TRUE(l.on_set_outputs(0, 1, armed(1800, 1800)));
  EXPECT_EQ(l.step(49, kRun).source, OutputSource::kHost);
  const LogicOutputs o = l.step(50, kRun);
  EXPECT_EQ(o.source, OutputSource::kFailsafe);
  EXPECT_EQ(o.pulse_us[0], 1520);
  EXPECT_EQ(o.pulse_us[1], 1480);
}

TEST(ArduinoLogic, NeverAutonomousWithoutRc) {
  FirmwareLogic l{no_boot_hold()};
  l.reset(0);
  ASSERT_TRUE(l.on_set_outputs(0, 1, armed(1800, 1800)));
  LogicOutputs o = l.step(1, kRun);
  EXPECT_FALSE(o.rc_present);
  EXPECT_EQ(o.mode, Mode::kManual);
  EXPECT_EQ(o.source, OutputSource::kNoRc);
  EXPECT_EQ(o.pulse_us[0], 1500);
  // Only two of three channels: still absent.
  l.on_rc_pulse(2, 0, 1500);
  l.on_rc_pulse(2, 1, 1500);
  EXPECT_EQ(l.step(3, kRun).source, OutputSource::kNoRc);
  l.on_rc_pulse(4, 2, 2000);
  o = l.step(5, kRun);
  EXPECT_TRUE(o.rc_present);
  EXPECT_EQ(o.mode, Mode::kAutonomous);
  EXPECT_EQ(o.source, OutputSource::kHost);
}

TEST(ArduinoLogic, RcLossEdgeAndRecovery) {
  FirmwareLogic l{no_boot_hold()};
  l.reset(0);
  feed_rc(l, 10, 1500, 1500, 2000);
  for (std::uint32_t t = 10; t < 300; t += 10) {
    (void)l.on_set_outputs(t, static_cast<std::uint16_t>(t), armed(1700, 1700));
    const LogicOutputs o = l.step(t, kRun);
    const bool present = t < 210;  // rc_timeout_ms = 200 after the pulses at t=10
    EXPECT_EQ(o.rc_present, present) << t;
    EXPECT_EQ(o.mode, present ? Mode::kAutonomous : Mode::kManual) << t;
    EXPECT_EQ(o.pulse_us[0], present ? 1700 : 1500) << t;
  }
  EXPECT_EQ(l.counters().rc_loss_events, 1U);
  // RC returns with the switch in the dead band: autonomy needs an explicit "auto" again.
  feed_rc(l, 300, 1500, 1500, 1500);
  (void)l.on_set_outputs(300, 400, armed(1700, 1700));
  LogicOutputs o = l.step(300, kRun);
  EXPECT_EQ(o.mode, Mode::kManual);
  EXPECT_EQ(o.source, OutputSource::kRcManual);
  feed_rc(l, 310, 1500, 1500, 1700);
  o = l.step(310, kRun);
  EXPECT_EQ(o.mode, Mode::kAutonomous);
}

TEST(ArduinoLogic, ManualPassesRcThroughClamped) {
  FirmwareLogic l{no_boot_hold()};
  l.reset(0);
  ASSERT_TRUE(l.on_set_outputs(0, 1, armed(1800, 1800)));
  feed_rc(l, 0, 1000, 1950, 1000);
  LogicOutputs o = l.step(1, kRun);
  EXPECT_EQ(o.mode, Mode::kManual);
  EXPECT_EQ(o.source, OutputSource::kRcManual);
  EXPECT_EQ(o.pulse_us[0], 1100);  // clamped to min_us
  EXPECT_EQ(o.pulse_us[1], 1900);  // clamped to max_us
  EXPECT_EQ(o.led, 1);             // LED still follows the host
  feed_rc(l, 2, 1234, 1666, 1200);
  o = l.step(3, kRun);
  EXPECT_EQ(o.pulse_us[0], 1234);
  EXPECT_EQ(o.pulse_us[1], 1666);
}

TEST(ArduinoLogic, ModeSwitchHysteresis) {
  FirmwareLogic l{no_boot_hold()};
  l.reset(0);
  ASSERT_TRUE(l.on_set_outputs(0, 1, armed(1800, 1800)));
  const std::uint16_t sw[] = {1500, 1699, 1700, 1500, 1301, 1300, 1500, 1699};
  const Mode expected[] = {Mode::kManual,     Mode::kManual, Mode::kAutonomous, Mode::kAutonomous,
                           Mode::kAutonomous, Mode::kManual, Mode::kManual,     Mode::kManual};
  for (std::size_t i = 0; i < std::size(sw); ++i) {
    feed_rc(l, 10, 1500, 1500, sw[i]);
    EXPECT_EQ(l.step(10, kRun).mode, expected[i]) << i;
  }
}

TEST(ArduinoLogic, EstopForcesNeutralInEveryMode) {
  FirmwareLogic l{no_boot_hold()};
  l.reset(0);
  ASSERT_TRUE(l.on_set_outputs(0, 1, armed(1800, 1200)));
  feed_rc(l, 0, 1800, 1800, 2000);  // autonomous
  LogicOutputs o = l.step(1, kStop);
  EXPECT_EQ(o.source, OutputSource::kEstop);
  EXPECT_EQ(o.mode, Mode::kManual);
  EXPECT_TRUE(o.estop);
  EXPECT_EQ(o.pulse_us[0], 1500);
  EXPECT_EQ(o.pulse_us[1], 1500);
  feed_rc(l, 2, 1800, 1800, 1000);  // manual
  o = l.step(3, kStop);
  EXPECT_EQ(o.source, OutputSource::kEstop);
  EXPECT_EQ(o.pulse_us[0], 1500);
  o = l.step(4, kRun);
  EXPECT_EQ(o.source, OutputSource::kRcManual);
}

TEST(ArduinoLogic, HostPulsesClampedAndDisarmNeutral) {
  FirmwareLogic l{no_boot_hold()};
  l.reset(0);
  feed_rc(l, 0, 1500, 1500, 2000);
  ASSERT_TRUE(l.on_set_outputs(0, 1, armed(0, 65535)));
  LogicOutputs o = l.step(1, kRun);
  EXPECT_EQ(o.pulse_us[0], 1100);
  EXPECT_EQ(o.pulse_us[1], 1900);
  ASSERT_TRUE(l.on_set_outputs(2, 2, SetOutputs{{1800, 1800}, 3, 0}));
  o = l.step(3, kRun);
  EXPECT_EQ(o.source, OutputSource::kDisarmed);
  EXPECT_FALSE(o.armed);
  EXPECT_FALSE(o.failsafe);
  EXPECT_EQ(o.pulse_us[0], 1500);
  EXPECT_EQ(o.led, 3);
}

TEST(ArduinoLogic, InvalidRcPulsesIgnored) {
  FirmwareLogic l{no_boot_hold()};
  l.reset(0);
  feed_rc(l, 0, 799, 2201, 65535);
  l.on_rc_pulse(0, 7, 1500);  // no such channel
  EXPECT_FALSE(l.step(1, kRun).rc_present);
  EXPECT_EQ(l.counters().rc_invalid_pulses, 3U);
  feed_rc(l, 0, 800, 2200, 1500);
  EXPECT_TRUE(l.step(1, kRun).rc_present);
}

TEST(ArduinoLogic, SequenceDuplicatesGapsAndWrap) {
  FirmwareLogic l{no_boot_hold()};
  l.reset(0);
  feed_rc(l, 0, 1500, 1500, 2000);
  EXPECT_TRUE(l.on_set_outputs(0, 65533, armed(1600, 1600)));
  EXPECT_TRUE(l.on_set_outputs(10, 65534, armed(1600, 1600)));
  EXPECT_TRUE(l.on_set_outputs(20, 65535, armed(1600, 1600)));
  EXPECT_TRUE(l.on_set_outputs(30, 0, armed(1600, 1600)));  // wrap: no gap
  EXPECT_EQ(l.counters().seq_gaps, 0U);
  EXPECT_TRUE(l.on_set_outputs(40, 3, armed(1600, 1600)));  // 1 and 2 lost
  EXPECT_EQ(l.counters().seq_gaps, 2U);
  EXPECT_EQ(l.last_seq(), 3);
  // A repeated sequence is ignored and does not refresh the failsafe timer.
  EXPECT_FALSE(l.on_set_outputs(300, 3, armed(1700, 1700)));
  EXPECT_EQ(l.counters().seq_duplicates, 1U);
  feed_rc(l, 300, 1500, 1500, 2000);
  EXPECT_EQ(l.step(339, kRun).pulse_us[0], 1600);
  EXPECT_EQ(l.step(340, kRun).source, OutputSource::kFailsafe);
  // Hello: the host restarted, so seq 3 again is accepted.
  l.on_hello();
  EXPECT_TRUE(l.on_set_outputs(341, 3, armed(1700, 1700)));
  EXPECT_EQ(l.counters().commands_accepted, 6U);
  EXPECT_EQ(l.counters().seq_gaps, 2U);
}

TEST(ArduinoLogic, MillisWrapKeepsTiming) {
  FirmwareLogic l{LogicConfig{}};
  const std::uint32_t t0 = 0xFFFFFFFFU - 3500U;
  l.reset(t0);
  std::uint32_t t = t0;
  std::uint16_t seq = 0;
  for (int i = 0; i < 100; ++i, t += 50) {  // crosses 2^32 at i = 70
    feed_rc(l, t, 1500, 1500, 2000);
    (void)l.on_set_outputs(t, seq++, armed(1750, 1750));
    const LogicOutputs o = l.step(t, kRun);
    const bool held = (t - t0) < 3000U;
    EXPECT_EQ(o.source, held ? OutputSource::kBootHold : OutputSource::kHost) << i;
  }
  // Stop commanding across the wrap: failsafe exactly 300 ms later.
  const std::uint32_t last = t - 50;
  feed_rc(l, last + 200, 1500, 1500, 2000);
  EXPECT_EQ(l.step(last + 299, kRun).source, OutputSource::kHost);
  EXPECT_EQ(l.step(last + 300, kRun).source, OutputSource::kFailsafe);
}

// Independent statement of the priority table of PROTOCOL.md.
OutputSource reference(bool estop, bool rc, bool sw_auto, int cmd /*0 none,1 fresh,2 stale*/,
                       bool arm) {
  if (estop) return OutputSource::kEstop;
  if (!rc) return OutputSource::kNoRc;
  if (!sw_auto) return OutputSource::kRcManual;
  if (cmd != 1) return OutputSource::kFailsafe;
  if (!arm) return OutputSource::kDisarmed;
  return OutputSource::kHost;
}

TEST(ArduinoLogic, ExhaustiveDecisionTable) {
  int cases = 0;
  for (int estop = 0; estop < 2; ++estop) {
    for (int rc = 0; rc < 2; ++rc) {
      for (int sw = 0; sw < 2; ++sw) {
        for (int cmd = 0; cmd < 3; ++cmd) {
          for (int arm = 0; arm < 2; ++arm) {
            for (std::uint32_t dt = 0; dt < 320; dt += 7) {  // command age sweep
              FirmwareLogic l{no_boot_hold()};
              const std::uint32_t base = 1000;
              l.reset(0);
              if (rc) feed_rc(l, base, 1300, 1700, sw ? 1900 : 1100);
              if (cmd != 0) {
                const std::uint32_t age = cmd == 1 ? dt % 300 : 300 + dt;
                (void)l.on_set_outputs(
                    base - age, 5, SetOutputs{{1650, 1350}, 4, arm ? kFlagArm : std::uint8_t{0}});
              }
              const LogicOutputs o = l.step(base, SwitchInputs{estop != 0, true});
              const OutputSource want = reference(estop, rc, sw, cmd, arm);
              const std::string ctx = std::to_string(estop) + std::to_string(rc) +
                                      std::to_string(sw) + std::to_string(cmd) +
                                      std::to_string(arm) + " dt=" + std::to_string(dt);
              ASSERT_EQ(o.source, want) << ctx;
              ASSERT_EQ(o.failsafe, cmd != 1) << ctx;
              ASSERT_EQ(o.mode, (rc && sw && !estop) ? Mode::kAutonomous : Mode::kManual) << ctx;
              ASSERT_TRUE(o.start_switch);
              if (want == OutputSource::kHost) {
                ASSERT_EQ(o.pulse_us[0], 1650);
                ASSERT_EQ(o.pulse_us[1], 1350);
              } else if (want == OutputSource::kRcManual) {
                ASSERT_EQ(o.pulse_us[0], 1300);
                ASSERT_EQ(o.pulse_us[1], 1700);
              } else {
                ASSERT_EQ(o.pulse_us[0], 1500) << ctx;
                ASSERT_EQ(o.pulse_us[1], 1500) << ctx;
              }
              ++cases;
            }
          }
        }
      }
    }
  }
  EXPECT_EQ(cases, 48 * 46);
}

TEST(ArduinoLogic, TelemetryReflectsOutputsAndCounters) {
  FirmwareLogic l{no_boot_hold()};
  l.reset(100);
  feed_rc(l, 100, 1400, 1600, 1900);
  (void)l.on_set_outputs(100, 10, armed(1750, 1250, 2));
  (void)l.on_set_outputs(101, 12, armed(1750, 1250, 2));
  const LogicOutputs o = l.step(150, SwitchInputs{false, true});
  DecoderStats rx{1000, 70000, 3, 4, 5};
  Telemetry t{};
  l.fill_telemetry(1100, o, rx, 12000, &t);
  EXPECT_EQ(t.uptime_ms, 1000U);
  EXPECT_EQ(t.applied_pulse_us[0], 1750);
  EXPECT_EQ(t.rc_pulse_us[0], 1400);
  EXPECT_EQ(t.rc_pulse_us[2], 1900);
  EXPECT_EQ(t.led, 2);
  EXPECT_EQ(t.mode, static_cast<std::uint8_t>(Mode::kAutonomous));
  EXPECT_EQ(t.flags, kTelRcPresent | kTelStartSwitch | kTelArmed);
  EXPECT_EQ(t.source, static_cast<std::uint8_t>(OutputSource::kHost));
  EXPECT_EQ(t.supply_mv, 12000);
  EXPECT_EQ(t.last_seq, 12);
  EXPECT_EQ(t.rx_frames_ok, static_cast<std::uint16_t>(70000 & 0xFFFF));
  EXPECT_EQ(t.rx_crc_errors, 3);
  EXPECT_EQ(t.seq_gaps, 1);
}

}  // namespace
}  // namespace coxswain::drivers::arduino
