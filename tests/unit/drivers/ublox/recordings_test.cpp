// SPDX-License-Identifier: Apache-2.0
// The decoder against real recordings (the shared test data folder; skipped when absent):
//  * gpsd regression captures: every TPV report with a position in gpsd's .chk must be matched
//    by one of our fixes of the same epoch (time), with tolerances set by gpsd's print precision:
//      lat/lon 1e-8 deg (gpsd prints 9 decimals; ~1 mm), eph vs hAcc 0.0011 m (3 decimals),
//      speed 0.0011 m/s (3 decimals), track 1.1e-4 deg (4 decimals), time 1 ms (gpsd prints
//      milliseconds of NAV-PVT's nano-corrected time).
//  * the long moving rover captures: zero checksum errors and plausible RTK counts.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "coxswain/core/angles.hpp"
#include "coxswain/drivers/ublox/codec.hpp"
#include "support/run_command.hpp"
#include "support/testdata.hpp"
#include "ublox_test_util.hpp"

namespace coxswain::drivers::ublox {
namespace {

constexpr double kLatLonTolDeg = 1e-8;
constexpr double kEphTolM = 0.0011;
constexpr double kSpeedTolMps = 0.0011;
constexpr double kTrackTolDeg = 1.1e-4;
constexpr std::int64_t kTimeTolNs = 1'000'000;
// GPS week-number rollover period: one capture's receiver reports 2015, gpsd "corrects" it.
constexpr std::int64_t k1024WeeksNs = 1024LL * 7 * 86400 * 1'000'000'000LL;

std::vector<std::uint8_t> read_file(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// gpsd .log: skip the leading '#' comment lines (docs/protocols.md 3.10).
std::vector<std::uint8_t> read_gpsd_log(const std::filesystem::path& p) {
  auto bytes = read_file(p);
  std::size_t pos = 0;
  while (pos < bytes.size() && bytes[pos] == '#') {
    while (pos < bytes.size() && bytes[pos] != '\n') ++pos;
    if (pos < bytes.size()) ++pos;
  }
  bytes.erase(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(pos));
  return bytes;
}

std::vector<std::uint8_t> gunzip(const std::filesystem::path& p) {
  bool ok = false;
  std::vector<std::uint8_t> out = coxswain::test::gunzip(p, &ok);
  EXPECT_TRUE(ok) << "gzip -dc " << p;
  return out;
}

struct Tpv {
  std::optional<std::int64_t> time_ns;
  double lat = 0.0;
  double lon = 0.0;
  int mode = 0;
  std::optional<double> eph;
  std::optional<double> speed;
  std::optional<double> track;
  std::string line;
};

std::int64_t parse_iso_time_ns(const std::string& s) {
  int y = 0, mo = 0, d = 0, h = 0, mi = 0;
  double sec = 0.0;
  if (std::sscanf(s.c_str(), "%d-%d-%dT%d:%d:%lfZ", &y, &mo, &d, &h, &mi, &sec) != 6) {
    ADD_FAILURE() << "bad time " << s;
    return 0;
  }
  const std::int64_t days =
      unix_days_from_civil(y, static_cast<unsigned>(mo), static_cast<unsigned>(d));
  return (days * 86400 + h * 3600 + mi * 60) * 1'000'000'000LL + std::llround(sec * 1e9);
}

std::vector<Tpv> read_tpvs_with_position(const std::filesystem::path& chk) {
  std::vector<Tpv> out;
  std::ifstream in(chk);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] != '{') continue;
    const auto j = nlohmann::json::parse(line);
    if (j.value("class", "") != "TPV" || !j.contains("lat") || !j.contains("lon")) continue;
    Tpv t;
    t.line = line;
    t.lat = j["lat"].get<double>();
    t.lon = j["lon"].get<double>();
    t.mode = j.value("mode", 0);
    if (j.contains("time")) t.time_ns = parse_iso_time_ns(j["time"].get<std::string>());
    if (j.contains("eph")) t.eph = j["eph"].get<double>();
    if (j.contains("speed")) t.speed = j["speed"].get<double>();
    if (j.contains("track")) t.track = j["track"].get<double>();
    out.push_back(t);
  }
  return out;
}

// gpsd's TPV mode for our fix. gpsd reports NAV-PVT fixType 5 (time only, surveyed position of
// a timing receiver such as the ZED-F9T) as mode 3 with status 7 ("time").
int gpsd_mode(const msg::GnssFix& f) {
  if (!f.fix_ok) return 1;
  if (f.fix_type == msg::FixType::k3D || f.fix_type == msg::FixType::kGnssDeadReckoning ||
      f.fix_type == msg::FixType::kTimeOnly) {
    return 3;
  }
  if (f.fix_type == msg::FixType::k2D) return 2;
  return 1;
}

bool same_epoch(std::int64_t tpv_ns, std::int64_t fix_ns, bool allow_week_rollover) {
  std::int64_t d = tpv_ns - fix_ns;
  if (allow_week_rollover) {
    const std::int64_t k = (d + k1024WeeksNs / 2) / k1024WeeksNs;
    d -= k * k1024WeeksNs;
  }
  return std::llabs(d) <= kTimeTolNs;
}

struct Capture {
  const char* log;
  bool ubx;                  // NAV-PVT capture (eph = hAcc comparable) vs NMEA
  std::size_t min_tpvs;      // guards against a vacuous pass
  bool allow_week_rollover;  // neo-m8n: receiver says 2015-03-18, gpsd prints 2034-11-01
};

class GpsdComparison : public ::testing::TestWithParam<Capture> {};

TEST_P(GpsdComparison, EveryPositionTpvIsMatched) {
  const Capture c = GetParam();
  COXSWAIN_REQUIRE_TESTDATA(log_path, std::string("gpsd/") + c.log);
  const auto bytes = read_gpsd_log(log_path);
  Decoder d;
  const auto out = test::decode_all(d, bytes, 4096);
  std::vector<msg::GnssFix> fixes;
  for (const auto& r : out) {
    if (r.kind == MessageKind::kFix) fixes.push_back(r.fix);
  }
  EXPECT_EQ(d.stats().checksum_errors, 0U);
  const auto tpvs = read_tpvs_with_position(log_path.string() + ".chk");
  ASSERT_GE(tpvs.size(), c.min_tpvs);
  std::size_t matched = 0;
  for (const Tpv& t : tpvs) {
    const msg::GnssFix* best = nullptr;
    for (const auto& f : fixes) {
      if (c.ubx && f.source != msg::GnssSource::kUbxNavPvt) continue;
      if (t.time_ns && !same_epoch(*t.time_ns, f.utc_ns, c.allow_week_rollover)) continue;
      if (std::abs(f.lat_deg - t.lat) > kLatLonTolDeg) continue;
      if (std::abs(f.lon_deg - t.lon) > kLatLonTolDeg) continue;
      if (gpsd_mode(f) != t.mode) continue;
      best = &f;
      break;
    }
    if (best == nullptr) {
      ADD_FAILURE() << c.log << ": no fix matches TPV " << t.line;
      continue;
    }
    ++matched;
    if (t.speed) {
      EXPECT_NEAR(best->ground_speed_mps, *t.speed, kSpeedTolMps) << t.line;
    }
    if (t.track) {
      EXPECT_NEAR(core::angle_diff_deg(best->course_deg, *t.track), 0.0, kTrackTolDeg) << t.line;
    }
    if (c.ubx && t.eph) {
      EXPECT_NEAR(best->h_acc_m, *t.eph, kEphTolM) << t.line;
    }
  }
  EXPECT_EQ(matched, tpvs.size());
  std::printf("%s: %zu fixes decoded, %zu/%zu position TPVs matched\n", c.log, fixes.size(),
              matched, tpvs.size());
}

INSTANTIATE_TEST_SUITE_P(Ublox, GpsdComparison,
                         ::testing::Values(Capture{"ublox-neo-m8n.log", true, 19, false},
                                           Capture{"ublox-zed-f9p-hp.log", true, 29, false},
                                           Capture{"ublox-zed-f9t-rtcm3.log", true, 26, false},
                                           Capture{"ublox-zed-f9p-nmea.log", false, 29, false},
                                           Capture{"ublox-8.log", false, 72, false},
                                           Capture{"neo-m8n.log", false, 23, true},
                                           // NAV-SOL/POSECEF/VELECEF/TIMEGPS, no NAV-PVT, no
                                           // NMEA (a timing receiver); eph is gpsd's DOP-based.
                                           Capture{"ublox-neo-m8t-s.log", false, 43, false}),
                         [](const ::testing::TestParamInfo<Capture>& param_info) {
                           std::string n = param_info.param.log;
                           for (char& ch : n) {
                             if (ch == '-' || ch == '.') ch = '_';
                           }
                           return n;
                         });

TEST(UbloxRecordings, F9tRtcm3InterleavedFramesAllRecovered) {
  COXSWAIN_REQUIRE_TESTDATA(log_path, "gpsd/ublox-zed-f9t-rtcm3.log");
  Decoder d;
  const auto out = test::decode_all(d, read_gpsd_log(log_path), 512);
  std::map<std::uint16_t, int> rtcm;
  int pvt = 0;
  for (const auto& r : out) {
    if (r.kind == MessageKind::kRtcm3) ++rtcm[r.rtcm_type];
    if (r.kind == MessageKind::kFix) ++pvt;
  }
  // docs/protocols.md 3.12: 1005, 1077, 1087, 1097, 1127, 1230, 4072 x 26 each; NAV-PVT x 26.
  for (const int type : {1005, 1077, 1087, 1097, 1127, 1230, 4072}) {
    EXPECT_EQ(rtcm[static_cast<std::uint16_t>(type)], 26) << type;
  }
  EXPECT_EQ(rtcm.size(), 7U);
  EXPECT_EQ(pvt, 26);
  EXPECT_EQ(d.stats().checksum_errors, 0U);

  // The stand-alone framer finds the same 182 frames in the same stream.
  Rtcm3Framer framer;
  const auto bytes = read_gpsd_log(log_path);
  std::span<const std::uint8_t> rest = bytes;
  int frames = 0;
  while (!rest.empty()) {
    const DecodeStep step = framer.decode(rest);
    rest = rest.subspan(step.consumed);
    if (step.produced) ++frames;
  }
  while (framer.decode({}).produced) ++frames;
  EXPECT_EQ(frames, 182);
}

TEST(UbloxRecordings, NeoM8tAckIsDecoded) {
  COXSWAIN_REQUIRE_TESTDATA(log_path, "gpsd/ublox-neo-m8t-s.log");
  Decoder d;
  const auto out = test::decode_all(d, read_gpsd_log(log_path));
  int acks = 0;
  for (const auto& r : out) {
    if (r.kind == MessageKind::kAck) {
      ++acks;
      EXPECT_EQ(r.ubx, (UbxId{0x06, 0x3D}));  // CFG-TMODE2
    }
  }
  EXPECT_EQ(acks, 1);
  EXPECT_EQ(d.stats().checksum_errors, 0U);
}

struct RoverCounts {
  int nav_pvt = 0, pvt_fixed = 0, pvt_float = 0;
  int gga = 0, gga_fixed = 0, gga_float = 0, gga_single = 0;
  int hpposllh = 0;
  bool pvt_time_monotonic = true;
};

RoverCounts count_rover(const std::vector<test::Record>& out) {
  RoverCounts c;
  std::int64_t last_utc = 0;
  for (const auto& r : out) {
    if (r.kind == MessageKind::kHpPosLlh) ++c.hpposllh;
    if (r.kind != MessageKind::kFix) continue;
    const msg::GnssFix& f = r.fix;
    if (f.source == msg::GnssSource::kUbxNavPvt) {
      ++c.nav_pvt;
      if (f.rtk == msg::RtkSolution::kFixed) ++c.pvt_fixed;
      if (f.rtk == msg::RtkSolution::kFloat) ++c.pvt_float;
      if (f.utc_ns != 0) {
        if (f.utc_ns <= last_utc) c.pvt_time_monotonic = false;
        last_utc = f.utc_ns;
      }
    } else if (f.source == msg::GnssSource::kNmeaGga) {
      ++c.gga;
      if (f.rtk == msg::RtkSolution::kFixed) ++c.gga_fixed;
      if (f.rtk == msg::RtkSolution::kFloat) ++c.gga_float;
      if (f.fix_ok && !f.diff_soln) ++c.gga_single;
    }
  }
  return c;
}

TEST(UbloxRecordings, M8pRoverRtkCounts) {
  COXSWAIN_REQUIRE_TESTDATA(gz_path, "gnss/ublox-m8p_rover-20181104-1634.ubx.gz");
  const auto bytes = gunzip(gz_path);
  ASSERT_GT(bytes.size(), 1'000'000U);
  Decoder d;
  const RoverCounts c = count_rover(test::decode_all(d, bytes, 4096));
  EXPECT_EQ(d.stats().checksum_errors, 0U);
  // README: GGA quality 4 = 2265, 5 = 1121, 1 = 834 in this recording.
  EXPECT_EQ(c.gga_fixed, 2265);
  EXPECT_EQ(c.gga_float, 1121);
  EXPECT_EQ(c.gga_single, 834);
  EXPECT_TRUE(c.pvt_time_monotonic);
  std::printf(
      "M8P rover: %zu bytes, GGA %d (fixed %d, float %d), NAV-PVT %d (fixed %d, float %d), "
      "frames_ok %llu, skipped %llu, framing errors %llu\n",
      bytes.size(), c.gga, c.gga_fixed, c.gga_float, c.nav_pvt, c.pvt_fixed, c.pvt_float,
      static_cast<unsigned long long>(d.stats().frames_ok),
      static_cast<unsigned long long>(d.stats().bytes_skipped),
      static_cast<unsigned long long>(d.stats().framing_errors));

  // The NMEA sentences extracted from the same drive give the same GGA counts.
  COXSWAIN_REQUIRE_TESTDATA(nmea_path, "gnss/ublox-m8p_rover-20181104-1634.nmea");
  Decoder dn;
  const RoverCounts n = count_rover(test::decode_all(dn, read_file(nmea_path), 4096));
  EXPECT_EQ(dn.stats().checksum_errors, 0U);
  EXPECT_EQ(n.gga_fixed, 2265);
  EXPECT_EQ(n.gga_float, 1121);
  EXPECT_EQ(n.gga, c.gga);
}

TEST(UbloxRecordings, F9RoverMostlyRtkFixed) {
  COXSWAIN_REQUIRE_TESTDATA(gz_path, "gnss/ublox-f9p_rover-20190416-1617.ubx.gz");
  const auto bytes = gunzip(gz_path);
  ASSERT_GT(bytes.size(), 1'000'000U);
  Decoder d;
  const RoverCounts c = count_rover(test::decode_all(d, bytes, 4096));
  EXPECT_EQ(d.stats().checksum_errors, 0U);
  // README: 23 min of NAV-PVT at ~4 Hz (~5500), mostly RTK fixed.
  EXPECT_GT(c.nav_pvt, 4000);
  EXPECT_LT(c.nav_pvt, 7000);
  EXPECT_GT(c.pvt_fixed, c.nav_pvt / 2);
  EXPECT_TRUE(c.pvt_time_monotonic);
  std::printf(
      "F9 rover: %zu bytes, NAV-PVT %d (fixed %d, float %d), HPPOSLLH %d, frames_ok %llu, "
      "skipped %llu, framing errors %llu\n",
      bytes.size(), c.nav_pvt, c.pvt_fixed, c.pvt_float, c.hpposllh,
      static_cast<unsigned long long>(d.stats().frames_ok),
      static_cast<unsigned long long>(d.stats().bytes_skipped),
      static_cast<unsigned long long>(d.stats().framing_errors));
}

}  // namespace
}  // namespace coxswain::drivers::ublox
