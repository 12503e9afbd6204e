// SPDX-License-Identifier: Apache-2.0
// Wire protocol (tools/arduino/PROTOCOL.md): CRC check value, golden frames whose bytes were
// computed independently (Python binascii.crc_hqx with init 0xFFFF = CRC-16/CCITT-FALSE), round
// trips of every message, split-at-every-byte decoding, garbage/CRC/length errors, resync.
#include "coxswain/drivers/arduino/wire.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <vector>

namespace coxswain::drivers::arduino {
namespace {

using Bytes = std::vector<std::uint8_t>;

// SetOutputs seq 0x1234: 1600 us, 1400 us, LED green (2), armed.
const Bytes kGoldenSetOutputs = {0xA5, 0x5A, 0x06, 0x10, 0x34, 0x12, 0x40,
                                 0x06, 0x78, 0x05, 0x02, 0x01, 0xC1, 0x22};
// Ping seq 0xFFFF, token 0xDEADBEEF.
const Bytes kGoldenPing = {0xA5, 0x5A, 0x04, 0x02, 0xFF, 0xFF, 0xEF, 0xBE, 0xAD, 0xDE, 0xCB, 0xA4};
// Hello seq 0, protocol version 1.
const Bytes kGoldenHello = {0xA5, 0x5A, 0x01, 0x01, 0x00, 0x00, 0x01, 0xC8, 0xDD};
// Ready seq 0: protocol 1, firmware 1.0.0, failsafe 300 ms, neutral 1500/1500, reset cause 1,
// 3 RC channels.
const Bytes kGoldenReady = {0xA5, 0x5A, 0x0C, 0x81, 0x00, 0x00, 0x01, 0x01, 0x00, 0x00,
                            0x2C, 0x01, 0xDC, 0x05, 0xDC, 0x05, 0x01, 0x03, 0xA2, 0x8B};
// Telemetry seq 7 (values in make_golden_telemetry()).
const Bytes kGoldenTelemetry = {0xA5, 0x5A, 0x24, 0x83, 0x07, 0x00, 0x40, 0xE2, 0x01, 0x00, 0x72,
                                0x06, 0xDC, 0x05, 0xE6, 0x05, 0xD2, 0x05, 0x6C, 0x07, 0x03, 0x01,
                                0x12, 0x04, 0x38, 0x31, 0x34, 0x12, 0x64, 0x00, 0x02, 0x00, 0x01,
                                0x00, 0x05, 0x00, 0x03, 0x00, 0x01, 0x00, 0x07, 0x00, 0xC5, 0xA1};

Telemetry make_golden_telemetry() {
  Telemetry t{};
  t.uptime_ms = 123456;
  t.applied_pulse_us[0] = 1650;
  t.applied_pulse_us[1] = 1500;
  t.rc_pulse_us[0] = 1510;
  t.rc_pulse_us[1] = 1490;
  t.rc_pulse_us[2] = 1900;
  t.led = 3;
  t.mode = 1;
  t.flags = kTelRcPresent | kTelArmed;
  t.source = 4;
  t.supply_mv = 12600;
  t.last_seq = 0x1234;
  t.rx_frames_ok = 100;
  t.rx_crc_errors = 2;
  t.rx_framing_errors = 1;
  t.rx_bytes_skipped = 5;
  t.seq_gaps = 3;
  t.seq_duplicates = 1;
  t.failsafe_events = 7;
  return t;
}

template <typename M>
Bytes encode_bytes(const M& m, std::uint16_t seq) {
  Bytes out(kMaxFrame);
  const std::size_t n = encode(m, seq, out.data(), out.size());
  out.resize(n);
  return out;
}

struct Decoded {
  std::uint8_t type;
  std::uint16_t seq;
  Bytes payload;
  bool operator==(const Decoded&) const = default;
};

// Feeds `chunks` in order with the codec-convention loop, then drains.
std::vector<Decoded> decode_all(FrameDecoder& d, const std::vector<Bytes>& chunks) {
  std::vector<Decoded> out;
  auto take = [&] {
    const Frame& f = d.frame();
    out.push_back({f.type, f.seq, Bytes(f.payload, f.payload + f.len)});
  };
  for (const Bytes& c : chunks) {
    std::size_t pos = 0;
    while (pos < c.size()) {
      bool produced = false;
      const std::size_t used = d.decode(c.data() + pos, c.size() - pos, &produced);
      EXPECT_GE(used, 1U);
      pos += used;
      if (produced) take();
    }
  }
  bool produced = true;
  while (produced) {
    (void)d.decode(nullptr, 0, &produced);
    if (produced) take();
  }
  return out;
}

TEST(ArduinoWire, Crc16CheckValue) {
  const char* check = "123456789";
  EXPECT_EQ(crc16_ccitt_false(reinterpret_cast<const std::uint8_t*>(check), 9), 0x29B1);
  EXPECT_EQ(crc16_ccitt_false(nullptr, 0), 0xFFFF);
  const std::uint8_t a = 'A';
  EXPECT_EQ(crc16_ccitt_false(&a, 1), 0xB915);  // CRC-16/CCITT-FALSE("A")
}

TEST(ArduinoWire, GoldenEncodings) {
  SetOutputs so{};
  so.pulse_us[0] = 1600;
  so.pulse_us[1] = 1400;
  so.led = 2;
  so.flags = kFlagArm;
  EXPECT_EQ(encode_bytes(so, 0x1234), kGoldenSetOutputs);
  EXPECT_EQ(encode_bytes(Ping{0xDEADBEEFU}, 0xFFFF), kGoldenPing);
  EXPECT_EQ(encode_bytes(Hello{1}, 0), kGoldenHello);
  Ready r{};
  r.protocol_version = 1;
  r.fw_major = 1;
  r.failsafe_ms = 300;
  r.neutral_us[0] = 1500;
  r.neutral_us[1] = 1500;
  r.reset_cause = 1;
  r.rc_channels = 3;
  EXPECT_EQ(encode_bytes(r, 0), kGoldenReady);
  EXPECT_EQ(encode_bytes(make_golden_telemetry(), 7), kGoldenTelemetry);
}

TEST(ArduinoWire, GoldenDecodings) {
  FrameDecoder d;
  const auto got = decode_all(d, {kGoldenSetOutputs, kGoldenTelemetry});
  ASSERT_EQ(got.size(), 2U);
  Frame f{got[0].type, got[0].seq, static_cast<std::uint8_t>(got[0].payload.size()),
          got[0].payload.data()};
  SetOutputs so{};
  ASSERT_TRUE(parse(f, &so));
  EXPECT_EQ(f.seq, 0x1234);
  EXPECT_EQ(so.pulse_us[0], 1600);
  EXPECT_EQ(so.pulse_us[1], 1400);
  EXPECT_EQ(so.led, 2);
  EXPECT_EQ(so.flags, kFlagArm);
  Telemetry wrong{};
  EXPECT_FALSE(parse(f, &wrong));  // type mismatch
  f = Frame{got[1].type, got[1].seq, static_cast<std::uint8_t>(got[1].payload.size()),
            got[1].payload.data()};
  Telemetry t{};
  ASSERT_TRUE(parse(f, &t));
  const Telemetry expected = make_golden_telemetry();
  EXPECT_EQ(std::memcmp(&t, &expected, sizeof(t)), 0);
  EXPECT_EQ(d.stats().frames_ok, 2U);
  EXPECT_EQ(d.stats().bytes_in, kGoldenSetOutputs.size() + kGoldenTelemetry.size());
  EXPECT_EQ(d.stats().bytes_skipped, 0U);
}

template <typename M>
M round_trip(const M& in, std::uint16_t seq) {
  FrameDecoder d;
  const auto got = decode_all(d, {encode_bytes(in, seq)});
  EXPECT_EQ(got.size(), 1U);
  M out{};
  if (got.size() == 1) {
    EXPECT_EQ(got[0].seq, seq);
    const Frame f{got[0].type, got[0].seq, static_cast<std::uint8_t>(got[0].payload.size()),
                  got[0].payload.data()};
    EXPECT_TRUE(parse(f, &out));
  }
  return out;
}

TEST(ArduinoWire, RoundTripEveryMessage) {
  EXPECT_EQ(round_trip(Hello{9}, 3).protocol_version, 9);
  EXPECT_EQ(round_trip(Ping{0x01020304U}, 65535).token, 0x01020304U);
  SetOutputs so{{1000, 2000}, 6, 0xFF};
  const SetOutputs so2 = round_trip(so, 1);
  EXPECT_EQ(std::memcmp(&so, &so2, sizeof(so)), 0);
  Ready r{1, 2, 3, 4, 500, {1490, 1510}, 0x08, 3};
  const Ready r2 = round_trip(r, 0);
  EXPECT_EQ(std::memcmp(&r, &r2, sizeof(r)), 0);
  Pong p{0xCAFEF00DU, 0xFFFFFFFFU};
  const Pong p2 = round_trip(p, 42);
  EXPECT_EQ(p2.token, p.token);
  EXPECT_EQ(p2.uptime_ms, p.uptime_ms);
  Telemetry t = make_golden_telemetry();
  t.uptime_ms = 0xFFFFFFFFU;
  t.rx_crc_errors = 0xFFFF;
  const Telemetry t2 = round_trip(t, 9);
  EXPECT_EQ(std::memcmp(&t, &t2, sizeof(t)), 0);
}

TEST(ArduinoWire, EncodeRejectsSmallBuffer) {
  std::uint8_t buf[kMaxFrame];
  EXPECT_EQ(encode(Hello{1}, 0, buf, 8), 0U);  // needs 9
  EXPECT_EQ(encode(Hello{1}, 0, buf, 9), 9U);
  std::uint8_t big[kMaxPayload + 1] = {};
  EXPECT_EQ(encode_frame(MsgType::kPing, 0, big, kMaxPayload + 1, buf, sizeof(buf)), 0U);
  EXPECT_EQ(encode_frame(MsgType::kPing, 0, big, kMaxPayload, buf, sizeof(buf)),
            static_cast<std::size_t>(kMaxFrame));
}

Bytes stream_of_all() {
  Bytes s;
  for (const Bytes* b :
       {&kGoldenHello, &kGoldenSetOutputs, &kGoldenPing, &kGoldenReady, &kGoldenTelemetry}) {
    s.insert(s.end(), b->begin(), b->end());
  }
  return s;
}

TEST(ArduinoWire, SplitAtEveryByte) {
  const Bytes s = stream_of_all();
  FrameDecoder whole_d;
  const auto expected = decode_all(whole_d, {s});
  ASSERT_EQ(expected.size(), 5U);
  for (std::size_t cut = 0; cut <= s.size(); ++cut) {
    FrameDecoder d;
    const auto got = decode_all(d, {Bytes(s.begin(), s.begin() + static_cast<long>(cut)),
                                    Bytes(s.begin() + static_cast<long>(cut), s.end())});
    EXPECT_EQ(got, expected) << "cut at " << cut;
  }
  std::vector<Bytes> singles;
  for (std::uint8_t b : s) singles.push_back({b});
  FrameDecoder d;
  EXPECT_EQ(decode_all(d, singles), expected);
  EXPECT_EQ(d.stats().bytes_skipped, 0U);
}

TEST(ArduinoWire, GarbageIsSkippedAndCounted) {
  Bytes s = {0x00, 0xFF, 0xA5, 0x00, 0x5A, 0x13};  // 6 garbage bytes, incl. a lone sync0
  s.insert(s.end(), kGoldenSetOutputs.begin(), kGoldenSetOutputs.end());
  s.insert(s.end(), {0xA5, 0xA5});  // sync0 twice: the first is garbage
  s.insert(s.end(), kGoldenSetOutputs.begin() + 1, kGoldenSetOutputs.end());
  FrameDecoder d;
  const auto got = decode_all(d, {s});
  ASSERT_EQ(got.size(), 2U);
  EXPECT_EQ(d.stats().bytes_skipped, 7U);
  EXPECT_EQ(d.stats().crc_errors, 0U);
  EXPECT_EQ(d.stats().frames_ok, 2U);
}

TEST(ArduinoWire, CrcErrorIsCountedAndNextFrameSurvives) {
  for (std::size_t flip = 2; flip < kGoldenSetOutputs.size(); ++flip) {
    Bytes bad = kGoldenSetOutputs;
    bad[flip] ^= 0x01;
    Bytes s = bad;
    s.insert(s.end(), kGoldenPing.begin(), kGoldenPing.end());
    FrameDecoder d;
    const auto got = decode_all(d, {s});
    ASSERT_EQ(got.size(), 1U) << "flip " << flip;
    EXPECT_EQ(got[0].type, static_cast<std::uint8_t>(MsgType::kPing));
    // Flipping the length byte may make the frame longer (CRC fails later) or shorter.
    EXPECT_EQ(d.stats().crc_errors, 1U) << "flip " << flip;
    EXPECT_EQ(d.stats().bytes_skipped, bad.size()) << "flip " << flip;
  }
}

TEST(ArduinoWire, FrameHiddenInFalseHeaderIsRecovered) {
  // A false header announcing 40 bytes swallows a real frame; the CRC fails and the decoder
  // rescans from the byte after the false sync, finding the real frame.
  Bytes s = {0xA5, 0x5A, 40, 0x83, 0x00, 0x00};
  s.insert(s.end(), kGoldenPing.begin(), kGoldenPing.end());
  s.resize(s.size() + 40, 0x11);  // enough bytes to complete the false frame
  s.insert(s.end(), kGoldenHello.begin(), kGoldenHello.end());
  FrameDecoder d;
  const auto got = decode_all(d, {s});
  ASSERT_EQ(got.size(), 2U);
  EXPECT_EQ(got[0].type, static_cast<std::uint8_t>(MsgType::kPing));
  EXPECT_EQ(got[1].type, static_cast<std::uint8_t>(MsgType::kHello));
  EXPECT_EQ(d.stats().crc_errors, 1U);
}

TEST(ArduinoWire, FrameHeldAfterResyncIsDeliveredByDrain) {
  // Two real frames inside one false frame: both must come out, the second via the drain call.
  Bytes s = {0xA5, 0x5A, 30, 0x83, 0x00, 0x00};
  s.insert(s.end(), kGoldenPing.begin(), kGoldenPing.end());
  s.insert(s.end(), kGoldenHello.begin(), kGoldenHello.end());
  s.resize(6 + 30 + 2, 0x22);
  FrameDecoder d;
  const auto got = decode_all(d, {s});
  ASSERT_EQ(got.size(), 2U);
  EXPECT_EQ(got[1].type, static_cast<std::uint8_t>(MsgType::kHello));
}

TEST(ArduinoWire, ImpossibleLengthIsAFramingError) {
  Bytes s = {0xA5, 0x5A, static_cast<std::uint8_t>(kMaxPayload + 1)};
  s.insert(s.end(), kGoldenHello.begin(), kGoldenHello.end());
  FrameDecoder d;
  const auto got = decode_all(d, {s});
  ASSERT_EQ(got.size(), 1U);
  EXPECT_EQ(d.stats().framing_errors, 1U);
  EXPECT_EQ(d.stats().bytes_skipped, 3U);
}

TEST(ArduinoWire, WrongPayloadLengthIsNotParsed) {
  std::uint8_t payload[7] = {};
  std::uint8_t buf[kMaxFrame];
  const std::size_t n = encode_frame(MsgType::kSetOutputs, 1, payload, 7, buf, sizeof(buf));
  FrameDecoder d;
  const auto got = decode_all(d, {Bytes(buf, buf + n)});
  ASSERT_EQ(got.size(), 1U);
  const Frame f{got[0].type, got[0].seq, 7, got[0].payload.data()};
  SetOutputs so{};
  EXPECT_FALSE(parse(f, &so));
}

TEST(ArduinoWire, SequenceWrapsInFrames) {
  FrameDecoder d;
  const auto got = decode_all(d, {encode_bytes(Hello{1}, 65535), encode_bytes(Hello{1}, 0)});
  ASSERT_EQ(got.size(), 2U);
  EXPECT_EQ(got[0].seq, 65535);
  EXPECT_EQ(got[1].seq, 0);
}

}  // namespace
}  // namespace coxswain::drivers::arduino
