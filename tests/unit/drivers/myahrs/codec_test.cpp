// SPDX-License-Identifier: Apache-2.0
// myAHRS+ decoder tests. Vectors: the sample lines quoted in docs/protocols.md 2.2-2.4 and the
// vendor SDK comments (checksums re-verified by hand), plus hand-built binary frames (no binary
// capture exists, docs/protocols.md 2.7).
#include "coxswain/drivers/myahrs/codec.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace coxswain::drivers::myahrs {
namespace {

using Bytes = std::vector<std::uint8_t>;

Bytes to_bytes(std::string_view s) { return Bytes(s.begin(), s.end()); }

// "$BODY" -> "$BODY*CC\r\n" with the correct checksum.
std::string with_checksum(std::string_view body) {
  std::uint8_t cs = 0;
  for (const char c : body) cs = static_cast<std::uint8_t>(cs ^ static_cast<std::uint8_t>(c));
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out(body);
  out += '*';
  out += kHex[cs >> 4];
  out += kHex[cs & 0x0F];
  out += "\r\n";
  return out;
}

// Wraps an unstuffed body into DLE STX body checksum DLE ETX with stuffing.
Bytes binary_frame(const Bytes& body) {
  std::uint8_t cs = 0;
  for (const std::uint8_t b : body) cs = static_cast<std::uint8_t>(cs ^ b);
  Bytes out{kDle, kStx};
  Bytes all = body;
  all.push_back(cs);
  for (const std::uint8_t b : all) {
    out.push_back(b);
    if (b == kDle) out.push_back(kDle);
  }
  out.push_back(kDle);
  out.push_back(kEtx);
  return out;
}

void append_i16(Bytes& out, std::int16_t v) {
  const auto u = static_cast<std::uint16_t>(v);
  out.push_back(static_cast<std::uint8_t>(u & 0xFF));
  out.push_back(static_cast<std::uint8_t>(u >> 8));
}

void append_node_i16_list(Bytes& out, char name, const std::vector<std::int16_t>& values,
                          bool more) {
  out.push_back(static_cast<std::uint8_t>(0x23 | (more ? kTagNextNode : 0)));
  out.push_back(static_cast<std::uint8_t>(name));
  out.push_back(0);
  out.push_back(static_cast<std::uint8_t>(values.size()));
  out.push_back(0);
  for (const std::int16_t v : values) append_i16(out, v);
}

// What one produced message looked like, for equivalence comparisons.
struct Record {
  Output kind = Output::kNone;
  unsigned sequence = 0;
  double roll = 0, pitch = 0, yaw = 0, heading = 0;
  std::array<double, 3> accel{}, gyro{}, mag{};
  double temperature = 0;
  bool has_inertial = false, has_attitude = false, has_raw = false;
  std::string command;
  bool ok = false;
  std::vector<std::pair<std::string, std::string>> attributes;

  bool operator==(const Record&) const = default;
};

Record record_of(const Decoder& d) {
  Record r;
  r.kind = d.last_output();
  if (r.kind == Output::kSample) {
    const auto& s = d.sample();
    r.sequence = s.sequence;
    r.roll = s.roll_deg;
    r.pitch = s.pitch_deg;
    r.yaw = s.yaw_magnetic_deg;
    r.heading = s.heading_deg;
    r.accel = s.accel_g;
    r.gyro = s.gyro_dps;
    r.mag = s.mag_ut;
    r.temperature = s.temperature_c;
    r.has_inertial = s.has_inertial;
    r.has_attitude = d.sample_detail().has_attitude;
    r.has_raw = d.sample_detail().has_raw;
  } else if (r.kind == Output::kResponse) {
    r.command = std::string(d.response().command);
    r.ok = d.response().ok;
    for (const auto& a : d.response().attributes) {
      r.attributes.emplace_back(std::string(a.name), std::string(a.value));
    }
  }
  return r;
}

// Feeds `bytes` in chunks of `chunk` bytes (0 = all at once); returns every produced message.
std::vector<Record> decode_all(Decoder& d, std::span<const std::uint8_t> bytes,
                               std::size_t chunk = 0) {
  std::vector<Record> out;
  std::size_t pos = 0;
  while (pos < bytes.size()) {
    const std::size_t n = chunk == 0 ? bytes.size() - pos : std::min(chunk, bytes.size() - pos);
    std::span<const std::uint8_t> rest = bytes.subspan(pos, n);
    while (!rest.empty()) {
      const DecodeStep step = d.decode(rest);
      EXPECT_GE(step.consumed, 1U);
      rest = rest.subspan(step.consumed);
      if (step.produced) out.push_back(record_of(d));
    }
    pos += n;
  }
  return out;
}

std::vector<Record> decode_all(std::string_view text, Decoder* keep = nullptr) {
  Decoder local;
  Decoder& d = keep != nullptr ? *keep : local;
  const Bytes b = to_bytes(text);
  return decode_all(d, b);
}

// ---------------------------------------------------------------------------------------------
// Checksum and the documented lines.

TEST(MyahrsChecksum, DocumentedExamplesVerify) {
  EXPECT_EQ(xor_checksum(std::string_view("@version")), 0x3A);
  EXPECT_EQ(xor_checksum(std::string_view(
                "$RPYIMU,15,-1.55,-1.25,97.31,-0.0142,-0.0010,-0.9224,-0.9756,-0.3659,-0.8537,"
                "-8.4000,-46.8000,5.4000,38.3")),
            0x36);
}

TEST(MyahrsDecoder, RpyImuSampleFromProtocolsDoc) {
  Decoder d;
  const auto out = decode_all(
      "$RPYIMU,15,-1.55,-1.25,97.31,-0.0142,-0.0010,-0.9224,-0.9756,-0.3659,-0.8537,-8.4000,"
      "-46.8000,5.4000,38.3*36\r\n",
      &d);
  ASSERT_EQ(out.size(), 1U);
  const auto& s = d.sample();
  EXPECT_EQ(s.sequence, 15U);
  EXPECT_DOUBLE_EQ(s.roll_deg, -1.55);
  EXPECT_DOUBLE_EQ(s.pitch_deg, -1.25);
  EXPECT_DOUBLE_EQ(s.yaw_magnetic_deg, 97.31);
  EXPECT_DOUBLE_EQ(s.heading_deg, 97.31);  // default config: no mount yaw, no declination
  EXPECT_DOUBLE_EQ(s.accel_g[0], -0.0142);
  EXPECT_DOUBLE_EQ(s.accel_g[2], -0.9224);  // z down: about -1 g at rest
  EXPECT_DOUBLE_EQ(s.gyro_dps[1], -0.3659);
  EXPECT_DOUBLE_EQ(s.mag_ut[1], -46.8);
  EXPECT_DOUBLE_EQ(s.temperature_c, 38.3);
  EXPECT_TRUE(s.has_inertial);
  EXPECT_EQ(s.stamp_ns, core::kNeverNs);  // the adapter stamps
  EXPECT_TRUE(d.sample_detail().has_attitude);
  EXPECT_FALSE(d.sample_detail().from_quaternion);
  EXPECT_EQ(d.sample_detail().encoding, Encoding::kAscii);
  EXPECT_EQ(d.stats().codec.frames_ok, 1U);
  EXPECT_EQ(d.stats().codec.messages_out, 1U);
  EXPECT_EQ(d.stats().codec.framing_errors, 0U);
}

TEST(MyahrsDecoder, RpySample) {
  Decoder d;
  ASSERT_EQ(decode_all("$RPY,04,-1.55,-1.25,96.94*50\r\n", &d).size(), 1U);
  EXPECT_EQ(d.sample().sequence, 4U);
  EXPECT_DOUBLE_EQ(d.sample().yaw_magnetic_deg, 96.94);
  EXPECT_FALSE(d.sample().has_inertial);
  EXPECT_TRUE(d.sample_detail().has_attitude);
}

TEST(MyahrsDecoder, QuatSampleConvertedToEuler) {
  Decoder d;
  ASSERT_EQ(decode_all("$QUAT,68,0.0006,0.0174,-0.7489,-0.6625*16\r\n", &d).size(), 1U);
  const auto& det = d.sample_detail();
  EXPECT_TRUE(det.has_quaternion);
  EXPECT_TRUE(det.from_quaternion);
  EXPECT_DOUBLE_EQ(det.quaternion_xyzw[3], -0.6625);  // w is LAST
  // Independent check through the rotation matrix: yaw = atan2(R10, R00).
  const double x = 0.0006, y = 0.0174, z = -0.7489, w = -0.6625;
  const double n2 = x * x + y * y + z * z + w * w;
  const double r00 = 1.0 - 2.0 * (y * y + z * z) / n2;
  const double r10 = 2.0 * (x * y + w * z) / n2;
  EXPECT_NEAR(d.sample().yaw_magnetic_deg, std::atan2(r10, r00) * 180.0 / std::numbers::pi, 1e-9);
  EXPECT_NEAR(d.sample().yaw_magnetic_deg, 97.3, 0.5);  // same pose as the RPY samples
  EXPECT_NEAR(d.sample().roll_deg, -1.5, 0.5);
}

TEST(MyahrsDecoder, QuatImuSample) {
  Decoder d;
  ASSERT_EQ(decode_all("$QUATIMU,53,0.0424,-0.1791,0.2366,0.9540,-0.3636,0.0027,-0.9260,0.0156,"
                       "0.1537,0.2896,212.2648,-72.7573,168.2144,36.8*7F\r\n",
                       &d)
                .size(),
            1U);
  EXPECT_EQ(d.sample().sequence, 53U);
  EXPECT_TRUE(d.sample().has_inertial);
  EXPECT_DOUBLE_EQ(d.sample().mag_ut[0], 212.2648);
  EXPECT_DOUBLE_EQ(d.sample().temperature_c, 36.8);
  EXPECT_TRUE(d.sample_detail().from_quaternion);
}

TEST(MyahrsDecoder, ImuAndRawImuSamples) {
  Decoder d;
  const std::string text =
      "$IMU,74,-0.0054,-0.0015,-0.9204,-0.7317,-0.4878,-0.7317,-7.2000,-45.6000,6.6000,38.2*68\r\n"
      "$RIIMU,59,-16,-8,-1897,-14,-7,-12,-26,-156,18,1101*79\r\n";
  const Bytes b = to_bytes(text);
  std::span<const std::uint8_t> rest(b);
  DecodeStep step = d.decode(rest);
  ASSERT_TRUE(step.produced);
  EXPECT_EQ(d.sample().sequence, 74U);
  EXPECT_TRUE(d.sample().has_inertial);
  EXPECT_FALSE(d.sample_detail().has_attitude);
  EXPECT_DOUBLE_EQ(d.sample().accel_g[2], -0.9204);
  rest = rest.subspan(step.consumed);
  step = d.decode(rest);
  ASSERT_TRUE(step.produced);
  EXPECT_EQ(step.consumed, rest.size());
  EXPECT_EQ(d.sample().sequence, 59U);
  EXPECT_FALSE(d.sample().has_inertial);  // raw counts are not calibrated values
  EXPECT_TRUE(d.sample_detail().has_raw);
  EXPECT_EQ(d.sample_detail().raw_imu[2], -1897);
  EXPECT_EQ(d.sample_detail().raw_imu[9], 1101);
}

TEST(MyahrsDecoder, ResponseWithSpacedValues) {
  Decoder d;
  const auto out = decode_all(
      "~set_offset,OK,yaw_offset=OFF,q_s2v=0.000000e+00 0.000000e+00 0.000000e+00 1.000000e+00,"
      "q_g2u=0.000000e+00 0.000000e+00 0.000000e+00 1.000000e+00*12\r\n",
      &d);
  ASSERT_EQ(out.size(), 1U);
  EXPECT_EQ(d.last_output(), Output::kResponse);
  EXPECT_EQ(d.response().command, "set_offset");
  EXPECT_TRUE(d.response().ok);
  ASSERT_EQ(d.response().attributes.size(), 3U);
  EXPECT_EQ(d.response().attribute("yaw_offset"), "OFF");
  EXPECT_EQ(d.response().attribute("q_g2u"), "0.000000e+00 0.000000e+00 0.000000e+00 1.000000e+00");
  EXPECT_FALSE(d.response().attribute("missing").has_value());
}

TEST(MyahrsDecoder, ResponseAttributesWithSpacesInNamesAndListValues) {
  Decoder d;
  ASSERT_EQ(decode_all(with_checksum("~divider,OK,divider=1,max rate=100"), &d).size(), 1U);
  EXPECT_EQ(d.response().attribute("max rate"), "100");
  EXPECT_EQ(d.response().attribute("divider"), "1");
  ASSERT_EQ(decode_all(with_checksum("~bin_out,OK,fmt=EULER, IMU"), &d).size(), 1U);
  EXPECT_EQ(d.response().attribute("fmt"), "EULER, IMU");
  ASSERT_EQ(decode_all(with_checksum("~version,OK,product=myAHRS+,platform=myAHRS+m3,sn=123,"
                                     "ver=1.6,build=Jul 12 2014"),
                       &d)
                .size(),
            1U);
  EXPECT_EQ(d.response().attribute("product"), "myAHRS+");
  EXPECT_EQ(d.response().attribute("ver"), "1.6");
}

TEST(MyahrsDecoder, ErrorResponseIsProducedAndCounted) {
  Decoder d;
  ASSERT_EQ(decode_all(with_checksum("~trig,ERROR"), &d).size(), 1U);
  EXPECT_EQ(d.response().command, "trig");
  EXPECT_FALSE(d.response().ok);
  EXPECT_EQ(d.stats().error_responses, 1U);
}

TEST(MyahrsDecoder, RequestsAreCheckedButNotProduced) {
  Decoder d;
  EXPECT_TRUE(decode_all("@version*3A\r\n", &d).empty());
  EXPECT_EQ(d.stats().requests_seen, 1U);
  EXPECT_EQ(d.stats().codec.frames_ok, 1U);
  EXPECT_EQ(d.stats().codec.unsupported, 1U);
  EXPECT_TRUE(decode_all("@version*3B\r\n", &d).empty());
  EXPECT_EQ(d.stats().ascii_checksum_errors, 1U);
}

// ---------------------------------------------------------------------------------------------
// Negative ASCII cases.

TEST(MyahrsDecoder, DocExamplesThatDoNotVerifyAreRejected) {
  // docs/protocols.md section 6: the SDK comment's ~calib line says *0E, the XOR is 0x25.
  const std::string calib_body =
      "~calib,OK,sensor=A,param=4.882813e-04 0.000000e+00 0.000000e+00 0.000000e+00 4.882813e-04 "
      "0.000000e+00 0.000000e+00 0.000000e+00 4.882813e-04 0.000000e+00 0.000000e+00 "
      "0.000000e+00";
  Decoder d;
  EXPECT_TRUE(decode_all(calib_body + "*0E\r\n", &d).empty());
  EXPECT_EQ(d.stats().ascii_checksum_errors, 1U);
  EXPECT_EQ(d.stats().codec.checksum_errors, 1U);
  const auto ok = decode_all(calib_body + "*25\r\n", &d);
  ASSERT_EQ(ok.size(), 1U);
  EXPECT_EQ(d.response().attribute("sensor"), "A");
}

TEST(MyahrsDecoder, WrongChecksumsAreRejected) {
  const std::string good =
      "$RPYIMU,15,-1.55,-1.25,97.31,-0.0142,-0.0010,-0.9224,-0.9756,-0.3659,-0.8537,-8.4000,"
      "-46.8000,5.4000,38.3";
  for (const char* suffix : {"*37\r\n", "*63\r\n", "*00\r\n"}) {
    Decoder d;
    EXPECT_TRUE(decode_all(good + suffix, &d).empty()) << suffix;
    EXPECT_EQ(d.stats().ascii_checksum_errors, 1U);
  }
  // One flipped value byte with the original checksum.
  Decoder d;
  EXPECT_TRUE(decode_all("$RPY,04,-1.55,-1.25,96.95*50\r\n", &d).empty());
  EXPECT_EQ(d.stats().codec.checksum_errors, 1U);
}

TEST(MyahrsDecoder, MalformedChecksumFields) {
  for (const char* line : {"$RPY,04,-1.55,-1.25,96.94\r\n", "$RPY,04,-1.55,-1.25,96.94*5\r\n",
                           "$RPY,04,-1.55,-1.25,96.94*500\r\n", "$RPY,04,-1.55,-1.25,96.94*5G\r\n",
                           "$RPY,04,-1.55*,-1.25,96.94*50\r\n"}) {
    Decoder d;
    EXPECT_TRUE(decode_all(line, &d).empty()) << line;
    EXPECT_EQ(d.stats().ascii_bad_checksum_field, 1U) << line;
    EXPECT_EQ(d.stats().codec.framing_errors, 1U) << line;
  }
}

TEST(MyahrsDecoder, LowerCaseChecksumAcceptedAndCrOptional) {
  EXPECT_EQ(decode_all(std::string("$QUATIMU,53,0.0424,-0.1791,0.2366,0.9540,-0.3636,0.0027,"
                                   "-0.9260,0.0156,0.1537,0.2896,212.2648,-72.7573,168.2144,"
                                   "36.8*7f\n"))
                .size(),
            1U);
}

TEST(MyahrsDecoder, BadFieldsAreCountedNotProduced) {
  for (const char* body :
       {"$RPY,04,-1.55,-1.25", "$RPY,04,-1.55,-1.25,96.94,1", "$RPY,04,abc,-1.25,96.94",
        "$RPY,,-1.55,-1.25,96.94", "$RPY,04,-1.55,-1.25,nan", "$RPY,-4,-1.55,-1.25,96.94",
        "$QUAT,1,0,0,0,0", "$RIIMU,59,-16,-8,-1897.5,-14,-7,-12,-26,-156,18,1101", "~mode,MAYBE",
        "~,OK", "~mode"}) {
    Decoder d;
    EXPECT_TRUE(decode_all(with_checksum(body), &d).empty()) << body;
    EXPECT_EQ(d.stats().ascii_bad_fields, 1U) << body;
    EXPECT_EQ(d.stats().codec.framing_errors, 1U) << body;
  }
  Decoder d;
  EXPECT_TRUE(decode_all(with_checksum("$FOO,1,2"), &d).empty());
  EXPECT_EQ(d.stats().unknown_sentences, 1U);
  EXPECT_EQ(d.stats().codec.unsupported, 1U);
}

TEST(MyahrsDecoder, InterruptedOverlongAndBinaryBytesInLines) {
  Decoder d;
  // A start char restarts the line (SDK behaviour): the first line is lost, the second decodes.
  EXPECT_EQ(decode_all("$RPY,04,-1.5$RPY,04,-1.55,-1.25,96.94*50\r\n", &d).size(), 1U);
  EXPECT_EQ(d.stats().ascii_interrupted, 1U);
  std::string overlong = "$RPY," + std::string(kMaxLineBytes, '1') + "*00\r\n";
  EXPECT_TRUE(decode_all(overlong, &d).empty());
  EXPECT_EQ(d.stats().ascii_overlong, 1U);
  std::string binary_byte = "$RPY,04,-1.55";
  binary_byte += '\xC3';
  binary_byte += ",-1.25,96.94*50\r\n";
  EXPECT_TRUE(decode_all(binary_byte, &d).empty());
  EXPECT_EQ(d.stats().ascii_bad_byte, 1U);
}

// ---------------------------------------------------------------------------------------------
// Binary frames.

TEST(MyahrsBinary, FullyHandWrittenFrameWithStuffedDle) {
  // Root node "d" (no value, has leaves), "s" = 0x10 (u8, next), "e" = i16[3] {0x1000, 0x0010,
  // -0x1000} (last). Three 0x10 bytes are doubled; checksum 0x70 worked out by hand.
  const Bytes frame{0x10, 0x02, 0x80, 0x64, 0x00, 0x42, 0x73, 0x00, 0x10, 0x10, 0x23, 0x65, 0x00,
                    0x03, 0x00, 0x00, 0x10, 0x10, 0x10, 0x10, 0x00, 0x00, 0xF0, 0x70, 0x10, 0x03};
  Decoder d;
  const auto out = decode_all(d, frame);
  ASSERT_EQ(out.size(), 1U);
  EXPECT_EQ(d.sample().sequence, 16U);
  EXPECT_NEAR(d.sample().roll_deg, 4096.0 / 32767.0 * 180.0, 1e-12);
  EXPECT_NEAR(d.sample().pitch_deg, 16.0 / 32767.0 * 180.0, 1e-12);
  EXPECT_NEAR(d.sample().yaw_magnetic_deg, -4096.0 / 32767.0 * 180.0, 1e-12);
  EXPECT_NEAR(d.sample().heading_deg, -22.5007, 1e-4);
  EXPECT_FALSE(d.sample().has_inertial);
  EXPECT_EQ(d.sample_detail().encoding, Encoding::kBinary);
  EXPECT_EQ(d.stats().binary_frames_ok, 1U);
}

Bytes full_body(std::uint8_t seq) {
  Bytes body{0x80, 'd', 0, 0x42, 's', 0, seq};
  append_node_i16_list(body, 'e', {16384, -32767, 32767}, true);
  append_node_i16_list(body, 'q', {0, 0, 23170, 23170}, true);
  append_node_i16_list(body, 'i', {0, 0, -2048, 4112, -4112, 16, 1000, -1000, 0x1010, 6389}, true);
  append_node_i16_list(body, 'r', {-16, -8, -1897, -14, -7, -12, -26, -156, 18, 1101}, false);
  return body;
}

TEST(MyahrsBinary, AllNodesScaled) {
  Decoder d;
  const Bytes frame = binary_frame(full_body(0x10));
  ASSERT_EQ(decode_all(d, frame).size(), 1U);
  const auto& s = d.sample();
  EXPECT_EQ(s.sequence, 16U);
  EXPECT_NEAR(s.roll_deg, 16384.0 / 32767.0 * 180.0, 1e-12);
  EXPECT_DOUBLE_EQ(s.pitch_deg, -180.0);
  EXPECT_DOUBLE_EQ(s.yaw_magnetic_deg, 180.0);
  EXPECT_DOUBLE_EQ(s.heading_deg, 180.0);           // (-180, 180]
  EXPECT_FALSE(d.sample_detail().from_quaternion);  // Euler present: used directly
  EXPECT_TRUE(d.sample_detail().has_quaternion);
  EXPECT_NEAR(d.sample_detail().quaternion_xyzw[2], 23170.0 / 32767.0, 1e-12);
  EXPECT_NEAR(s.accel_g[2], -2048.0 / 32767.0 * 16.0, 1e-12);
  EXPECT_NEAR(s.gyro_dps[0], 4112.0 / 32767.0 * 2000.0, 1e-12);
  EXPECT_NEAR(s.gyro_dps[1], -4112.0 / 32767.0 * 2000.0, 1e-12);
  EXPECT_NEAR(s.mag_ut[2], 4112.0 / 32767.0 * 300.0, 1e-12);
  EXPECT_NEAR(s.temperature_c, 6389.0 / 32767.0 * 200.0, 1e-12);  // ~39 C
  EXPECT_TRUE(s.has_inertial);
  EXPECT_EQ(d.sample_detail().raw_imu[2], -1897);
}

TEST(MyahrsBinary, QuaternionOnlyFrameGivesEuler) {
  Bytes body{0x42, 's', 0, 7};
  append_node_i16_list(body, 'q', {0, 0, 23170, 23170}, false);  // 90 deg about z
  Decoder d;
  ASSERT_EQ(decode_all(d, binary_frame(body)).size(), 1U);
  EXPECT_TRUE(d.sample_detail().from_quaternion);
  EXPECT_NEAR(d.sample().yaw_magnetic_deg, 90.0, 1e-9);
  EXPECT_NEAR(d.sample().roll_deg, 0.0, 1e-9);
}

TEST(MyahrsBinary, CorruptedChecksumAndAbortedFrames) {
  Bytes frame = binary_frame(full_body(3));
  frame[frame.size() - 3] ^= 0x01;  // the checksum byte (not a DLE here)
  Decoder d;
  EXPECT_TRUE(decode_all(d, frame).empty());
  EXPECT_EQ(d.stats().binary_checksum_errors, 1U);
  EXPECT_EQ(d.stats().codec.checksum_errors, 1U);

  Bytes flipped = binary_frame(full_body(3));
  flipped[20] ^= 0x40;  // a value byte
  EXPECT_TRUE(decode_all(d, flipped).empty());
  EXPECT_EQ(d.stats().binary_checksum_errors, 2U);

  // DLE followed by a byte other than DLE/STX/ETX aborts the frame.
  const Bytes aborted{0x10, 0x02, 0x42, 's', 0, 0x10, 0x55, 0x01, 0x10, 0x03};
  EXPECT_TRUE(decode_all(d, aborted).empty());
  EXPECT_EQ(d.stats().binary_aborted, 1U);
  // Empty frame.
  EXPECT_TRUE(decode_all(d, Bytes{0x10, 0x02, 0x10, 0x03}).empty());
  EXPECT_EQ(d.stats().binary_malformed, 1U);
  // Decoder still works afterwards.
  EXPECT_EQ(decode_all(d, binary_frame(full_body(4))).size(), 1U);
}

TEST(MyahrsBinary, MalformedNodeChains) {
  const std::vector<Bytes> bodies = {
      Bytes{0x42, 's'},                                               // name without NUL
      Bytes{0x63, 'e', 0, 3, 0, 1, 0},                                // list shorter than its count
      Bytes{0x23, 'e', 0, 2, 0, 1, 0, 2, 0},                          // e with 2 values
      Bytes{0x29, 'e', 0, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0},  // e as f32
      Bytes{0x4C, 'x', 0},                                            // value type 12
      Bytes{0x0B, 'n', 0, 'a', 'b'},                                  // string without NUL
      Bytes{0x23, 'q', 0, 4, 0, 0, 0, 0, 0, 0, 0, 0, 0},              // zero quaternion, no Euler
  };
  for (const Bytes& body : bodies) {
    Decoder d;
    EXPECT_TRUE(decode_all(d, binary_frame(body)).empty());
    EXPECT_EQ(d.stats().binary_malformed, 1U);
    EXPECT_EQ(d.stats().binary_frames_ok, 1U);  // checksum was fine
  }
  Decoder d;
  EXPECT_TRUE(decode_all(d, binary_frame(Bytes{0x80, 'd', 0, 0x02, 's', 0, 5})).empty());
  EXPECT_EQ(d.stats().binary_without_data, 1U);
  // Unknown nodes (string, list of u32, the DCM 'c') are skipped.
  Bytes body{0xCB, 'v', 0, '1', '.', '6', 0, 0x66, 'c', 0, 1, 0, 1, 2, 3, 4};
  append_node_i16_list(body, 'e', {0, 0, 100}, false);
  EXPECT_EQ(decode_all(d, binary_frame(body)).size(), 1U);
}

TEST(MyahrsBinary, OverlongFrame) {
  Bytes body(kMaxFrameBytes + 10, 0x01);
  Decoder d;
  EXPECT_TRUE(decode_all(d, binary_frame(body)).empty());
  EXPECT_EQ(d.stats().binary_overlong, 1U);
}

// ---------------------------------------------------------------------------------------------
// Mixed streams, garbage, resync and split equivalence.

Bytes mixed_stream() {
  Bytes s;
  const auto add = [&s](const Bytes& b) { s.insert(s.end(), b.begin(), b.end()); };
  add(to_bytes("\x01\xFFgarbage\r\n"));
  add(to_bytes("$RPY,04,-1.55,-1.25,96.94*50\r\n"));
  add(binary_frame(full_body(0x10)));
  add(to_bytes(with_checksum("~mode,OK,mode=AC")));
  add(Bytes{0x10, 0x10, 0x10, 0x05, 0x02});  // stray DLEs
  add(to_bytes("$QUAT,68,0.0006,0.0174,-0.7489,-0.6625*16\r\n"));
  add(to_bytes("$RPY,04,-1.55,-1.25,96.94*51\r\n"));  // bad checksum
  add(binary_frame(full_body(0x11)));
  add(
      to_bytes("$IMU,74,-0.0054,-0.0015,-0.9204,-0.7317,-0.4878,-0.7317,-7.2000,-45.6000,"
               "6.6000,38.2*68\r\n"));
  add(to_bytes(with_checksum("~bin_out,OK,fmt=EULER, IMU")));
  return s;
}

TEST(MyahrsStream, GarbageAndResync) {
  Decoder d;
  const Bytes s = mixed_stream();
  const auto out = decode_all(d, s);
  ASSERT_EQ(out.size(), 7U);
  EXPECT_EQ(out[0].sequence, 4U);
  EXPECT_EQ(out[1].sequence, 16U);
  EXPECT_EQ(out[2].command, "mode");
  EXPECT_EQ(out[3].sequence, 68U);
  EXPECT_EQ(out[4].sequence, 17U);
  EXPECT_EQ(out[5].sequence, 74U);
  EXPECT_EQ(out[6].command, "bin_out");
  EXPECT_EQ(d.stats().ascii_checksum_errors, 1U);
  EXPECT_GT(d.stats().codec.bytes_skipped, 0U);
  EXPECT_EQ(d.stats().codec.bytes_in, s.size());
}

TEST(MyahrsStream, SplitAtEveryByteIsEquivalent) {
  const Bytes s = mixed_stream();
  Decoder whole;
  const auto expected = decode_all(whole, s);
  {
    Decoder d;
    EXPECT_EQ(decode_all(d, s, 1), expected);
  }
  for (std::size_t cut = 1; cut < s.size(); ++cut) {
    Decoder d;
    std::vector<Record> got = decode_all(d, std::span<const std::uint8_t>(s).first(cut));
    const auto tail = decode_all(d, std::span<const std::uint8_t>(s).subspan(cut));
    got.insert(got.end(), tail.begin(), tail.end());
    ASSERT_EQ(got, expected) << "cut at " << cut;
    EXPECT_EQ(d.stats().codec.framing_errors, whole.stats().codec.framing_errors);
    EXPECT_EQ(d.stats().codec.bytes_skipped, whole.stats().codec.bytes_skipped);
  }
}

TEST(MyahrsStream, BinaryFrameContainingStartCharsIsNotAscii) {
  // '$' (0x24), '~' (0x7E), '@' (0x40) and LF inside a binary frame must not start ASCII lines.
  Bytes body{0x42, 's', 0, 0x24};
  append_node_i16_list(body, 'e', {0x7E40, 0x0A24, 0x407E}, false);
  Decoder d;
  ASSERT_EQ(decode_all(d, binary_frame(body)).size(), 1U);
  EXPECT_EQ(d.sample().sequence, 0x24U);
  EXPECT_EQ(d.stats().codec.framing_errors, 0U);
}

TEST(MyahrsStream, ResetDropsPartialFrame) {
  Decoder d;
  const Bytes part = to_bytes("$RPY,04,-1.55");
  EXPECT_TRUE(decode_all(d, part).empty());
  d.reset();
  EXPECT_TRUE(decode_all(d, to_bytes(",-1.25,96.94*50\r\n")).empty());
  EXPECT_EQ(decode_all(d, to_bytes("$RPY,04,-1.55,-1.25,96.94*50\r\n")).size(), 1U);
}

TEST(MyahrsDecoder, HeadingConfigAppliedToSamples) {
  HeadingConfig cfg;
  cfg.declination_deg = -9.0;
  cfg.mount_yaw_deg = 90.0;
  Decoder d(cfg);
  ASSERT_EQ(decode_all("$RPY,04,-1.55,-1.25,96.94*50\r\n", &d).size(), 1U);
  EXPECT_DOUBLE_EQ(d.sample().yaw_magnetic_deg, 96.94);
  EXPECT_NEAR(d.sample().heading_deg, 96.94 - 90.0 - 9.0, 1e-12);
}

}  // namespace
}  // namespace coxswain::drivers::myahrs
