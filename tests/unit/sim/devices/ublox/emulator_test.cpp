// SPDX-License-Identifier: Apache-2.0
// The u-blox receiver emulator core checked through the production decoder: golden frames from
// docs/protocols.md 3.2/3.6/3.7, ACK/NAK rules per model, split-anywhere host input, epochs at the
// configured rate decoding to the truth (UBX and NMEA), faults, RTCM counting and capture replay.
#include "sim/devices/ublox/emulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "coxswain/drivers/ublox/codec.hpp"
#include "coxswain/drivers/ublox/config.hpp"
#include "support/testdata.hpp"

namespace coxswain::sim::devices::ublox {
namespace {

namespace ub = drivers::ublox;
using Bytes = std::vector<std::uint8_t>;
constexpr core::TimeNs kMs = core::kNsPerMs;

Bytes hex(std::string_view h) {
  Bytes out;
  int hi = -1;
  for (const char c : h) {
    int v = -1;
    if (c >= '0' && c <= '9') v = c - '0';
    if (c >= 'A' && c <= 'F') v = c - 'A' + 10;
    if (c >= 'a' && c <= 'f') v = c - 'a' + 10;
    if (v < 0) continue;
    if (hi < 0) {
      hi = v;
    } else {
      out.push_back(static_cast<std::uint8_t>(hi * 16 + v));
      hi = -1;
    }
  }
  return out;
}

Bytes bytes_of(std::span<const std::uint8_t> s) { return {s.begin(), s.end()}; }

struct Decoded {
  std::vector<ub::Message> acks;  // kind kAck/kNak with ubx
  std::vector<msg::GnssFix> fixes;
  std::uint64_t checksum_errors = 0;
};

Decoded decode(std::span<const std::uint8_t> bytes) {
  ub::Decoder d;
  Decoded out;
  while (true) {
    const auto step = d.decode(bytes);
    bytes = bytes.subspan(step.consumed);
    if (step.produced) {
      const auto& m = d.message();
      if (m.kind == ub::MessageKind::kAck || m.kind == ub::MessageKind::kNak) out.acks.push_back(m);
      if (m.kind == ub::MessageKind::kFix) out.fixes.push_back(m.fix);
      continue;
    }
    if (bytes.empty()) break;
  }
  out.checksum_errors = d.stats().checksum_errors;
  return out;
}

TEST(UbloxEmulator, AnswersTheProtocolDocumentsGoldenFramesWithAckAck) {
  Emulator e2;  // F9
  // docs/protocols.md 3.7: CFG-RATE 5 Hz GPS time, answered first thing (before the t = 0 epoch's
  // NMEA) with ACK-ACK for 06 08 (Fletcher worked by hand as for the doc's 06 3D example).
  e2.receive(hex("B5 62 06 08 06 00 C8 00 01 00 01 00 DE 6A"), 0);
  const Bytes out = bytes_of(e2.poll(0));
  ASSERT_GE(out.size(), 10U);
  EXPECT_EQ(Bytes(out.begin(), out.begin() + 10), hex("B5 62 05 01 02 00 06 08 16 3F"));
  EXPECT_EQ(e2.meas_period_ms(), 200);
  // docs/protocols.md 3.7: CFG-MSG NAV-PVT every epoch; 3.6: VALSET 10 Hz and NAV-PVT on USB.
  e2.receive(hex("B5 62 06 01 03 00 01 07 01 13 51"), 0);
  e2.receive(hex("B5 62 06 8A 0A 00 00 01 00 00 01 00 21 30 64 00 51 B9"), 0);
  e2.receive(hex("B5 62 06 8A 09 00 00 01 00 00 09 00 91 20 01 55 52"), 0);
  const auto d = decode(e2.poll(0));
  ASSERT_EQ(d.acks.size(), 3U);
  for (const auto& m : d.acks) EXPECT_EQ(m.kind, ub::MessageKind::kAck);
  EXPECT_EQ(d.acks[0].ubx, ub::kCfgMsg);
  EXPECT_EQ(d.acks[1].ubx, ub::kCfgValset);
  EXPECT_EQ(e2.meas_period_ms(), 100);
  EXPECT_EQ(e2.nav_pvt_rate(), 1);
  EXPECT_EQ(e2.stats().acks, 4U);
}

TEST(UbloxEmulator, NaksMalformedAndUnsupportedAndIgnoresBadChecksums) {
  Emulator f9;
  // CFG-RATE with 5 payload bytes.
  f9.receive(ub::make_ubx_frame(ub::kCfgRate, Bytes{0x64, 0, 1, 0, 1}).bytes(), 0);
  // CFG-RATE with measRate 10 ms (impossible).
  f9.receive(ub::m8_set_rate(10).bytes(), 0);
  // VALSET with an unknown key (and a valid one): NAKed as a whole, nothing applied.
  ub::ValsetBuilder b;
  ASSERT_TRUE(b.add(ub::key::kRateMeas, 250));
  ASSERT_TRUE(b.add(0x20910999, 1));
  f9.receive(b.build().bytes(), 0);
  // CFG-CFG (06 09): not emulated.
  f9.receive(ub::make_ubx_frame(ub::UbxId{0x06, 0x09}, Bytes(12, 0)).bytes(), 0);
  // A good frame with a bad checksum: no answer at all.
  Bytes bad = bytes_of(ub::m8_set_rate(200).bytes());
  bad.back() ^= 0x01;
  f9.receive(bad, 0);
  // Non-CFG input: no answer (only CFG is acknowledged).
  f9.receive(ub::make_ubx_frame(ub::UbxId{0x0A, 0x04}, {}).bytes(), 0);
  const auto d = decode(f9.poll(0));
  ASSERT_EQ(d.acks.size(), 4U);
  for (const auto& m : d.acks) EXPECT_EQ(m.kind, ub::MessageKind::kNak);
  EXPECT_EQ(f9.meas_period_ms(), 1000);  // unchanged power-on 1 Hz
  EXPECT_EQ(f9.stats().host_bad_frames, 1U);

  Emulator m8(EmulatorConfig{.model = Model::kM8});
  m8.receive(ub::f9_set_meas_period(100).bytes(), 0);  // M8 (protocol < 27) has no VALSET
  m8.receive(ub::m8_set_rate(100).bytes(), 0);
  m8.receive(ub::m8_set_dyn_model(ub::kDynModelSea).bytes(), 0);
  const auto d8 = decode(m8.poll(0));
  ASSERT_EQ(d8.acks.size(), 3U);
  EXPECT_EQ(d8.acks[0].kind, ub::MessageKind::kNak);
  EXPECT_EQ(d8.acks[1].kind, ub::MessageKind::kAck);
  EXPECT_EQ(d8.acks[2].kind, ub::MessageKind::kAck);
  EXPECT_EQ(m8.meas_period_ms(), 100);
  EXPECT_EQ(m8.dyn_model(), ub::kDynModelSea);
}

TEST(UbloxEmulator, HostInputSplitAnywhereGivesTheSameAnswers) {
  const auto plan = ub::make_config_plan(ub::Generation::kF9, ub::ConfigParams{});
  Bytes all;
  for (const auto& s : plan.view())
    all.insert(all.end(), s.frame.bytes().begin(), s.frame.bytes().end());
  Emulator whole;
  whole.receive(all, 0);
  const Bytes expected = bytes_of(whole.poll(0));
  ASSERT_EQ(decode(expected).acks.size(), plan.count);
  for (std::size_t chunk : {1U, 2U, 5U, 13U}) {
    Emulator e;
    for (std::size_t o = 0; o < all.size(); o += chunk) {
      e.receive(std::span(all).subspan(o, std::min(chunk, all.size() - o)), 0);
    }
    EXPECT_EQ(bytes_of(e.poll(0)), expected) << chunk;
  }
}

msg::GnssFix truth() {
  msg::GnssFix t;
  t.fix_type = msg::FixType::k3D;
  t.fix_ok = true;
  t.rtk = msg::RtkSolution::kFloat;
  t.diff_soln = true;
  t.lat_deg = -33.8688197;
  t.lon_deg = 151.2092955;
  t.height_msl_m = 5.25;
  t.h_acc_m = 0.35;
  t.v_acc_m = 0.5;
  t.hdop = 1.1;
  t.satellites = 17;
  t.vel_north_mps = -0.5;
  t.vel_east_mps = -0.5;
  t.vel_down_mps = 0.0;
  t.ground_speed_mps = std::hypot(0.5, 0.5);
  t.course_deg = -135.0;
  t.utc_ns = (ub::unix_days_from_civil(2025, 12, 31) * 86400 + 23 * 3600 + 59 * 60 + 59) *
                 core::kNsPerSec +
             900 * kMs;
  return t;
}

TEST(UbloxEmulator, PowerOnIsNmeaOnlyAtOneHertzAndDecodesToTheTruth) {
  Emulator e(EmulatorConfig{.model = Model::kM8});
  e.set_truth(truth());
  Bytes out;
  for (core::TimeNs t = 0; t <= 3'000 * kMs; t += 50 * kMs) {
    const auto o = e.poll(t);
    out.insert(out.end(), o.begin(), o.end());
  }
  const auto d = decode(out);
  EXPECT_EQ(e.stats().epochs, 4U);  // t = 0, 1, 2, 3 s
  EXPECT_EQ(e.stats().nav_pvt_sent, 0U);
  ASSERT_EQ(d.fixes.size(), 8U);  // RMC + GGA per epoch
  const msg::GnssFix& gga = d.fixes[1];
  const msg::GnssFix t = truth();
  EXPECT_EQ(d.fixes[0].source, msg::GnssSource::kNmeaRmc);
  EXPECT_EQ(gga.source, msg::GnssSource::kNmeaGga);
  EXPECT_NEAR(gga.lat_deg, t.lat_deg, 2e-7);  // 1e-5 minute
  EXPECT_NEAR(gga.lon_deg, t.lon_deg, 2e-7);
  EXPECT_EQ(gga.rtk, msg::RtkSolution::kFloat);
  EXPECT_EQ(gga.satellites, 17);
  EXPECT_NEAR(gga.hdop, 1.1, 1e-9);
  EXPECT_NEAR(gga.height_msl_m, 5.25, 0.051);
  EXPECT_NEAR(gga.ground_speed_mps, t.ground_speed_mps, 1e-3);
  EXPECT_NEAR(gga.course_deg, t.course_deg, 0.006);
  EXPECT_EQ(gga.utc_ns, t.utc_ns);  // .90 s survives the 2-decimal time field
}

TEST(UbloxEmulator, NavPvtAtTheConfiguredRateCarriesEveryDecodedField) {
  Emulator e;
  e.receive(ub::f9_set_meas_period(50).bytes(), 0);                          // 20 Hz
  e.receive(ub::f9_set_output_protocols(ub::Port::kUsb, false).bytes(), 0);  // NMEA off
  e.receive(ub::f9_set_nav_pvt_output(ub::Port::kUsb, 1).bytes(), 0);
  (void)e.poll(0);  // answers (and the t = 0 epoch)
  e.set_truth(truth());
  Bytes out;
  for (core::TimeNs t = 10 * kMs; t <= 1'000 * kMs; t += 10 * kMs) {
    const auto o = e.poll(t);
    out.insert(out.end(), o.begin(), o.end());
  }
  const auto d = decode(out);
  ASSERT_EQ(d.fixes.size(), 20U);
  const msg::GnssFix t = truth();
  for (const auto& f : d.fixes) {
    EXPECT_EQ(f.source, msg::GnssSource::kUbxNavPvt);
    EXPECT_EQ(f.fix_type, msg::FixType::k3D);
    EXPECT_TRUE(f.fix_ok);
    EXPECT_TRUE(f.diff_soln);
    EXPECT_EQ(f.rtk, msg::RtkSolution::kFloat);
    EXPECT_NEAR(f.lat_deg, t.lat_deg, 1e-7);
    EXPECT_NEAR(f.lon_deg, t.lon_deg, 1e-7);
    EXPECT_NEAR(f.h_acc_m, t.h_acc_m, 1e-3);
    EXPECT_NEAR(f.v_acc_m, t.v_acc_m, 1e-3);
    EXPECT_EQ(f.satellites, t.satellites);
    EXPECT_NEAR(f.vel_north_mps, t.vel_north_mps, 1e-3);
    EXPECT_NEAR(f.ground_speed_mps, t.ground_speed_mps, 1e-3);
    EXPECT_NEAR(f.course_deg, t.course_deg, 1e-5);
    EXPECT_EQ(f.utc_ns, t.utc_ns);
    // iTOW from UTC: GPS = UTC + 18 s; 2025-12-31 is a Wednesday.
    EXPECT_EQ(f.itow_ms,
              ((3 * 86400 + 23 * 3600 + 59 * 60 + 59 + 18) * 1000 + 900) % (7 * 86400 * 1000));
  }
  // Run-time rate change: 20 Hz -> 4 Hz.
  e.set_rate_hz(4.0);
  out.clear();
  for (core::TimeNs now = 1'010 * kMs; now <= 3'000 * kMs; now += 10 * kMs) {
    const auto o = e.poll(now);
    out.insert(out.end(), o.begin(), o.end());
  }
  EXPECT_NEAR(static_cast<double>(decode(out).fixes.size()), 8.0, 1.0);
}

TEST(UbloxEmulator, FaultsCorruptGarbleAndSilence) {
  EmulatorConfig c;
  c.faults.corrupt_checksum_probability = 0.5;
  c.faults.garbage_probability = 0.5;
  c.faults.seed = 7;
  Emulator e(c);
  e.set_truth(truth());
  Bytes out;
  for (core::TimeNs t = 0; t <= 40'000 * kMs; t += 100 * kMs) {
    const auto o = e.poll(t);
    out.insert(out.end(), o.begin(), o.end());
  }
  const auto d = decode(out);
  EXPECT_GT(e.stats().corrupted_messages, 10U);
  EXPECT_GT(e.stats().garbage_bursts, 5U);
  // Every corrupted sentence is rejected (garbage may add a few more rejections of its own).
  EXPECT_GE(d.checksum_errors, e.stats().corrupted_messages);
  EXPECT_EQ(d.fixes.size(), e.stats().nmea_sent - e.stats().corrupted_messages);
  for (const auto& f : d.fixes) EXPECT_NEAR(f.lat_deg, truth().lat_deg, 2e-7);
  // Silence: nothing at all, answers included.
  EmulatorFaults quiet;
  quiet.silent = true;
  e.set_faults(quiet);
  e.receive(ub::m8_set_rate(200).bytes(), 0);
  EXPECT_TRUE(e.poll(50'000 * kMs).empty());
  EXPECT_EQ(e.meas_period_ms(), 200);  // the receiver still obeys
}

Bytes rtcm(std::uint16_t type, std::size_t n) {
  Bytes f{ub::kRtcm3Preamble, static_cast<std::uint8_t>(n >> 8), static_cast<std::uint8_t>(n)};
  for (std::size_t i = 0; i < n; ++i) f.push_back(static_cast<std::uint8_t>(i));
  f[3] = static_cast<std::uint8_t>(type >> 4);
  f[4] = static_cast<std::uint8_t>((type & 0x0F) << 4);
  const std::uint32_t crc = ub::crc24q(f);
  f.push_back(static_cast<std::uint8_t>(crc >> 16));
  f.push_back(static_cast<std::uint8_t>(crc >> 8));
  f.push_back(static_cast<std::uint8_t>(crc));
  return f;
}

TEST(UbloxEmulator, CountsRtcmFramesInterleavedWithCommands) {
  Emulator e;
  Bytes in = rtcm(1005, 19);
  const auto cmd = ub::m8_set_rate(200);
  in.insert(in.end(), cmd.bytes().begin(), cmd.bytes().end());
  Bytes bad = rtcm(1077, 100);
  bad[20] ^= 0x40;
  in.insert(in.end(), bad.begin(), bad.end());
  const Bytes good = rtcm(1087, 200);
  in.insert(in.end(), good.begin(), good.end());
  for (std::size_t o = 0; o < in.size(); o += 7) {
    e.receive(std::span(in).subspan(o, std::min<std::size_t>(7, in.size() - o)), 0);
  }
  EXPECT_EQ(e.stats().rtcm_frames, 2U);
  EXPECT_EQ(e.stats().rtcm_bytes, 25U + good.size());
  EXPECT_EQ(e.stats().acks, 1U);
}

TEST(UbloxEmulator, ReplaysACapturePacedByItow) {
  // Synthetic capture: NAV-PVT at iTOW 1000, 1200, 1400 ms.
  Bytes cap;
  for (int i = 0; i < 3; ++i) {
    Bytes p(92, 0);
    const std::uint32_t itow = 1000 + 200 * static_cast<std::uint32_t>(i);
    for (int k = 0; k < 4; ++k)
      p[static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(itow >> (8 * k));
    p[20] = 3;
    p[21] = 1;
    const auto f = ub::make_ubx_frame(ub::kNavPvt, p);
    cap.insert(cap.end(), f.bytes().begin(), f.bytes().end());
  }
  const Capture capture(cap);
  ASSERT_EQ(capture.frames().size(), 3U);
  EXPECT_EQ(capture.frames()[1].at_ns, 200 * kMs);
  EXPECT_EQ(capture.duration_ns(), 400 * kMs);
  Emulator e;
  e.play_capture(&capture);
  const core::TimeNs t0 = 7'000 * kMs;
  EXPECT_EQ(decode(e.poll(t0)).fixes.size(), 1U);
  EXPECT_EQ(decode(e.poll(t0 + 150 * kMs)).fixes.size(), 0U);
  EXPECT_EQ(decode(e.poll(t0 + 200 * kMs)).fixes.size(), 1U);
  EXPECT_FALSE(e.capture_finished());
  const auto last = decode(e.poll(t0 + 500 * kMs));
  ASSERT_EQ(last.fixes.size(), 1U);
  EXPECT_EQ(last.fixes[0].itow_ms, 1400U);
  EXPECT_TRUE(e.capture_finished());
  // Commands are still answered during a replay.
  e.receive(ub::m8_set_rate(200).bytes(), t0);
  EXPECT_EQ(decode(e.poll(t0 + 600 * kMs)).acks.size(), 1U);
}

std::string nmea(std::string_view body) {
  unsigned x = 0;
  for (const char c : body) x ^= static_cast<unsigned char>(c);
  char tail[8];
  std::snprintf(tail, sizeof tail, "*%02X\r\n", x);
  return "$" + std::string(body) + tail;
}

TEST(UbloxEmulator, NmeaOnlyCaptureIsPacedByUtcAcrossMidnightAndSkipsJunk) {
  Bytes cap{0x00, 0xB5, 0x62, 0x13};  // junk, including a false UBX start
  for (const char* tod : {"235959.50", "000000.50", "000001.50"}) {
    const std::string rmc =
        nmea(std::string("GPRMC,") + tod + ",A,3506.0,N,12648.0,E,0.1,0.0,010126,,,A");
    const std::string gga =
        nmea(std::string("GPGGA,") + tod + ",3506.0,N,12648.0,E,1,08,1.0,5.0,M,0,M,,");
    const std::string txt = nmea("GPTXT,01,01,02,untimed");
    for (const std::string* line : {&rmc, &gga, &txt})
      cap.insert(cap.end(), line->begin(), line->end());
    cap.push_back(0xD3);  // a false RTCM start between epochs
  }
  const Capture capture(cap);
  ASSERT_EQ(capture.frames().size(), 9U);
  EXPECT_EQ(capture.frames()[0].at_ns, 0);
  EXPECT_EQ(capture.frames()[2].at_ns, 0);            // GPTXT inherits its epoch's time
  EXPECT_EQ(capture.frames()[3].at_ns, 1'000 * kMs);  // across midnight
  EXPECT_EQ(capture.frames()[8].at_ns, 2'000 * kMs);
  for (const auto& f : capture.frames()) EXPECT_EQ(capture.bytes(f)[0], '$');
}

TEST(UbloxEmulatorRecordings, ReplaysTheGpsdNeoM8nCaptureByteExactPacedByItow) {
  COXSWAIN_REQUIRE_TESTDATA(path, "gpsd/ublox-neo-m8n.log");
  std::ifstream in(path, std::ios::binary);
  Bytes bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  std::size_t pos = 0;  // skip gpsd's '#' header lines
  while (pos < bytes.size() && bytes[pos] == '#') {
    while (pos < bytes.size() && bytes[pos] != '\n') ++pos;
    ++pos;
  }
  bytes.erase(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(pos));
  const Capture capture(bytes);
  ub::Decoder ref;
  std::vector<msg::GnssFix> ref_fixes;
  std::span<const std::uint8_t> rest = bytes;
  while (!rest.empty()) {
    const auto s = ref.decode(rest);
    rest = rest.subspan(s.consumed);
    if (s.produced && ref.message().kind == ub::MessageKind::kFix)
      ref_fixes.push_back(ref.message().fix);
  }
  ASSERT_EQ(ref_fixes.size(), 24U);  // docs/protocols.md 3.12: NAV-PVT x24
  // The capture spans the iTOW range of its NAV-PVT frames (5 Hz here).
  EXPECT_EQ(capture.duration_ns(),
            core::ms_to_ns(ref_fixes.back().itow_ms - ref_fixes.front().itow_ms));
  Emulator e;
  e.play_capture(&capture);
  Bytes out;
  std::vector<core::TimeNs> released_at;  // poll time at which each fix first appeared
  constexpr core::TimeNs kStep = 50 * kMs;
  const core::TimeNs t0 = 3'000 * kMs;
  for (core::TimeNs t = t0; t <= t0 + capture.duration_ns() + kStep; t += kStep) {
    const auto o = e.poll(t);
    out.insert(out.end(), o.begin(), o.end());
    const std::size_t n = decode(out).fixes.size();
    while (released_at.size() < n) released_at.push_back(t);
  }
  EXPECT_TRUE(e.capture_finished());
  EXPECT_EQ(out, bytes_of(std::span(bytes).subspan(capture.frames().front().offset,
                                                   capture.frames().back().offset +
                                                       capture.frames().back().size -
                                                       capture.frames().front().offset)));
  const auto d = decode(out);
  ASSERT_EQ(d.fixes.size(), ref_fixes.size());
  for (std::size_t i = 0; i < d.fixes.size(); ++i) {
    EXPECT_EQ(d.fixes[i].itow_ms, ref_fixes[i].itow_ms);
    EXPECT_EQ(d.fixes[i].lat_deg, ref_fixes[i].lat_deg);
    // Paced by iTOW: released within one poll step after its time.
    const core::TimeNs due = t0 + core::ms_to_ns(ref_fixes[i].itow_ms - ref_fixes[0].itow_ms);
    EXPECT_GE(released_at[i], due) << i;
    EXPECT_LT(released_at[i], due + kStep) << i;
  }
}

}  // namespace
}  // namespace coxswain::sim::devices::ublox
