// SPDX-License-Identifier: Apache-2.0
// Golden vectors from docs/protocols.md section 3 and hand-built frames (RTK float/fixed, NMEA RTK,
// RTCM 3) for the u-blox decoder and RTCM 3 framer. Needs no recordings.
#include "coxswain/drivers/ublox/codec.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "ublox_test_util.hpp"

namespace coxswain::drivers::ublox {
namespace {

using test::append;
using test::decode_all;
using test::from_hex;
using test::nmea;
using test::Record;

// docs/protocols.md 3.3: first NAV-PVT of gpsd's ublox-neo-m8n.log.
constexpr std::string_view kNavPvtExample =
    "b56201075c0030985811e107071308320037030000002780ad2f03030a0eadeb9d5289bb31eb50630000df70000"
    "06c04000042060000f6ffffffe4ffffff260000001e000000aa053000e5000000685f0d00910000e0ac4c220000"
    "e000e000000080c855";
// docs/protocols.md 3.4: first NAV-HPPOSLLH of ublox-zed-f9p-hp.log.
constexpr std::string_view kHpPosLlhExample =
    "b562011424000000000010e6b9095a41a0650aa5a7e432720000336b0000f20efc00a6350200d6f70100b445";
// docs/protocols.md 3.2: ACK-ACK for CFG-TMODE2.
constexpr std::string_view kAckExample = "B5 62 05 01 02 00 06 3D 4B 74";

std::vector<std::uint8_t> rtcm3_frame(std::uint16_t type, std::size_t payload_len,
                                      std::uint8_t fill) {
  std::vector<std::uint8_t> f{kRtcm3Preamble, static_cast<std::uint8_t>(payload_len >> 8),
                              static_cast<std::uint8_t>(payload_len & 0xFF)};
  std::vector<std::uint8_t> payload(payload_len, fill);
  payload[0] = static_cast<std::uint8_t>(type >> 4);
  payload[1] = static_cast<std::uint8_t>(((type & 0x0F) << 4) | (fill & 0x0F));
  f.insert(f.end(), payload.begin(), payload.end());
  const std::uint32_t crc = crc24q(f);
  f.push_back(static_cast<std::uint8_t>(crc >> 16));
  f.push_back(static_cast<std::uint8_t>(crc >> 8));
  f.push_back(static_cast<std::uint8_t>(crc));
  return f;
}

TEST(UbloxChecksums, FletcherMatchesCapturedAck) {
  const auto ack = from_hex(kAckExample);
  const auto ck = ubx_checksum(std::span(ack).subspan(2, 6));
  EXPECT_EQ(ck[0], 0x4B);
  EXPECT_EQ(ck[1], 0x74);
}

TEST(UbloxChecksums, Crc24qStandardCheckValue) {
  const std::string s = "123456789";
  EXPECT_EQ(crc24q(std::span(reinterpret_cast<const std::uint8_t*>(s.data()), s.size())),
            0xCDE703U);
}

TEST(UbloxChecksums, DaysFromCivil) {
  EXPECT_EQ(unix_days_from_civil(1970, 1, 1), 0);
  EXPECT_EQ(unix_days_from_civil(2000, 3, 1), 11017);
  EXPECT_EQ(unix_days_from_civil(2017, 7, 19) * 86400, 1500422400);
}

TEST(UbloxDecoder, NavPvtWorkedExample) {
  Decoder d;
  const auto bytes = from_hex(kNavPvtExample);
  ASSERT_EQ(bytes.size(), 100U);
  const auto out = decode_all(d, bytes);
  ASSERT_EQ(out.size(), 1U);
  ASSERT_EQ(out[0].kind, MessageKind::kFix);
  const msg::GnssFix& f = out[0].fix;
  EXPECT_EQ(f.source, msg::GnssSource::kUbxNavPvt);
  EXPECT_EQ(f.itow_ms, 291018800U);
  EXPECT_EQ(f.fix_type, msg::FixType::k3D);
  EXPECT_TRUE(f.fix_ok);
  EXPECT_TRUE(f.diff_soln);
  EXPECT_EQ(f.rtk, msg::RtkSolution::kNone);
  EXPECT_EQ(f.satellites, 14);
  EXPECT_NEAR(f.lat_deg, -34.9062263, 1e-10);
  EXPECT_NEAR(f.lon_deg, 138.6081197, 1e-10);
  EXPECT_NEAR(f.height_msl_m, 28.895, 1e-9);
  EXPECT_NEAR(f.h_acc_m, 1.132, 1e-9);
  EXPECT_NEAR(f.v_acc_m, 1.602, 1e-9);
  EXPECT_NEAR(f.ground_speed_mps, 0.030, 1e-9);
  EXPECT_NEAR(f.course_deg, 31.47178, 1e-9);
  EXPECT_NEAR(f.vel_north_mps, -0.010, 1e-9);  // f6ffffff
  EXPECT_NEAR(f.vel_east_mps, -0.028, 1e-9);   // e4ffffff
  EXPECT_NEAR(f.vel_down_mps, 0.038, 1e-9);    // 26000000
  EXPECT_NEAR(f.s_acc_mps, 0.229, 1e-9);       // sAcc e5000000 mm/s
  EXPECT_TRUE(f.velocity_valid);
  // 2017-07-19 08:50:00 UTC + nano 0x2FAD8027 = 799899687 ns.
  EXPECT_EQ(f.utc_ns, 1500454200LL * 1'000'000'000LL + 799'899'687LL);
  EXPECT_EQ(f.stamp_ns, core::kNeverNs);  // the adapter stamps
  EXPECT_TRUE(f.usable());
  EXPECT_EQ(d.stats().frames_ok, 1U);
  EXPECT_EQ(d.stats().messages_out, 1U);
  EXPECT_EQ(d.stats().bytes_in, 100U);
  EXPECT_EQ(d.stats().checksum_errors + d.stats().framing_errors + d.stats().bytes_skipped, 0U);
}

TEST(UbloxDecoder, HpPosLlhWorkedExample) {
  Decoder d;
  const auto out = decode_all(d, from_hex(kHpPosLlhExample));
  ASSERT_EQ(out.size(), 1U);
  ASSERT_EQ(out[0].kind, MessageKind::kHpPosLlh);
  const HpPosLlh& hp = out[0].hp;
  EXPECT_EQ(hp.itow_ms, 163178000U);
  EXPECT_FALSE(hp.invalid_llh);
  EXPECT_NEAR(hp.lon_deg, 170.500130586, 1e-12);
  EXPECT_NEAR(hp.lat_deg, -45.877528586, 1e-12);
  EXPECT_NEAR(hp.height_m, 29.2336, 1e-9);
  EXPECT_NEAR(hp.height_msl_m, 27.443, 1e-9);
  EXPECT_NEAR(hp.h_acc_m, 14.48, 1e-3);
}

TEST(UbloxDecoder, AckAndNak) {
  Decoder d;
  auto bytes = from_hex(kAckExample);
  const std::array<std::uint8_t, 2> nak_payload{0x06, 0x8A};
  append(bytes, make_ubx_frame(UbxId{0x05, 0x00}, nak_payload).bytes());
  const auto out = decode_all(d, bytes);
  ASSERT_EQ(out.size(), 2U);
  EXPECT_EQ(out[0].kind, MessageKind::kAck);
  EXPECT_EQ(out[0].ubx, (UbxId{0x06, 0x3D}));
  EXPECT_EQ(out[1].kind, MessageKind::kNak);
  EXPECT_EQ(out[1].ubx, (UbxId{0x06, 0x8A}));
}

TEST(UbloxDecoder, HandBuiltRtkFloatAndFixed) {
  Decoder d;
  test::PvtSpec fl;
  fl.flags = 0x01 | 0x02 | (1 << 6);  // gnssFixOK, diffSoln, carrSoln float
  test::PvtSpec fx = fl;
  fx.itow_ms += 200;
  fx.flags = 0x01 | 0x02 | (2 << 6);  // carrSoln fixed
  fx.nano = -1000;                    // negative nano: 1 us before the second
  std::vector<std::uint8_t> bytes;
  append(bytes, test::nav_pvt_frame(fl).bytes());
  append(bytes, test::nav_pvt_frame(fx).bytes());
  const auto out = decode_all(d, bytes);
  ASSERT_EQ(out.size(), 2U);
  const msg::GnssFix& a = out[0].fix;
  EXPECT_EQ(a.rtk, msg::RtkSolution::kFloat);
  EXPECT_TRUE(a.diff_soln);
  EXPECT_TRUE(a.usable());
  EXPECT_NEAR(a.lat_deg, 35.1, 1e-12);
  EXPECT_NEAR(a.lon_deg, 126.8, 1e-12);
  EXPECT_NEAR(a.h_acc_m, 0.014, 1e-12);
  EXPECT_NEAR(a.v_acc_m, 0.021, 1e-12);
  EXPECT_NEAR(a.vel_north_mps, 1.5, 1e-12);
  EXPECT_NEAR(a.vel_east_mps, -2.0, 1e-12);
  EXPECT_NEAR(a.vel_down_mps, 0.03, 1e-12);
  EXPECT_NEAR(a.ground_speed_mps, 2.5, 1e-12);
  EXPECT_NEAR(a.course_deg, 306.87 - 360.0, 1e-9);  // wrapped into (-180, 180]
  EXPECT_EQ(a.satellites, 20);
  EXPECT_EQ(a.utc_ns, 1715915045LL * 1'000'000'000LL + 250'000'000LL);
  const msg::GnssFix& b = out[1].fix;
  EXPECT_EQ(b.rtk, msg::RtkSolution::kFixed);
  EXPECT_EQ(b.itow_ms, fl.itow_ms + 200);
  EXPECT_EQ(b.utc_ns, 1715915045LL * 1'000'000'000LL - 1000LL);
}

TEST(UbloxDecoder, NavPvtWithoutValidTimeOrFix) {
  Decoder d;
  test::PvtSpec s;
  s.valid = 0x00;  // neither validDate nor validTime
  s.fix_type = 0;
  s.flags = 0;
  const auto out = decode_all(d, test::nav_pvt_frame(s).bytes());
  ASSERT_EQ(out.size(), 1U);
  EXPECT_EQ(out[0].fix.utc_ns, 0);
  EXPECT_FALSE(out[0].fix.usable());
  EXPECT_FALSE(out[0].fix.velocity_valid);
  EXPECT_EQ(out[0].fix.rtk, msg::RtkSolution::kNone);
}

TEST(UbloxDecoder, MalformedNavPvtLengthIsAFramingError) {
  Decoder d;
  const std::vector<std::uint8_t> short_payload(50, 0);
  const auto out = decode_all(d, make_ubx_frame(kNavPvt, short_payload).bytes());
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(d.stats().frames_ok, 1U);
  EXPECT_EQ(d.stats().framing_errors, 1U);
  EXPECT_EQ(d.stats().messages_out, 0U);
}

TEST(UbloxDecoder, NmeaRmcThenGgaRtkFixedAndFloat) {
  Decoder d;
  std::string text;
  text += nmea("GNRMC,123519.00,A,3507.12345,N,12648.00000,E,10.0,90.0,170524,,,R,V");
  text += nmea("GNGGA,123519.00,3507.12345,N,12648.00000,E,4,18,0.55,12.3,M,20.1,M,1.0,0000");
  text += nmea("GNGGA,123519.20,3507.12345,N,12648.00000,E,5,18,0.55,12.3,M,20.1,M,1.0,0000");
  text += nmea("GNGSV,1,1,01,05,40,083,46");
  const auto out =
      decode_all(d, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
  ASSERT_EQ(out.size(), 4U);
  const std::int64_t day_ns = unix_days_from_civil(2024, 5, 17) * 86400LL * 1'000'000'000LL;
  const std::int64_t tod_ns = (12 * 3600 + 35 * 60 + 19) * 1'000'000'000LL;

  const msg::GnssFix& rmc = out[0].fix;
  EXPECT_EQ(out[0].nmea_address, "GNRMC");
  EXPECT_EQ(rmc.source, msg::GnssSource::kNmeaRmc);
  EXPECT_EQ(rmc.rtk, msg::RtkSolution::kFixed);
  EXPECT_EQ(rmc.fix_type, msg::FixType::k2D);
  EXPECT_NEAR(rmc.lat_deg, 35.0 + 7.12345 / 60.0, 1e-12);
  EXPECT_NEAR(rmc.lon_deg, 126.8, 1e-12);
  EXPECT_NEAR(rmc.ground_speed_mps, 10.0 * 1852.0 / 3600.0, 1e-12);
  EXPECT_NEAR(rmc.vel_east_mps, 10.0 * 1852.0 / 3600.0, 1e-9);
  EXPECT_NEAR(rmc.vel_north_mps, 0.0, 1e-9);
  EXPECT_EQ(rmc.utc_ns, day_ns + tod_ns);

  const msg::GnssFix& fixed = out[1].fix;
  EXPECT_EQ(fixed.source, msg::GnssSource::kNmeaGga);
  EXPECT_EQ(fixed.rtk, msg::RtkSolution::kFixed);
  EXPECT_EQ(fixed.fix_type, msg::FixType::k3D);
  EXPECT_TRUE(fixed.usable());
  EXPECT_TRUE(fixed.diff_soln);
  EXPECT_EQ(fixed.satellites, 18);
  EXPECT_NEAR(fixed.hdop, 0.55, 1e-12);
  EXPECT_NEAR(fixed.height_msl_m, 12.3, 1e-12);
  EXPECT_EQ(fixed.utc_ns, day_ns + tod_ns);  // date from the RMC
  EXPECT_TRUE(fixed.velocity_valid);         // velocity of the RMC of the same second
  EXPECT_NEAR(fixed.course_deg, 90.0, 1e-12);

  const msg::GnssFix& flt = out[2].fix;
  EXPECT_EQ(flt.rtk, msg::RtkSolution::kFloat);
  EXPECT_EQ(flt.utc_ns, day_ns + tod_ns + 200'000'000LL);
  EXPECT_FALSE(flt.velocity_valid);  // not the RMC's second

  EXPECT_EQ(out[3].kind, MessageKind::kOtherNmea);
  EXPECT_EQ(out[3].nmea_address, "GNGSV");
  EXPECT_EQ(d.stats().unsupported, 1U);
}

TEST(UbloxDecoder, NmeaGgaNoFixAndMidnightCrossing) {
  Decoder d;
  std::string text;
  text += nmea("GNRMC,235959.50,A,3507.00000,N,12648.00000,E,0.0,,311224,,,A");
  text += nmea("GNGGA,000000.50,3507.00000,N,12648.00000,E,1,08,1.0,5.0,M,20.0,M,,");
  text += nmea("GNGGA,,,,,,0,00,99.99,,,,,,");
  const auto out =
      decode_all(d, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
  ASSERT_EQ(out.size(), 3U);
  const std::int64_t jan1 = unix_days_from_civil(2025, 1, 1) * 86400LL * 1'000'000'000LL;
  EXPECT_EQ(out[1].fix.utc_ns, jan1 + 500'000'000LL);
  EXPECT_FALSE(out[1].fix.velocity_valid);
  EXPECT_EQ(out[2].fix.fix_type, msg::FixType::kNoFix);
  EXPECT_FALSE(out[2].fix.fix_ok);
  EXPECT_EQ(out[2].fix.utc_ns, 0);  // no time field
}

TEST(UbloxDecoder, NmeaGllPositionFix) {
  Decoder d;
  std::string text;
  text += nmea("GNGLL,4404.14066,N,12118.85481,W,171925.00,A,A");  // before any date
  text += nmea("GNRMC,171926.00,A,4404.14063,N,12118.85478,W,0.117,,180315,,,A");
  text += nmea("GNGLL,4404.14063,N,12118.85478,W,171926.00,A,D");
  text += nmea("GNGLL,,,,,171927.00,V,N");
  const auto out =
      decode_all(d, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
  ASSERT_EQ(out.size(), 4U);
  EXPECT_EQ(out[0].fix.source, msg::GnssSource::kNmeaGll);
  EXPECT_NEAR(out[0].fix.lat_deg, 44.0 + 4.14066 / 60.0, 1e-12);
  EXPECT_NEAR(out[0].fix.lon_deg, -(121.0 + 18.85481 / 60.0), 1e-12);
  EXPECT_EQ(out[0].fix.utc_ns, 0);
  EXPECT_EQ(out[0].fix.fix_type, msg::FixType::k2D);
  EXPECT_TRUE(out[2].fix.diff_soln);
  EXPECT_EQ(
      out[2].fix.utc_ns,
      (unix_days_from_civil(2015, 3, 18) * 86400 + 17 * 3600 + 19 * 60 + 26) * 1'000'000'000LL);
  EXPECT_FALSE(out[3].fix.fix_ok);
  EXPECT_FALSE(out[3].fix.usable());
}

TEST(UbloxDecoder, Rtcm3FrameIsAViewIntoTheBuffer) {
  Decoder d;
  const auto f = rtcm3_frame(1077, 40, 0x5A);
  const auto out = decode_all(d, f);
  ASSERT_EQ(out.size(), 1U);
  EXPECT_EQ(out[0].kind, MessageKind::kRtcm3);
  EXPECT_EQ(out[0].rtcm_type, 1077);
  EXPECT_EQ(out[0].rtcm_bytes, f);
}

TEST(UbloxDecoder, OtherUbxIsReportedAsUnsupported) {
  Decoder d;
  const std::array<std::uint8_t, 4> eoe{1, 2, 3, 4};
  const auto out = decode_all(d, make_ubx_frame(UbxId{0x01, 0x61}, eoe).bytes());
  ASSERT_EQ(out.size(), 1U);
  EXPECT_EQ(out[0].kind, MessageKind::kOtherUbx);
  EXPECT_EQ(out[0].ubx, (UbxId{0x01, 0x61}));
  EXPECT_EQ(d.stats().unsupported, 1U);
}

TEST(UbloxDecoder, CorruptedChecksumsAreCountedAndSkipped) {
  Decoder d;
  const auto good = test::nav_pvt_frame(test::PvtSpec{});
  auto bad = std::vector<std::uint8_t>(good.bytes().begin(), good.bytes().end());
  bad[40] ^= 0x01;  // payload bit flip
  std::string bad_nmea = nmea("GNGGA,000000.50,3507.00000,N,12648.00000,E,1,08,1.0,5.0,M,,M,,");
  bad_nmea[10] = '9';
  auto bad_rtcm = rtcm3_frame(1005, 19, 0x11);
  bad_rtcm[10] ^= 0x80;
  std::vector<std::uint8_t> bytes;
  append(bytes, good.bytes());
  append(bytes, bad);
  append(bytes, bad_nmea);
  append(bytes, bad_rtcm);
  append(bytes, good.bytes());
  const auto out = decode_all(d, bytes);
  ASSERT_EQ(out.size(), 2U);
  EXPECT_EQ(out[0].kind, MessageKind::kFix);
  EXPECT_EQ(out[1].kind, MessageKind::kFix);
  EXPECT_EQ(d.stats().checksum_errors, 3U);
  EXPECT_EQ(d.stats().frames_ok, 2U);
  EXPECT_EQ(d.stats().bytes_in, bytes.size());
  // Everything except the two good frames was dropped one way or another.
  EXPECT_EQ(d.stats().bytes_skipped, bytes.size() - 2 * good.size);
}

TEST(UbloxDecoder, FalseLengthDoesNotSwallowFollowingFrames) {
  // A fake UBX header claiming 300 bytes and a fake RTCM preamble claiming 1000 bytes, each
  // followed by real frames: the real frames are recovered after the fake fails its checksum.
  Decoder d;
  std::vector<std::uint8_t> bytes{0xB5, 0x62, 0x01, 0x07, 0x2C, 0x01};
  const auto pvt = test::nav_pvt_frame(test::PvtSpec{});
  for (int i = 0; i < 3; ++i) append(bytes, pvt.bytes());
  append(bytes, std::vector<std::uint8_t>{0xD3, 0x03, 0xE8});
  for (int i = 0; i < 12; ++i) append(bytes, pvt.bytes());
  append(bytes, from_hex(kAckExample));
  const auto out = decode_all(d, bytes);
  ASSERT_EQ(out.size(), 16U);
  EXPECT_EQ(out.back().kind, MessageKind::kAck);
  EXPECT_EQ(d.stats().checksum_errors, 2U);
  EXPECT_EQ(d.stats().bytes_skipped, 9U);
}

TEST(UbloxDecoder, LineNoiseBeforeNmeaIsSkipped) {
  Decoder d;
  std::mt19937 rng(7);
  std::vector<std::uint8_t> bytes(300);
  for (auto& b : bytes) b = static_cast<std::uint8_t>(rng() & 0xFF);
  append(bytes, nmea("GNRMC,000941.00,A,4404.13387,N,12118.85628,W,0.029,,100117,,,A"));
  append(bytes, nmea("GNGGA,000941.00,4404.13387,N,12118.85628,W,1,12,1.01,1144.8,M,-21.4,M,,"));
  const auto out = decode_all(d, bytes);
  ASSERT_GE(out.size(), 2U);
  EXPECT_EQ(out[out.size() - 2].nmea_address, "GNRMC");
  EXPECT_EQ(out.back().nmea_address, "GNGGA");
  EXPECT_NEAR(out.back().fix.lat_deg, 44.068897833, 1e-9);
  EXPECT_GT(d.stats().bytes_skipped, 250U);
}

std::vector<std::uint8_t> mixed_stream() {
  std::vector<std::uint8_t> s{0x00, 0xB5, 0x13, '$', 'G', 0xD3, 0xFF, 0x0A};  // leading noise
  append(s, from_hex(kNavPvtExample));
  append(s, nmea("GNGGA,123519.00,3507.12345,N,12648.00000,E,4,18,0.55,12.3,M,20.1,M,1.0,0000"));
  append(s, rtcm3_frame(1005, 19, 0x21));
  append(s, from_hex(kHpPosLlhExample));
  append(s, std::vector<std::uint8_t>{0xB5, 0x62, 0x01, 0x07, 0x40, 0x00});  // false header
  append(s, from_hex(kAckExample));
  auto bad = from_hex(kNavPvtExample);
  bad[50] ^= 0x10;
  append(s, bad);
  append(s, rtcm3_frame(1230, 8, 0x00));
  append(s, nmea("GNRMC,123519.00,A,3507.12345,N,12648.00000,E,10.0,90.0,170524,,,F,V"));
  test::PvtSpec fixed;
  fixed.flags = 0x83;
  append(s, test::nav_pvt_frame(fixed).bytes());
  append(s, std::vector<std::uint8_t>{'$', 'G', 'P', 0xB5});
  return s;
}

TEST(UbloxDecoder, EverySplitGivesIdenticalResults) {
  const auto stream = mixed_stream();
  Decoder ref;
  const auto expected = decode_all(ref, stream);
  ASSERT_EQ(expected.size(), 8U);
  EXPECT_GE(ref.stats().checksum_errors, 2U);  // the false header and the corrupted NAV-PVT
  EXPECT_GE(ref.stats().framing_errors, 3U);   // the leading noise
  for (std::size_t k = 1; k < stream.size(); ++k) {
    Decoder d;
    std::vector<Record> got;
    for (const auto part : {std::span(stream).first(k), std::span(stream).subspan(k)}) {
      std::span<const std::uint8_t> rest = part;
      while (!rest.empty()) {
        const DecodeStep step = d.decode(rest);
        ASSERT_GE(step.consumed, 1U);
        rest = rest.subspan(step.consumed);
        if (step.produced) got.push_back(test::record(d.message()));
      }
    }
    while (d.decode({}).produced) got.push_back(test::record(d.message()));
    ASSERT_EQ(got, expected) << "split at " << k;
    ASSERT_EQ(d.stats().bytes_skipped, ref.stats().bytes_skipped) << "split at " << k;
    ASSERT_EQ(d.stats().checksum_errors, ref.stats().checksum_errors) << "split at " << k;
    ASSERT_EQ(d.stats().framing_errors, ref.stats().framing_errors) << "split at " << k;
    ASSERT_EQ(d.stats().frames_ok, ref.stats().frames_ok) << "split at " << k;
  }
  for (const std::size_t chunk : {1U, 2U, 3U, 7U, 64U}) {
    Decoder d;
    EXPECT_EQ(decode_all(d, stream, chunk), expected) << "chunk " << chunk;
    EXPECT_EQ(d.stats().bytes_in, stream.size());
  }
}

TEST(UbloxDecoder, RandomBytesAlwaysProgress) {
  std::mt19937 rng(11);
  std::vector<std::uint8_t> bytes(20000);
  for (auto& b : bytes) b = static_cast<std::uint8_t>(rng() & 0xFF);
  Decoder d;
  (void)decode_all(d, bytes, 97);  // throws if a call consumes nothing
  EXPECT_EQ(d.stats().bytes_in, bytes.size());
}

TEST(Rtcm3Framer, ExtractsFramesAndResyncs) {
  const auto a = rtcm3_frame(1077, 200, 0x33);
  const auto b = rtcm3_frame(4072, 3, 0xD3);                // payload full of fake preambles
  std::vector<std::uint8_t> bytes{0xD3, 0x00, 0x05, 0x01};  // truncated fake frame
  append(bytes, a);
  append(bytes, from_hex(kNavPvtExample));  // not RTCM: skipped
  append(bytes, b);
  std::vector<std::vector<std::uint8_t>> frames;
  std::vector<std::uint16_t> types;
  for (std::size_t chunk : {std::size_t{1}, std::size_t{5}, bytes.size()}) {
    frames.clear();
    types.clear();
    Rtcm3Framer f;
    for (std::size_t off = 0; off < bytes.size(); off += chunk) {
      std::span<const std::uint8_t> rest =
          std::span(bytes).subspan(off, std::min(chunk, bytes.size() - off));
      while (!rest.empty()) {
        const DecodeStep step = f.decode(rest);
        ASSERT_GE(step.consumed, 1U);
        rest = rest.subspan(step.consumed);
        if (step.produced) {
          frames.emplace_back(f.frame().bytes.begin(), f.frame().bytes.end());
          types.push_back(f.frame().message_type);
        }
      }
    }
    while (f.decode({}).produced) {
      frames.emplace_back(f.frame().bytes.begin(), f.frame().bytes.end());
      types.push_back(f.frame().message_type);
    }
    ASSERT_EQ(frames.size(), 2U) << "chunk " << chunk;
    EXPECT_EQ(frames[0], a);
    EXPECT_EQ(frames[1], b);
    EXPECT_EQ(types, (std::vector<std::uint16_t>{1077, 4072}));
    EXPECT_EQ(f.stats().messages_out, 2U);
    EXPECT_EQ(f.stats().bytes_skipped, bytes.size() - a.size() - b.size());
  }
}

}  // namespace
}  // namespace coxswain::drivers::ublox

namespace coxswain::drivers::ublox {
namespace {

std::vector<std::uint8_t> ubx(std::uint8_t id, std::vector<std::uint8_t> payload) {
  const UbxFrame f = make_ubx_frame(UbxId{0x01, id}, payload);
  return {f.bytes().begin(), f.bytes().end()};
}

TEST(UbloxDecoder, OlderNavMessagesOfOneEpochMergeIntoOneFix) {
  // A u-blox 6-style epoch: NAV-POSLLH, NAV-STATUS, NAV-VELNED (no NAV-PVT).
  std::vector<std::uint8_t> posllh(28, 0);
  test::put_le(posllh, 0, 200'000, 4);
  test::put_le(posllh, 4, 1'268'000'000, 4);  // lon 126.8
  test::put_le(posllh, 8, 351'000'000, 4);    // lat 35.1
  test::put_le(posllh, 16, 12'345, 4);        // hMSL mm
  test::put_le(posllh, 20, 1'500, 4);         // hAcc mm
  std::vector<std::uint8_t> status(16, 0);
  test::put_le(status, 0, 200'000, 4);
  status[4] = 3;     // 3-D
  status[5] = 0x03;  // gpsFixOk, diffSoln
  std::vector<std::uint8_t> velned(36, 0);
  test::put_le(velned, 0, 200'000, 4);
  test::put_le(velned, 4, 150, 4);          // north cm/s
  test::put_le(velned, 8, -200, 4);         // east
  test::put_le(velned, 20, 250, 4);         // ground speed
  test::put_le(velned, 24, 30'687'000, 4);  // heading 306.87 deg
  test::put_le(velned, 28, 40, 4);          // sAcc cm/s
  std::vector<std::uint8_t> bytes;
  for (const auto& f : {ubx(0x02, posllh), ubx(0x03, status), ubx(0x12, velned)}) {
    bytes.insert(bytes.end(), f.begin(), f.end());
  }
  Decoder d;
  const auto out = test::decode_all(d, bytes, 7);
  std::vector<msg::GnssFix> fixes;
  for (const auto& r : out) {
    if (r.kind == MessageKind::kFix) fixes.push_back(r.fix);
  }
  ASSERT_EQ(fixes.size(), 2U);  // position known once STATUS came, completed by VELNED
  const msg::GnssFix& f = fixes.back();
  EXPECT_EQ(f.source, msg::GnssSource::kUbxNavLegacy);
  EXPECT_EQ(f.itow_ms, 200'000U);
  EXPECT_TRUE(f.fix_ok);
  EXPECT_TRUE(f.diff_soln);
  EXPECT_EQ(f.fix_type, msg::FixType::k3D);
  EXPECT_DOUBLE_EQ(f.lat_deg, 35.1);
  EXPECT_DOUBLE_EQ(f.lon_deg, 126.8);
  EXPECT_DOUBLE_EQ(f.h_acc_m, 1.5);
  EXPECT_DOUBLE_EQ(f.ground_speed_mps, 2.5);
  EXPECT_NEAR(f.course_deg, -53.13, 1e-9);
  EXPECT_DOUBLE_EQ(f.s_acc_mps, 0.4);
  EXPECT_TRUE(f.velocity_valid);
  EXPECT_EQ(d.stats().framing_errors, 0U);
}

TEST(UbloxDecoder, NavSolAloneGivesPositionFromEcefAndUtcFromTheWeek) {
  // ECEF of 44.068817081 N, 121.314317437 W, 1110.233 m (gpsd's NEO-M8T capture).
  std::vector<std::uint8_t> sol(52, 0);
  test::put_le(sol, 0, 353'735'000, 4);
  test::put_le(sol, 8, 2039, 2);
  sol[10] = 5;     // time only (surveyed in)
  sol[11] = 0x0D;  // gpsFixOK, week and TOW valid
  test::put_le(sol, 12, -238'607'116, 4);
  test::put_le(sol, 16, -392'218'940, 4);
  test::put_le(sol, 20, 441'436'102, 4);
  test::put_le(sol, 24, 99, 4);
  test::put_le(sol, 40, 35, 4);  // sAcc cm/s
  sol[47] = 18;
  Decoder d;
  const auto out = test::decode_all(d, ubx(0x06, sol));
  ASSERT_EQ(out.size(), 1U);
  ASSERT_EQ(out[0].kind, MessageKind::kFix);
  const msg::GnssFix& f = out[0].fix;
  EXPECT_NEAR(f.lat_deg, 44.068817081, 1e-8);
  EXPECT_NEAR(f.lon_deg, -121.314317437, 1e-8);
  EXPECT_EQ(f.fix_type, msg::FixType::kTimeOnly);
  EXPECT_EQ(f.satellites, 18U);
  EXPECT_DOUBLE_EQ(f.s_acc_mps, 0.35);
  // 2019-02-07T02:15:17Z: GPS week 2039, 353735 s, less 18 leap seconds.
  EXPECT_EQ(f.utc_ns, 1549505717LL * 1'000'000'000LL);
}

TEST(UbloxDecoder, OlderNavMessagesGiveNoSecondFixWhenNavPvtIsSent) {
  std::vector<std::uint8_t> sol(52, 0);
  test::put_le(sol, 0, 100'000, 4);
  sol[10] = 3;
  sol[11] = 0x0D;
  test::put_le(sol, 12, -238'607'116, 4);
  test::put_le(sol, 16, -392'218'940, 4);
  test::put_le(sol, 20, 441'436'102, 4);
  std::vector<std::uint8_t> bytes;
  const auto pvt = test::nav_pvt_frame({});
  bytes.insert(bytes.end(), pvt.bytes().begin(), pvt.bytes().end());
  const auto s = ubx(0x06, sol);
  bytes.insert(bytes.end(), s.begin(), s.end());
  Decoder d;
  int fixes = 0;
  for (const auto& r : test::decode_all(d, bytes)) {
    if (r.kind == MessageKind::kFix) {
      ++fixes;
      EXPECT_EQ(r.fix.source, msg::GnssSource::kUbxNavPvt);
    }
  }
  EXPECT_EQ(fixes, 1);
}

TEST(UbloxDecoder, MalformedOlderNavMessageIsAFramingError) {
  Decoder d;
  const auto out = test::decode_all(d, ubx(0x06, std::vector<std::uint8_t>(51, 0)));
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(d.stats().framing_errors, 1U);
}

}  // namespace
}  // namespace coxswain::drivers::ublox
