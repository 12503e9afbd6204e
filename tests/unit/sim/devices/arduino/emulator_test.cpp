// SPDX-License-Identifier: Apache-2.0
// The Arduino emulator (tools/sim/devices/arduino) runs the firmware's FirmwareLogic: checked
// through the daemon's ArduinoCodec and CommandEncoder for the bootloader, Ready/Hello/Ping,
// telemetry rate, the exact 300 ms failsafe, the RC-absent rule and faults.
#include "sim/devices/arduino/emulator.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "coxswain/drivers/arduino/codec.hpp"

namespace coxswain::sim::devices::arduino {
namespace {

namespace d = drivers::arduino;
constexpr core::TimeNs kMs = core::kNsPerMs;

struct Collected {
  std::vector<d::BoardMessage> messages;
  std::vector<core::TimeNs> at;
};

void collect(Emulator& e, d::ArduinoCodec& codec, core::TimeNs from, core::TimeNs to,
             Collected& out, core::TimeNs step = kMs) {
  for (core::TimeNs t = from; t <= to; t += step) {
    auto bytes = e.poll(t);
    while (!bytes.empty()) {
      const auto s = codec.decode(bytes);
      bytes = bytes.subspan(s.consumed);
      if (s.produced) {
        out.messages.push_back(codec.message());
        out.at.push_back(t);
      }
    }
  }
}

msg::ActuatorCommand armed(std::uint16_t a, std::uint16_t b) {
  return {0, {a, b}, msg::LedColour::kBlue, true};
}

TEST(ArduinoEmulator, BootloaderIsSilentThenReadyThenTelemetryAtTwentyHertz) {
  Emulator e;
  d::ArduinoCodec codec;
  d::CommandEncoder enc;
  e.reset(0);
  e.receive(enc.encode(armed(1600, 1600)), 100 * kMs);
  EXPECT_EQ(e.stats().bytes_lost_in_bootloader, 14U);
  Collected c;
  collect(e, codec, 0, 1'499 * kMs, c);
  EXPECT_TRUE(c.messages.empty());
  EXPECT_EQ(e.outputs().pulse_us[0], 0) << "no PWM while the bootloader runs";
  collect(e, codec, 1'500 * kMs, 2'500 * kMs, c);
  ASSERT_FALSE(c.messages.empty());
  EXPECT_EQ(c.messages[0].type, d::MsgType::kReady);
  EXPECT_EQ(c.messages[0].ready.failsafe_ms, 300);
  EXPECT_EQ(c.messages[0].ready.reset_cause, 0x02);
  std::size_t telemetry = 0;
  for (std::size_t i = 1; i < c.messages.size(); ++i) {
    EXPECT_EQ(c.messages[i].type, d::MsgType::kTelemetry);
    EXPECT_EQ(c.messages[i].seq, c.messages[i - 1].seq + 1);
    ++telemetry;
    if (i > 1) {
      EXPECT_EQ(c.at[i] - c.at[i - 1], 50 * kMs);
    }
  }
  EXPECT_EQ(telemetry, 20U);
  EXPECT_EQ(c.messages.back().telemetry.source,
            static_cast<std::uint8_t>(d::OutputSource::kBootHold));
  EXPECT_EQ(e.outputs().pulse_us[0], 1500);
}

TEST(ArduinoEmulator, FailsafeFallsExactlyThreeHundredMillisecondsAfterTheLastCommand) {
  Emulator e;
  d::ArduinoCodec codec;
  d::CommandEncoder enc;
  e.reset(0);
  const core::TimeNs ready = 1'500 * kMs + 3'000 * kMs;  // bootloader + boot hold
  Collected c;
  collect(e, codec, 0, ready, c, 10 * kMs);
  const core::TimeNs t = ready + 100 * kMs;
  (void)e.poll(t);
  e.receive(enc.encode(armed(1700, 1300)), t);
  (void)e.poll(t + kMs);
  EXPECT_EQ(e.outputs().source, d::OutputSource::kHost);
  EXPECT_EQ(e.outputs().pulse_us[0], 1700);
  EXPECT_EQ(e.outputs().pulse_us[1], 1300);
  (void)e.poll(t + 299 * kMs);
  EXPECT_EQ(e.outputs().source, d::OutputSource::kHost);
  (void)e.poll(t + 300 * kMs);
  EXPECT_EQ(e.outputs().source, d::OutputSource::kFailsafe);
  EXPECT_EQ(e.outputs().pulse_us[0], 1500);
  EXPECT_EQ(e.logic().counters().failsafe_events, 1);
  // A repeated sequence does not refresh the failsafe; a new one does.
  e.receive(enc.encode(armed(1800, 1800)), t + 310 * kMs);
  (void)e.poll(t + 311 * kMs);
  EXPECT_EQ(e.outputs().pulse_us[0], 1800);
}

TEST(ArduinoEmulator, RcAbsentEstopAndManualFollowTheFirmwareRules) {
  Emulator e;
  d::CommandEncoder enc;
  e.reset(0);
  core::TimeNs t = 4'600 * kMs;
  (void)e.poll(t);
  const auto command = [&] {
    e.receive(enc.encode(armed(1650, 1650)), t);
    t += 20 * kMs;
    (void)e.poll(t);
  };
  command();
  EXPECT_EQ(e.outputs().source, d::OutputSource::kHost);
  BoardInputs in;
  in.rc_present = false;
  e.set_inputs(in);
  for (int i = 0; i < 12; ++i) command();
  EXPECT_EQ(e.outputs().source, d::OutputSource::kNoRc) << "RC lost after 200 ms";
  EXPECT_EQ(e.outputs().mode, d::Mode::kManual);
  in.rc_present = true;
  e.set_inputs(in);
  for (int i = 0; i < 3; ++i) command();
  EXPECT_EQ(e.outputs().source, d::OutputSource::kHost) << "switch seen in auto again";
  in.estop = true;
  e.set_inputs(in);
  command();
  EXPECT_EQ(e.outputs().source, d::OutputSource::kEstop);
  in.estop = false;
  in.mode_auto = false;
  in.rc_throttle_us = 1234;
  e.set_inputs(in);
  for (int i = 0; i < 2; ++i) command();
  EXPECT_EQ(e.outputs().source, d::OutputSource::kRcManual);
  EXPECT_EQ(e.outputs().pulse_us[1], 1234);
}

TEST(ArduinoEmulator, HelloGetsReadyAndPingGetsPong) {
  Emulator e;
  d::ArduinoCodec codec;
  d::CommandEncoder enc;
  e.reset(0);
  Collected c;
  collect(e, codec, 0, 1'500 * kMs, c, 10 * kMs);
  c = {};
  e.receive(enc.encode_hello(), 1'510 * kMs);
  e.receive(enc.encode_ping(0xCAFEF00D), 1'510 * kMs);
  collect(e, codec, 1'510 * kMs, 1'510 * kMs, c);
  ASSERT_EQ(c.messages.size(), 2U);
  EXPECT_EQ(c.messages[0].type, d::MsgType::kReady);
  EXPECT_EQ(c.messages[1].type, d::MsgType::kPong);
  EXPECT_EQ(c.messages[1].pong.token, 0xCAFEF00DU);
  EXPECT_EQ(e.stats().hellos, 1U);
}

TEST(ArduinoEmulator, FaultsCorruptTelemetryAddGarbageOrSilenceTheBoard) {
  EmulatorConfig cfg;
  cfg.faults.corrupt_probability = 0.2;
  cfg.faults.garbage_probability = 0.2;
  cfg.faults.seed = 42;
  Emulator e(cfg);
  d::ArduinoCodec codec;
  e.reset(0);
  Collected c;
  collect(e, codec, 0, 11'500 * kMs, c, 10 * kMs);
  EXPECT_EQ(e.stats().telemetry_sent, 200U);
  EXPECT_GT(e.stats().corrupted_frames, 20U);
  EXPECT_GE(codec.stats().checksum_errors, e.stats().corrupted_frames);
  EXPECT_GE(c.messages.size() + e.stats().corrupted_frames, 200U);
  EXPECT_LT(c.messages.size(), 200U);
  e.set_faults({0.0, 0.0, true, 1});
  Collected silent;
  collect(e, codec, 11'510 * kMs, 12'500 * kMs, silent, 10 * kMs);
  EXPECT_TRUE(silent.messages.empty());
}

}  // namespace
}  // namespace coxswain::sim::devices::arduino
