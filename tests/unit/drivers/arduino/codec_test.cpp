// SPDX-License-Identifier: Apache-2.0
// Daemon-side codec: message filtering and counters, ActuatorCommand -> SetOutputs frames,
// Telemetry -> ArduinoStatus.
#include "coxswain/drivers/arduino/codec.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace coxswain::drivers::arduino {
namespace {

using Bytes = std::vector<std::uint8_t>;

template <typename M>
Bytes frame_of(const M& m, std::uint16_t seq) {
  Bytes out(kMaxFrame);
  out.resize(encode(m, seq, out.data(), out.size()));
  return out;
}

std::vector<BoardMessage> run(ArduinoCodec& codec, const Bytes& bytes) {
  std::vector<BoardMessage> out;
  std::span<const std::uint8_t> rest(bytes);
  while (!rest.empty()) {
    const DecodeStep step = codec.decode(rest);
    EXPECT_GE(step.consumed, 1U);
    rest = rest.subspan(step.consumed);
    if (step.produced) out.push_back(codec.message());
  }
  for (DecodeStep step = codec.decode({}); step.produced; step = codec.decode({})) {
    out.push_back(codec.message());
  }
  return out;
}

TEST(ArduinoCodec, DeliversBoardMessagesAndCountsOthers) {
  Telemetry tel{};
  tel.applied_pulse_us[0] = 1700;
  tel.flags = kTelRcPresent;
  Ready ready{};
  ready.protocol_version = kProtocolVersion;
  ready.failsafe_ms = 300;
  Bytes s = frame_of(ready, 0);
  const Bytes host = frame_of(Ping{5}, 3);  // host -> board type: unsupported here
  s.insert(s.end(), host.begin(), host.end());
  std::uint8_t junk[3] = {1, 2, 3};
  std::uint8_t buf[kMaxFrame];
  const std::size_t n = encode_frame(MsgType::kTelemetry, 9, junk, 3, buf, sizeof(buf));
  s.insert(s.end(), buf, buf + n);  // telemetry with a wrong length: malformed
  const Bytes t = frame_of(tel, 1);
  s.insert(s.end(), t.begin(), t.end());
  const Bytes p = frame_of(Pong{77, 1000}, 2);
  s.insert(s.end(), p.begin(), p.end());

  ArduinoCodec codec;
  const auto got = run(codec, s);
  ASSERT_EQ(got.size(), 3U);
  EXPECT_EQ(got[0].type, MsgType::kReady);
  EXPECT_EQ(got[0].ready.failsafe_ms, 300);
  EXPECT_EQ(got[1].type, MsgType::kTelemetry);
  EXPECT_EQ(got[1].seq, 1);
  EXPECT_EQ(got[1].telemetry.applied_pulse_us[0], 1700);
  EXPECT_EQ(got[2].type, MsgType::kPong);
  EXPECT_EQ(got[2].pong.token, 77U);
  const CodecStats st = codec.stats();
  EXPECT_EQ(st.bytes_in, s.size());
  EXPECT_EQ(st.frames_ok, 5U);
  EXPECT_EQ(st.messages_out, 3U);
  EXPECT_EQ(st.unsupported, 1U);
  EXPECT_EQ(st.framing_errors, 1U);
  EXPECT_EQ(st.checksum_errors, 0U);
}

TEST(ArduinoCodec, CommandEncoderFramesAndSequence) {
  CommandEncoder enc(65534);
  msg::ActuatorCommand cmd;
  cmd.pulse_us = {1600, 1400};
  cmd.led = msg::LedColour::kGreen;
  cmd.active = true;
  // Same bytes as the golden SetOutputs frame of wire_test.cpp but at seq 65534.
  const auto f1 = enc.encode(cmd);
  FrameDecoder d;
  std::vector<std::uint16_t> seqs;
  SetOutputs so{};
  for (int i = 0; i < 3; ++i) {
    const auto f = i == 0 ? f1 : enc.encode(cmd);
    bool produced = false;
    ASSERT_EQ(d.decode(f.data(), f.size(), &produced), f.size());
    ASSERT_TRUE(produced);
    ASSERT_TRUE(parse(d.frame(), &so));
    seqs.push_back(d.frame().seq);
  }
  EXPECT_EQ(seqs, (std::vector<std::uint16_t>{65534, 65535, 0}));
  EXPECT_EQ(so.pulse_us[0], 1600);
  EXPECT_EQ(so.pulse_us[1], 1400);
  EXPECT_EQ(so.led, 2);
  EXPECT_EQ(so.flags, kFlagArm);
  EXPECT_EQ(enc.next_seq(), 1);
  // Hello and Ping do not advance the SetOutputs sequence.
  const auto h = enc.encode_hello();
  EXPECT_EQ(h.size(), 9U);
  EXPECT_EQ(h[3], static_cast<std::uint8_t>(MsgType::kHello));
  EXPECT_EQ(enc.encode_ping(1).size(), 12U);
  EXPECT_EQ(enc.next_seq(), 1);
}

TEST(ArduinoCodec, InactiveCommandIsDisarmed) {
  msg::ActuatorCommand cmd;
  cmd.active = false;
  cmd.led = msg::LedColour::kWhite;
  const SetOutputs so = to_set_outputs(cmd);
  EXPECT_EQ(so.flags, 0);
  EXPECT_EQ(so.led, 6);
  EXPECT_EQ(so.pulse_us[0], 1500);
}

TEST(ArduinoCodec, TelemetryToStatus) {
  Telemetry t{};
  t.applied_pulse_us[0] = 1234;
  t.applied_pulse_us[1] = 1777;
  t.led = 5;
  t.mode = 1;
  t.flags = kTelEstop | kTelStartSwitch;
  t.supply_mv = 12345;
  t.last_seq = 999;
  msg::ArduinoStatus s = to_status(t, 42);
  EXPECT_EQ(s.stamp_ns, 42);
  EXPECT_EQ(s.applied_pulse_us[0], 1234);
  EXPECT_EQ(s.applied_pulse_us[1], 1777);
  EXPECT_EQ(s.led, msg::LedColour::kPurple);
  EXPECT_EQ(s.mode, msg::ControlMode::kAutonomous);
  EXPECT_TRUE(s.estop);
  EXPECT_FALSE(s.rc_present);
  EXPECT_FALSE(s.failsafe);
  EXPECT_TRUE(s.start_switch);
  EXPECT_DOUBLE_EQ(s.supply_v, 12.345);
  EXPECT_EQ(s.last_sequence_seen, 999);

  t.led = 200;
  t.mode = 7;
  t.flags = kTelRcPresent | kTelFailsafe;
  s = to_status(t, 1);
  EXPECT_EQ(s.led, msg::LedColour::kOff);
  EXPECT_EQ(s.mode, msg::ControlMode::kManual);
  EXPECT_FALSE(s.estop);
  EXPECT_TRUE(s.rc_present);
  EXPECT_TRUE(s.failsafe);
}

}  // namespace
}  // namespace coxswain::drivers::arduino
