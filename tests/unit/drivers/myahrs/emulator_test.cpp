// SPDX-License-Identifier: Apache-2.0
// The myAHRS+ emulator (tools/sim/devices/myahrs) checked through the production decoder and the
// start-up plan: what the simulator feeds the daemon must decode to the truth it was given.
#include "sim/devices/myahrs/emulator.hpp"

#include <gtest/gtest.h>

#include <span>
#include <string>
#include <vector>

#include "coxswain/drivers/myahrs/codec.hpp"
#include "coxswain/drivers/myahrs/commands.hpp"

namespace coxswain::sim::devices::myahrs {
namespace {

using drivers::myahrs::Decoder;
using drivers::myahrs::EncodedCommand;
using drivers::myahrs::Output;

constexpr core::TimeNs kMs = core::kNsPerMs;

msg::ImuSample truth() {
  msg::ImuSample s;
  s.roll_deg = -1.55;
  s.pitch_deg = 2.25;
  s.yaw_magnetic_deg = 97.31;
  s.accel_g = {-0.0142, -0.0010, -0.9224};
  s.gyro_dps = {-0.9756, -0.3659, 12.5};
  s.mag_ut = {-8.4, -46.8, 5.4};
  s.temperature_c = 38.3;
  return s;
}

struct Collected {
  std::vector<msg::ImuSample> samples;
  std::vector<std::string> responses;  // "name OK|ERROR"
  std::vector<std::string> fmt;        // the `fmt` attribute of each response, if any
};

void feed(Decoder& d, std::span<const std::uint8_t> bytes, Collected& c) {
  while (!bytes.empty()) {
    const auto step = d.decode(bytes);
    bytes = bytes.subspan(step.consumed);
    if (!step.produced) continue;
    if (d.last_output() == Output::kSample) {
      c.samples.push_back(d.sample());
    } else {
      c.responses.push_back(std::string(d.response().command) +
                            (d.response().ok ? " OK" : " ERROR"));
      c.fmt.push_back(std::string(d.response().attribute("fmt").value_or("")));
    }
  }
}

void send(Emulator& e, const EncodedCommand& c) { e.receive(c.data()); }

TEST(MyahrsEmulator, DefaultAsciiStreamAtHundredHertzDecodesToTruth) {
  Emulator e;
  e.set_truth(truth());
  Decoder d;
  Collected c;
  for (core::TimeNs t = 0; t < 1000 * kMs; t += kMs) feed(d, e.poll(t), c);
  ASSERT_EQ(c.samples.size(), 100U);
  EXPECT_EQ(d.stats().codec.checksum_errors, 0U);
  const auto& s = c.samples.back();
  EXPECT_EQ(s.sequence, 99U);
  EXPECT_NEAR(s.roll_deg, -1.55, 0.005);
  EXPECT_NEAR(s.yaw_magnetic_deg, 97.31, 0.005);
  EXPECT_NEAR(s.accel_g[2], -0.9224, 5e-5);
  EXPECT_NEAR(s.gyro_dps[2], 12.5, 5e-5);
  EXPECT_NEAR(s.mag_ut[1], -46.8, 5e-5);
  EXPECT_NEAR(s.temperature_c, 38.3, 0.05);
  EXPECT_TRUE(s.has_inertial);
}

TEST(MyahrsEmulator, StartupPlanSwitchesToBinaryQuaternionAtFiftyHertz) {
  Emulator e;
  e.set_truth(truth());
  Decoder d;
  Collected c;
  drivers::myahrs::StartupParams p;
  p.form = drivers::myahrs::OutputForm::kBinary;
  p.content = drivers::myahrs::Content::kQuatImu;
  p.rate_hz = 50.0;
  core::TimeNs t = 0;
  // The plan must outlive the loop: view() points into it.
  const auto plan = drivers::myahrs::make_startup_plan(p);
  for (const auto& step : plan.view()) {
    send(e, step.command);
    t += 5 * kMs;
    const std::size_t before = c.responses.size();
    feed(d, e.poll(t), c);
    ASSERT_EQ(c.responses.size(), before + 1) << step.command.text();
    EXPECT_EQ(c.responses.back(), std::string(step.awaits) + " OK");
  }
  EXPECT_TRUE(e.binary());
  EXPECT_TRUE(e.continuous());
  EXPECT_EQ(e.divider(), 2);
  EXPECT_EQ(c.fmt[3], "QUATERNION IMU");

  c.samples.clear();
  const core::TimeNs start = t;
  for (t += kMs; t <= start + 1000 * kMs; t += kMs) feed(d, e.poll(t), c);
  EXPECT_EQ(c.samples.size(), 50U);
  EXPECT_EQ(d.stats().codec.checksum_errors, 0U);
  EXPECT_EQ(d.stats().codec.framing_errors, 0U);
  ASSERT_FALSE(c.samples.empty());
  const auto& s = c.samples.back();
  // Quaternion -> Euler through int16 / 32767 resolution.
  EXPECT_NEAR(s.yaw_magnetic_deg, 97.31, 0.02);
  EXPECT_NEAR(s.roll_deg, -1.55, 0.02);
  EXPECT_NEAR(s.pitch_deg, 2.25, 0.02);
  EXPECT_NEAR(s.accel_g[2], -0.9224, 16.0 / 32767.0);
  EXPECT_NEAR(s.gyro_dps[2], 12.5, 2000.0 / 32767.0);
  EXPECT_NEAR(s.temperature_c, 38.3, 200.0 / 32767.0);
}

TEST(MyahrsEmulator, BinaryAllNodesWithStuffingAndHeading) {
  drivers::myahrs::HeadingConfig hc;
  hc.mount_yaw_deg = 180.0;
  hc.declination_deg = -9.0;
  auto s = truth();
  s.yaw_magnetic_deg = Emulator::sensor_yaw_for_heading(179.5, hc);
  EmulatorConfig cfg;
  cfg.binary = true;
  cfg.binary_format = {true, true, true, true};
  Emulator e(cfg);
  e.set_truth(s);
  Decoder d(hc);
  Collected c;
  // 40 messages: sequences 16 (0x10) and the 0x10 bytes of some values must be stuffed.
  for (core::TimeNs t = 0; t < 400 * kMs; t += 10 * kMs) feed(d, e.poll(t), c);
  ASSERT_EQ(c.samples.size(), 40U);
  EXPECT_EQ(c.samples[16].sequence, 16U);
  EXPECT_EQ(d.stats().codec.framing_errors, 0U);
  EXPECT_TRUE(d.sample_detail().has_raw);
  EXPECT_TRUE(d.sample_detail().has_quaternion);
  EXPECT_EQ(d.sample_detail().raw_imu[2], -1889);  // -0.9224 g / 4.882813e-4 g/LSB
  EXPECT_NEAR(
      std::abs(drivers::myahrs::true_heading_deg(c.samples.back().yaw_magnetic_deg, hc) - 179.5),
      0.0, 0.01);
  EXPECT_NEAR(c.samples.back().heading_deg, 179.5, 0.01);
}

TEST(MyahrsEmulator, TriggerModeAndErrors) {
  Emulator e;
  e.set_truth(truth());
  Decoder d;
  Collected c;
  send(e, drivers::myahrs::trig_command());  // continuous: error
  send(e, drivers::myahrs::mode_command("T").value());
  feed(d, e.poll(0), c);
  ASSERT_EQ(c.responses.size(), 2U);
  EXPECT_EQ(c.responses[0], "trig ERROR");
  EXPECT_EQ(c.responses[1], "mode OK");
  c.samples.clear();
  feed(d, e.poll(500 * kMs), c);
  EXPECT_TRUE(c.samples.empty());  // quiet in trigger mode
  send(e, drivers::myahrs::trig_command());
  feed(d, e.poll(510 * kMs), c);
  EXPECT_EQ(c.samples.size(), 1U);

  send(e, drivers::myahrs::encode_request("asc_out", "NOPE").value());
  send(e, drivers::myahrs::encode_request("frobnicate").value());
  send(e, drivers::myahrs::encode_request("mode", "AB").value());
  const std::string bad = "@version*00\r\n";  // wrong checksum: no answer at all
  e.receive({reinterpret_cast<const std::uint8_t*>(bad.data()), bad.size()});
  send(e, drivers::myahrs::encode_request("divider", "4").value());
  feed(d, e.poll(520 * kMs), c);
  ASSERT_EQ(c.responses.size(), 6U);
  EXPECT_EQ(c.responses[2], "asc_out ERROR");
  EXPECT_EQ(c.responses[3], "frobnicate ERROR");
  EXPECT_EQ(c.responses[4], "mode ERROR");
  EXPECT_EQ(c.responses[5], "divider OK");
  EXPECT_EQ(e.stats().requests_bad_checksum, 1U);
  EXPECT_EQ(e.divider(), 4);
}

TEST(MyahrsEmulator, CorruptedChecksumsAreAllRejected) {
  EmulatorConfig cfg;
  cfg.faults.corrupt_checksum_probability = 1.0;
  for (const bool binary : {false, true}) {
    cfg.binary = binary;
    Emulator e(cfg);
    e.set_truth(truth());
    Decoder d;
    Collected c;
    for (core::TimeNs t = 0; t < 200 * kMs; t += 10 * kMs) feed(d, e.poll(t), c);
    EXPECT_TRUE(c.samples.empty());
    EXPECT_EQ(e.stats().data_messages, 20U);
    EXPECT_EQ(d.stats().codec.checksum_errors, 20U);
  }
}

TEST(MyahrsEmulator, GarbageAndCorruptionAreSurvived) {
  EmulatorConfig cfg;
  cfg.faults.garbage_probability = 0.5;
  cfg.faults.corrupt_checksum_probability = 0.2;
  cfg.faults.seed = 42;
  for (const bool binary : {false, true}) {
    cfg.binary = binary;
    Emulator e(cfg);
    e.set_truth(truth());
    Decoder d;
    Collected c;
    for (core::TimeNs t = 0; t < 5000 * kMs; t += 10 * kMs) feed(d, e.poll(t), c);
    const auto& st = e.stats();
    EXPECT_EQ(st.data_messages, 500U);
    EXPECT_GT(st.garbage_bursts, 150U);
    EXPECT_GT(st.corrupted_messages, 50U);
    // Garbage can swallow the next message (e.g. a random DLE STX), never invent one.
    EXPECT_LE(c.samples.size(), st.data_messages - st.corrupted_messages);
    EXPECT_GE(c.samples.size(), st.data_messages - st.corrupted_messages - st.garbage_bursts);
    EXPECT_GT(c.samples.size(), 300U);
    for (const auto& s : c.samples) EXPECT_NEAR(s.yaw_magnetic_deg, 97.31, 0.02);
  }
}

TEST(MyahrsEmulator, SilentSendsNothing) {
  EmulatorConfig cfg;
  cfg.faults.silent = true;
  Emulator e(cfg);
  send(e, drivers::myahrs::version_command());
  for (core::TimeNs t = 0; t < 100 * kMs; t += 10 * kMs) EXPECT_TRUE(e.poll(t).empty());
  EXPECT_EQ(e.stats().requests_ok, 1U);
}

TEST(MyahrsEmulator, LargeTimeJumpIsBounded) {
  Emulator e;
  e.set_truth(truth());
  Decoder d;
  Collected c;
  feed(d, e.poll(0), c);
  feed(d, e.poll(10'000 * kMs), c);  // 10 s later
  EXPECT_EQ(c.samples.size(), 1U + Emulator::kMaxCatchUpTicks);
  EXPECT_EQ(e.stats().skipped_ticks, 1000U - Emulator::kMaxCatchUpTicks);
  feed(d, e.poll(10'010 * kMs), c);
  EXPECT_EQ(c.samples.size(), 2U + Emulator::kMaxCatchUpTicks);
}

TEST(MyahrsEmulator, ConfigValidation) {
  EXPECT_FALSE(EmulatorConfig{}.validate().has_value());
  EmulatorConfig cfg;
  cfg.divider = 0;
  EXPECT_TRUE(cfg.validate().has_value());
  cfg.divider = 1;
  cfg.faults.garbage_probability = 1.5;
  EXPECT_TRUE(cfg.validate().has_value());
}

}  // namespace
}  // namespace coxswain::sim::devices::myahrs
