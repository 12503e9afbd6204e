// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/ublox/codec.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <numbers>

#include "coxswain/core/angles.hpp"

namespace coxswain::drivers::ublox {
namespace {

constexpr std::size_t kUbxOverhead = 8;    // sync(2) + class + id + length(2) + checksum(2)
constexpr std::size_t kRtcm3Overhead = 6;  // preamble + length(2) + CRC(3)
constexpr std::int64_t kMsPerDay = 86'400'000;
constexpr double kKnotsToMps = 1852.0 / 3600.0;

std::uint16_t get_u2(std::span<const std::uint8_t> p, std::size_t off) {
  return static_cast<std::uint16_t>(p[off] | (p[off + 1] << 8));
}
std::uint32_t get_u4(std::span<const std::uint8_t> p, std::size_t off) {
  return static_cast<std::uint32_t>(p[off]) | (static_cast<std::uint32_t>(p[off + 1]) << 8) |
         (static_cast<std::uint32_t>(p[off + 2]) << 16) |
         (static_cast<std::uint32_t>(p[off + 3]) << 24);
}
std::int32_t get_i4(std::span<const std::uint8_t> p, std::size_t off) {
  return static_cast<std::int32_t>(get_u4(p, off));
}
std::int8_t get_i1(std::span<const std::uint8_t> p, std::size_t off) {
  return static_cast<std::int8_t>(p[off]);
}

int hex_value(std::uint8_t c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

// ---- NMEA field helpers (no allocation: string_views into the frame) ----

constexpr std::size_t kMaxNmeaFields = 32;
struct NmeaFields {
  std::array<std::string_view, kMaxNmeaFields> f{};
  std::size_t count = 0;
  [[nodiscard]] std::string_view at(std::size_t i) const {
    return i < count ? f[i] : std::string_view{};
  }
};

bool parse_double(std::string_view s, double& out) {
  if (s.empty()) return false;
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, out);
  return ec == std::errc{} && ptr == end && std::isfinite(out);
}

bool parse_uint(std::string_view s, unsigned& out) {
  if (s.empty()) return false;
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, out);
  return ec == std::errc{} && ptr == end;
}

// "hhmmss.ss" -> milliseconds of the UTC day.
bool parse_tod_ms(std::string_view s, std::int64_t& tod_ms) {
  if (s.size() < 6) return false;
  unsigned hh = 0;
  unsigned mm = 0;
  double ss = 0.0;
  if (!parse_uint(s.substr(0, 2), hh) || !parse_uint(s.substr(2, 2), mm) ||
      !parse_double(s.substr(4), ss)) {
    return false;
  }
  if (hh > 23 || mm > 59 || ss < 0.0 || ss >= 61.0) return false;
  tod_ms = (static_cast<std::int64_t>(hh) * 3600 + static_cast<std::int64_t>(mm) * 60) * 1000 +
           std::llround(ss * 1000.0);
  return true;
}

// "ddmm.mmmm" + hemisphere -> signed degrees.
bool parse_coord(std::string_view value, std::string_view hemi, double max_deg, double& deg) {
  double v = 0.0;
  if (!parse_double(value, v) || v < 0.0) return false;
  const double whole_deg = std::floor(v / 100.0);
  const double minutes = v - whole_deg * 100.0;
  if (minutes >= 60.0) return false;
  deg = whole_deg + minutes / 60.0;
  if (deg > max_deg) return false;
  if (hemi == "S" || hemi == "W") {
    deg = -deg;
  } else if (hemi != "N" && hemi != "E") {
    return false;
  }
  return true;
}

std::int64_t utc_ns_from_ms(std::int64_t days, std::int64_t tod_ms) {
  return (days * kMsPerDay + tod_ms) * core::kNsPerMs;
}

}  // namespace

std::array<std::uint8_t, 2> ubx_checksum(std::span<const std::uint8_t> bytes) {
  unsigned a = 0;
  unsigned b = 0;
  for (const std::uint8_t v : bytes) {
    a = (a + v) & 0xFFU;
    b = (b + a) & 0xFFU;
  }
  return {static_cast<std::uint8_t>(a), static_cast<std::uint8_t>(b)};
}

std::uint32_t crc24q(std::span<const std::uint8_t> bytes) {
  // Table-free bitwise form; RTCM frames are short and this runs once per frame.
  std::uint32_t crc = 0;
  for (const std::uint8_t v : bytes) {
    crc ^= static_cast<std::uint32_t>(v) << 16;
    for (int bit = 0; bit < 8; ++bit) {
      crc <<= 1;
      if ((crc & 0x1000000U) != 0) crc ^= 0x1864CFBU;
    }
  }
  return crc & 0xFFFFFFU;
}

std::int64_t unix_days_from_civil(int year, unsigned month, unsigned day) {
  // Howard Hinnant's days_from_civil.
  const std::int64_t y = static_cast<std::int64_t>(year) - (month <= 2 ? 1 : 0);
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const auto yoe = static_cast<std::int64_t>(y - era * 400);
  const auto m = static_cast<std::int64_t>(month);
  const std::int64_t doy =
      (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + static_cast<std::int64_t>(day) - 1;
  const std::int64_t doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + doe - 719468;
}

std::uint16_t rtcm3_message_type(std::span<const std::uint8_t> frame) {
  if (frame.size() < kRtcm3Overhead + 2) return 0;
  return static_cast<std::uint16_t>((frame[3] << 4) | (frame[4] >> 4));
}

// ------------------------------------ FrameScanner ------------------------------------------

bool FrameScanner::is_start(std::uint8_t b) const {
  return (b == kUbxSync1 && mask_.ubx) || (b == '$' && mask_.nmea) ||
         (b == kRtcm3Preamble && mask_.rtcm3);
}

void FrameScanner::drop_front(std::size_t n) {
  n = std::min(n, len_);
  if (n == 0) return;
  std::memmove(buf_.data(), buf_.data() + n, len_ - n);
  len_ -= n;
}

FrameScanner::Verdict FrameScanner::assess(std::size_t& need) const {
  const std::uint8_t first = buf_[0];
  if (first == kUbxSync1) {
    need = 6;
    if (len_ >= 2 && buf_[1] != kUbxSync2) return Verdict::kBad;
    if (len_ < 6) return Verdict::kNeedMore;
    const std::size_t payload = get_u2(buf_, 4);
    if (payload + kUbxOverhead > kMaxFrameBytes) return Verdict::kBad;
    need = payload + kUbxOverhead;
    if (len_ < need) return Verdict::kNeedMore;
    const auto ck = ubx_checksum(std::span<const std::uint8_t>(buf_.data() + 2, payload + 4));
    if (ck[0] != buf_[need - 2] || ck[1] != buf_[need - 1]) return Verdict::kBadChecksum;
    return Verdict::kComplete;
  }
  if (first == kRtcm3Preamble) {
    need = 3;
    if (len_ >= 2 && (buf_[1] & 0xFCU) != 0) return Verdict::kBad;
    if (len_ < 3) return Verdict::kNeedMore;
    const std::size_t payload = static_cast<std::size_t>(((buf_[1] & 0x03U) << 8) | buf_[2]);
    need = payload + kRtcm3Overhead;
    if (len_ < need) return Verdict::kNeedMore;
    const std::uint32_t crc = crc24q(std::span<const std::uint8_t>(buf_.data(), payload + 3));
    const std::uint32_t got = (static_cast<std::uint32_t>(buf_[need - 3]) << 16) |
                              (static_cast<std::uint32_t>(buf_[need - 2]) << 8) | buf_[need - 1];
    return crc == got ? Verdict::kComplete : Verdict::kBadChecksum;
  }
  // NMEA: '$' printable... '*' hex hex [CR] LF. Any other byte, a second '$' or no LF within
  // kMaxNmeaBytes is a framing error, so garbage that happens to contain '$' is dropped quickly.
  std::size_t star = 0;
  for (std::size_t i = 1; i < len_; ++i) {
    const std::uint8_t c = buf_[i];
    if (c == '\n') {
      need = i + 1;
      std::size_t end = i;  // exclusive end of "*hh"
      if (buf_[end - 1] == '\r') --end;
      if (star == 0 || end != star + 3) return Verdict::kBad;
      const int hi = hex_value(buf_[star + 1]);
      const int lo = hex_value(buf_[star + 2]);
      if (hi < 0 || lo < 0) return Verdict::kBad;
      std::uint8_t x = 0;
      for (std::size_t k = 1; k < star; ++k) x = static_cast<std::uint8_t>(x ^ buf_[k]);
      return x == static_cast<std::uint8_t>(hi * 16 + lo) ? Verdict::kComplete
                                                          : Verdict::kBadChecksum;
    }
    if (c == '\r') {
      if (i + 1 < len_ && buf_[i + 1] != '\n') return Verdict::kBad;
      continue;
    }
    if (c < 0x20 || c > 0x7E || c == '$') return Verdict::kBad;
    if (c == '*') {
      if (star != 0) return Verdict::kBad;
      star = i;
    }
  }
  if (len_ >= kMaxNmeaBytes) return Verdict::kBad;
  need = 0;  // unknown: up to the next LF
  return Verdict::kNeedMore;
}

DecodeStep FrameScanner::next(std::span<const std::uint8_t> input) {
  drop_front(frame_len_);
  frame_len_ = 0;
  std::size_t taken = 0;
  auto take = [&](std::size_t n) {
    std::memcpy(buf_.data() + len_, input.data() + taken, n);
    len_ += n;
    taken += n;
  };
  while (true) {
    // Hunt in what is buffered (bytes left over after a failed candidate).
    std::size_t skip = 0;
    while (skip < len_ && !is_start(buf_[skip])) ++skip;
    if (skip > 0) {
      drop_front(skip);
      stats_.bytes_skipped += skip;
    }
    if (len_ == 0) {
      // Hunt directly in the input without copying garbage.
      std::size_t i = taken;
      while (i < input.size() && !is_start(input[i])) ++i;
      stats_.bytes_skipped += i - taken;
      taken = i;
      if (taken == input.size()) break;
      take(1);
    }
    std::size_t need = 0;
    switch (assess(need)) {
      case Verdict::kNeedMore: {
        if (taken == input.size()) return finish(taken, false);
        if (need > 0) {
          take(std::min(need - len_, input.size() - taken));
        } else {
          // NMEA: copy up to and including LF, stopping early at a byte that breaks the frame.
          while (taken < input.size() && len_ < kMaxNmeaBytes) {
            const std::uint8_t c = input[taken];
            take(1);
            if (c == '\n' || c == '$' || ((c < 0x20 || c > 0x7E) && c != '\r')) break;
          }
        }
        continue;
      }
      case Verdict::kBad:
        ++stats_.framing_errors;
        drop_front(1);
        ++stats_.bytes_skipped;
        continue;
      case Verdict::kBadChecksum:
        ++stats_.checksum_errors;
        drop_front(1);
        ++stats_.bytes_skipped;
        continue;
      case Verdict::kComplete:
        frame_len_ = need;
        kind_ = buf_[0] == kUbxSync1        ? FrameKind::kUbx
                : buf_[0] == kRtcm3Preamble ? FrameKind::kRtcm3
                                            : FrameKind::kNmea;
        ++stats_.frames_ok;
        // Keep `consumed` >= 1 for a frame that was already complete in the buffer.
        if (taken == 0 && !input.empty() && len_ < buf_.size()) take(1);
        return finish(taken, true);
    }
  }
  return finish(taken, false);
}

DecodeStep FrameScanner::finish(std::size_t taken, bool produced) {
  stats_.bytes_in += taken;
  return DecodeStep{taken, produced};
}

// -------------------------------------- Decoder ---------------------------------------------

std::int64_t Decoder::date_for(std::int64_t tod_ms) const {
  // The date came with an earlier sentence; correct a midnight crossing in between.
  std::int64_t days = date_days_;
  if (tod_ms + kMsPerDay / 2 < date_tod_ms_) ++days;
  if (tod_ms > date_tod_ms_ + kMsPerDay / 2) --days;
  return days;
}

namespace {

// WGS-84 ECEF to geodetic latitude/longitude (deg) and ellipsoidal height (m), iterated to well
// below a millimetre.
void ecef_to_geodetic(const double (&xyz)[3], double& lat_deg, double& lon_deg, double& h_m) {
  constexpr double a = 6378137.0;
  constexpr double f = 1.0 / 298.257223563;
  constexpr double e2 = f * (2.0 - f);
  const double x = xyz[0];
  const double y = xyz[1];
  const double z = xyz[2];
  const double p = std::hypot(x, y);
  double lat = std::atan2(z, p * (1.0 - e2));
  double h = 0.0;
  for (int i = 0; i < 10; ++i) {
    const double s = std::sin(lat);
    const double n = a / std::sqrt(1.0 - e2 * s * s);
    h = p / std::cos(lat) - n;
    if (p < 1.0) h = std::abs(z) - a * std::sqrt(1.0 - e2);  // at a pole
    lat = std::atan2(z, p * (1.0 - e2 * n / (n + h)));
  }
  lat_deg = lat * 180.0 / std::numbers::pi;
  lon_deg = std::atan2(y, x) * 180.0 / std::numbers::pi;
  h_m = h;
}

}  // namespace

Decoder::LegacyEpoch& Decoder::legacy_epoch(std::uint32_t itow_ms) {
  if (!legacy_.active || legacy_.itow_ms != itow_ms) {
    legacy_ = LegacyEpoch{};
    legacy_.active = true;
    legacy_.itow_ms = itow_ms;
  }
  return legacy_;
}

bool Decoder::used_ubx(UbxId id) {
  msg_.kind = MessageKind::kOtherUbx;  // read into the epoch, nothing to hand out yet
  msg_.ubx = id;
  return true;
}

bool Decoder::emit_legacy() {
  const LegacyEpoch& e = legacy_;
  // A receiver that sends NAV-PVT gets its fixes from it alone, not twice per epoch.
  if (pvt_seen_ || !e.have_status || (!e.have_llh && !e.have_ecef)) return false;
  msg::GnssFix fix;
  fix.source = msg::GnssSource::kUbxNavLegacy;
  fix.itow_ms = e.itow_ms;
  fix.fix_type = e.fix_type <= 5 ? static_cast<msg::FixType>(e.fix_type) : msg::FixType::kNoFix;
  fix.fix_ok = e.fix_ok;
  fix.diff_soln = e.diff_soln;
  fix.satellites = e.satellites;
  double lat_deg = e.lat_deg;
  double lon_deg = e.lon_deg;
  if (e.have_llh) {
    fix.height_msl_m = e.height_msl_m;
    fix.h_acc_m = e.h_acc_m;
    fix.v_acc_m = e.v_acc_m;
  } else {
    double h_m = 0.0;
    ecef_to_geodetic(e.ecef_m, lat_deg, lon_deg, h_m);
    fix.height_msl_m = h_m;   // ellipsoidal: these messages carry no geoid separation
    fix.h_acc_m = e.p_acc_m;  // 3-D accuracy: an upper bound of the horizontal one
  }
  fix.lat_deg = lat_deg;
  fix.lon_deg = lon_deg;
  if (e.have_velned) {
    fix.vel_north_mps = e.vel_ned_mps[0];
    fix.vel_east_mps = e.vel_ned_mps[1];
    fix.vel_down_mps = e.vel_ned_mps[2];
    fix.ground_speed_mps = e.ground_speed_mps;
    fix.course_deg = e.course_deg;
  } else if (e.have_ecef_vel) {
    const double lat = lat_deg * std::numbers::pi / 180.0;
    const double lon = lon_deg * std::numbers::pi / 180.0;
    const double sl = std::sin(lat), cl = std::cos(lat), so = std::sin(lon), co = std::cos(lon);
    const double* v = e.ecef_vel_mps;
    fix.vel_north_mps = -sl * co * v[0] - sl * so * v[1] + cl * v[2];
    fix.vel_east_mps = -so * v[0] + co * v[1];
    fix.vel_down_mps = -(cl * co * v[0] + cl * so * v[1] + sl * v[2]);
    fix.ground_speed_mps = std::hypot(fix.vel_north_mps, fix.vel_east_mps);
    fix.course_deg = fix.ground_speed_mps > 0.0
                         ? core::wrap_deg(std::atan2(fix.vel_east_mps, fix.vel_north_mps) * 180.0 /
                                          std::numbers::pi)
                         : 0.0;
  }
  fix.s_acc_mps = e.s_acc_mps;
  fix.velocity_valid =
      (e.have_velned || e.have_ecef_vel) && fix.fix_ok && e.fix_type >= 2 && e.fix_type <= 4;
  if (e.have_week && e.week > 0) {
    constexpr std::int64_t kGpsEpochUnixS = 315964800;  // 1980-01-06
    const std::int64_t gps_ms = static_cast<std::int64_t>(e.week) * 604800000LL + e.itow_ms;
    fix.utc_ns =
        (kGpsEpochUnixS - leap_seconds_) * core::kNsPerSec + gps_ms * 1'000'000LL + e.ftow_ns;
  }
  msg_.kind = MessageKind::kFix;
  msg_.fix = fix;
  msg_.nmea_address = {};
  return true;
}

void Decoder::reset() {
  scanner_.reset();
  msg_ = Message{};
  legacy_ = LegacyEpoch{};
  pvt_seen_ = false;
  have_date_ = false;
  have_rmc_velocity_ = false;
  rmc_tod_ms_ = -1;
}

DecodeStep Decoder::decode(std::span<const std::uint8_t> input) {
  std::size_t consumed = 0;
  while (true) {
    const DecodeStep step = scanner_.next(input.subspan(consumed));
    consumed += step.consumed;
    if (!step.produced) return {consumed, false};
    if (interpret(scanner_.kind(), scanner_.frame())) {
      ++scanner_.mutable_stats().messages_out;
      return {consumed, true};
    }
    // Checksum-valid but malformed: counted, keep going.
    ++scanner_.mutable_stats().framing_errors;
  }
}

bool Decoder::interpret(FrameKind kind, std::span<const std::uint8_t> frame) {
  msg_.kind = MessageKind::kNone;
  switch (kind) {
    case FrameKind::kUbx:
      return interpret_ubx(frame);
    case FrameKind::kNmea:
      return interpret_nmea(frame);
    case FrameKind::kRtcm3:
      msg_.kind = MessageKind::kRtcm3;
      msg_.rtcm3 = Rtcm3Frame{rtcm3_message_type(frame), frame};
      return true;
  }
  return false;
}

bool Decoder::interpret_ubx(std::span<const std::uint8_t> frame) {
  const UbxId id{frame[2], frame[3]};
  const auto p = frame.subspan(6, frame.size() - kUbxOverhead);
  if (id == UbxId{0x01, 0x07}) {
    // NAV-PVT: 92 bytes (84 on u-blox 6/7; nothing we read lies beyond 84).
    if (p.size() != 92 && p.size() != 84) return false;
    pvt_seen_ = true;
    msg::GnssFix fix;
    fix.source = msg::GnssSource::kUbxNavPvt;
    fix.itow_ms = get_u4(p, 0);
    const unsigned year = get_u2(p, 4);
    const unsigned month = p[6];
    const unsigned day = p[7];
    const unsigned hour = p[8];
    const unsigned minute = p[9];
    const unsigned second = p[10];
    const std::uint8_t valid = p[11];
    const std::int32_t nano = get_i4(p, 16);
    const bool date_time_ok = (valid & 0x03U) == 0x03U && month >= 1 && month <= 12 && day >= 1 &&
                              day <= 31 && hour < 24 && minute < 60 && second <= 60;
    if (date_time_ok) {
      const std::int64_t secs = unix_days_from_civil(static_cast<int>(year), month, day) * 86400 +
                                hour * 3600LL + minute * 60LL + second;
      fix.utc_ns = secs * core::kNsPerSec + nano;
    }
    const std::uint8_t fix_type = p[20];
    fix.fix_type = fix_type <= 5 ? static_cast<msg::FixType>(fix_type) : msg::FixType::kNoFix;
    const std::uint8_t flags = p[21];
    fix.fix_ok = (flags & 0x01U) != 0;
    fix.diff_soln = (flags & 0x02U) != 0;
    const unsigned carr = (flags >> 6) & 0x03U;
    fix.rtk = carr == 1   ? msg::RtkSolution::kFloat
              : carr == 2 ? msg::RtkSolution::kFixed
                          : msg::RtkSolution::kNone;
    fix.satellites = p[23];
    fix.lon_deg = get_i4(p, 24) * 1e-7;
    fix.lat_deg = get_i4(p, 28) * 1e-7;
    fix.height_msl_m = get_i4(p, 36) * 1e-3;
    fix.h_acc_m = get_u4(p, 40) * 1e-3;
    fix.v_acc_m = get_u4(p, 44) * 1e-3;
    fix.vel_north_mps = get_i4(p, 48) * 1e-3;
    fix.vel_east_mps = get_i4(p, 52) * 1e-3;
    fix.vel_down_mps = get_i4(p, 56) * 1e-3;
    fix.ground_speed_mps = get_i4(p, 60) * 1e-3;
    fix.course_deg = core::wrap_deg(get_i4(p, 64) * 1e-5);
    fix.s_acc_mps = get_u4(p, 68) * 1e-3;
    fix.hdop = -1.0;  // NAV-PVT carries pDOP only
    fix.velocity_valid = fix.fix_ok && fix_type >= 2 && fix_type <= 4;
    msg_.kind = MessageKind::kFix;
    msg_.fix = fix;
    msg_.nmea_address = {};
    return true;
  }
  if (id.msg_class == 0x01) {
    switch (id.msg_id) {
      case 0x01: {  // NAV-POSECEF
        if (p.size() != 20) return false;
        LegacyEpoch& e = legacy_epoch(get_u4(p, 0));
        if (!e.have_ecef) {
          for (std::size_t i = 0; i < 3; ++i) e.ecef_m[i] = get_i4(p, 4 + 4 * i) * 1e-2;
          e.p_acc_m = get_u4(p, 16) * 1e-2;
          e.have_ecef = true;
        }
        if (!e.sol_emitted && emit_legacy()) return true;
        return used_ubx(id);
      }
      case 0x02: {  // NAV-POSLLH
        if (p.size() != 28) return false;
        LegacyEpoch& e = legacy_epoch(get_u4(p, 0));
        e.lon_deg = get_i4(p, 4) * 1e-7;
        e.lat_deg = get_i4(p, 8) * 1e-7;
        e.height_msl_m = get_i4(p, 16) * 1e-3;
        e.h_acc_m = get_u4(p, 20) * 1e-3;
        e.v_acc_m = get_u4(p, 24) * 1e-3;
        e.have_llh = true;
        return emit_legacy() || used_ubx(id);
      }
      case 0x03: {  // NAV-STATUS
        if (p.size() != 16) return false;
        LegacyEpoch& e = legacy_epoch(get_u4(p, 0));
        if (!e.have_status) {
          e.fix_type = p[4];
          e.fix_ok = (p[5] & 0x01U) != 0;
          e.diff_soln = (p[5] & 0x02U) != 0;
          e.have_status = true;
        }
        if (!e.sol_emitted && emit_legacy()) return true;
        return used_ubx(id);
      }
      case 0x06: {  // NAV-SOL
        if (p.size() != 52) return false;
        LegacyEpoch& e = legacy_epoch(get_u4(p, 0));
        e.ftow_ns = get_i4(p, 4);
        e.week = static_cast<std::int16_t>(get_u2(p, 8));
        e.fix_type = p[10];
        const std::uint8_t flags = p[11];
        e.fix_ok = (flags & 0x01U) != 0;
        e.diff_soln = (flags & 0x02U) != 0;
        e.have_week = (flags & 0x0CU) == 0x0CU;  // week and time of week valid
        e.have_status = true;
        for (std::size_t i = 0; i < 3; ++i) {
          e.ecef_m[i] = get_i4(p, 12 + 4 * i) * 1e-2;
          e.ecef_vel_mps[i] = get_i4(p, 28 + 4 * i) * 1e-2;
        }
        e.p_acc_m = get_u4(p, 24) * 1e-2;
        if (!e.have_velned) e.s_acc_mps = get_u4(p, 40) * 1e-2;
        e.have_ecef = true;
        e.have_ecef_vel = true;
        e.satellites = p[47];
        e.sol_emitted = true;
        return emit_legacy() || used_ubx(id);
      }
      case 0x12: {  // NAV-VELNED
        if (p.size() != 36) return false;
        LegacyEpoch& e = legacy_epoch(get_u4(p, 0));
        for (std::size_t i = 0; i < 3; ++i) e.vel_ned_mps[i] = get_i4(p, 4 + 4 * i) * 1e-2;
        e.ground_speed_mps = get_u4(p, 20) * 1e-2;
        e.course_deg = core::wrap_deg(get_i4(p, 24) * 1e-5);
        e.s_acc_mps = get_u4(p, 28) * 1e-2;
        e.have_velned = true;
        return emit_legacy() || used_ubx(id);
      }
      case 0x20: {  // NAV-TIMEGPS: only its leap seconds
        if (p.size() != 16) return false;
        if ((p[11] & 0x04U) != 0) leap_seconds_ = get_i1(p, 10);
        return used_ubx(id);
      }
      default:
        break;
    }
  }
  if (id == UbxId{0x01, 0x14}) {
    if (p.size() != 36) return false;
    HpPosLlh hp;
    hp.invalid_llh = (p[3] & 0x01U) != 0;
    hp.itow_ms = get_u4(p, 4);
    hp.lon_deg = get_i4(p, 8) * 1e-7 + get_i1(p, 24) * 1e-9;
    hp.lat_deg = get_i4(p, 12) * 1e-7 + get_i1(p, 25) * 1e-9;
    hp.height_m = get_i4(p, 16) * 1e-3 + get_i1(p, 26) * 1e-4;
    hp.height_msl_m = get_i4(p, 20) * 1e-3 + get_i1(p, 27) * 1e-4;
    hp.h_acc_m = get_u4(p, 28) * 1e-4;
    hp.v_acc_m = get_u4(p, 32) * 1e-4;
    msg_.kind = MessageKind::kHpPosLlh;
    msg_.hp = hp;
    return true;
  }
  if (id.msg_class == 0x05 && (id.msg_id == 0x00 || id.msg_id == 0x01)) {
    if (p.size() != 2) return false;
    msg_.kind = id.msg_id == 0x01 ? MessageKind::kAck : MessageKind::kNak;
    msg_.ubx = UbxId{p[0], p[1]};
    return true;
  }
  msg_.kind = MessageKind::kOtherUbx;
  msg_.ubx = id;
  ++scanner_.mutable_stats().unsupported;
  return true;
}

bool Decoder::interpret_nmea(std::span<const std::uint8_t> frame) {
  // The scanner guarantees '$' ... '*hh' [CR] LF with printable ASCII in between.
  const std::string_view text(reinterpret_cast<const char*>(frame.data()), frame.size());
  const std::size_t star = text.rfind('*');
  const std::string_view body = text.substr(1, star - 1);
  NmeaFields fields;
  std::size_t start = 0;
  while (fields.count < kMaxNmeaFields) {
    const std::size_t comma = body.find(',', start);
    fields.f[fields.count++] =
        body.substr(start, comma == std::string_view::npos ? body.npos : comma - start);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  const std::string_view address = fields.at(0);
  msg_.nmea_address = address;
  if (address.size() != 5 || address[0] == 'P') {
    msg_.kind = MessageKind::kOtherNmea;
    ++scanner_.mutable_stats().unsupported;
    return true;
  }
  const std::string_view type = address.substr(2);

  if (type == "RMC" || type == "GLL") {
    // RMC: 1 time, 2 status, 3-6 lat/lon, 7 speed kn, 8 course, 9 date, 12 mode.
    // GLL: 1-4 lat/lon, 5 time, 6 status, 7 mode (position and time only).
    const bool rmc = type == "RMC";
    std::int64_t tod_ms = 0;
    const bool have_tod = parse_tod_ms(fields.at(rmc ? 1 : 5), tod_ms);
    const std::string_view status = fields.at(rmc ? 2 : 6);
    if (status != "A" && status != "V") return false;
    const std::string_view mode_field = fields.at(rmc ? 12 : 7);
    const char mode = mode_field.empty() ? 'A' : mode_field[0];
    msg::GnssFix fix;
    fix.source = rmc ? msg::GnssSource::kNmeaRmc : msg::GnssSource::kNmeaGll;
    fix.fix_ok = status == "A" && mode != 'N';
    if (fix.fix_ok) {
      const std::size_t pos = rmc ? 3 : 1;
      if (!parse_coord(fields.at(pos), fields.at(pos + 1), 90.0, fix.lat_deg) ||
          !parse_coord(fields.at(pos + 2), fields.at(pos + 3), 180.0, fix.lon_deg)) {
        return false;
      }
      // RMC/GLL cannot tell 2-D from 3-D; the matching GGA does.
      fix.fix_type = mode == 'E' ? msg::FixType::kDeadReckoning : msg::FixType::k2D;
      fix.diff_soln = mode == 'D' || mode == 'F' || mode == 'R';
      fix.rtk = mode == 'F'   ? msg::RtkSolution::kFloat
                : mode == 'R' ? msg::RtkSolution::kFixed
                              : msg::RtkSolution::kNone;
    }
    if (!rmc) {
      if (have_tod && have_date_) fix.utc_ns = utc_ns_from_ms(date_for(tod_ms), tod_ms);
      msg_.kind = MessageKind::kFix;
      msg_.fix = fix;
      return true;
    }
    const std::string_view date = fields.at(9);
    unsigned dd = 0;
    unsigned mo = 0;
    unsigned yy = 0;
    if (have_tod && date.size() == 6 && parse_uint(date.substr(0, 2), dd) &&
        parse_uint(date.substr(2, 2), mo) && parse_uint(date.substr(4, 2), yy) && dd >= 1 &&
        dd <= 31 && mo >= 1 && mo <= 12) {
      const int year = static_cast<int>(yy) + (yy < 80 ? 2000 : 1900);
      have_date_ = true;
      date_days_ = unix_days_from_civil(year, mo, dd);
      date_tod_ms_ = tod_ms;
      fix.utc_ns = utc_ns_from_ms(date_days_, tod_ms);
    }
    double speed_kn = 0.0;
    double course = 0.0;
    const bool have_speed = parse_double(fields.at(7), speed_kn);
    const bool have_course = parse_double(fields.at(8), course);
    if (have_speed) fix.ground_speed_mps = speed_kn * kKnotsToMps;
    if (have_course) fix.course_deg = core::wrap_deg(course);
    // N/E velocity only when both speed and course are known; vertical speed is unknown.
    fix.velocity_valid = fix.fix_ok && have_speed && have_course;
    if (fix.velocity_valid) {
      fix.vel_north_mps = fix.ground_speed_mps * std::cos(core::deg_to_rad(course));
      fix.vel_east_mps = fix.ground_speed_mps * std::sin(core::deg_to_rad(course));
    }
    have_rmc_velocity_ = fix.fix_ok && have_speed && have_tod;
    rmc_tod_ms_ = have_tod ? tod_ms : -1;
    rmc_speed_mps_ = fix.ground_speed_mps;
    rmc_course_valid_ = have_course;
    rmc_course_deg_ = fix.course_deg;
    msg_.kind = MessageKind::kFix;
    msg_.fix = fix;
    return true;
  }

  if (type == "GGA") {
    std::int64_t tod_ms = 0;
    const bool have_tod = parse_tod_ms(fields.at(1), tod_ms);
    unsigned quality = 0;
    if (!fields.at(6).empty() && !parse_uint(fields.at(6), quality)) return false;
    msg::GnssFix fix;
    fix.source = msg::GnssSource::kNmeaGga;
    // 1 GPS, 2 DGPS, 3 PPS, 4 RTK fixed, 5 RTK float count as a GNSS fix; 6 estimated (dead
    // reckoning), 7 manual and 8 simulator do not.
    fix.fix_ok = quality >= 1 && quality <= 5;
    unsigned sats = 0;
    if (parse_uint(fields.at(7), sats))
      fix.satellites = static_cast<std::uint8_t>(std::min(sats, 255U));
    double hdop = 0.0;
    if (parse_double(fields.at(8), hdop)) fix.hdop = hdop;
    if (quality != 0) {
      if (!parse_coord(fields.at(2), fields.at(3), 90.0, fix.lat_deg) ||
          !parse_coord(fields.at(4), fields.at(5), 180.0, fix.lon_deg)) {
        return false;
      }
      const bool have_alt = parse_double(fields.at(9), fix.height_msl_m);
      fix.fix_type = quality == 6 ? msg::FixType::kDeadReckoning
                     : have_alt   ? msg::FixType::k3D
                                  : msg::FixType::k2D;
      fix.diff_soln = quality == 2 || quality == 4 || quality == 5;
      fix.rtk = quality == 4   ? msg::RtkSolution::kFixed
                : quality == 5 ? msg::RtkSolution::kFloat
                               : msg::RtkSolution::kNone;
    }
    if (have_tod && have_date_) fix.utc_ns = utc_ns_from_ms(date_for(tod_ms), tod_ms);
    if (fix.fix_ok && have_tod && have_rmc_velocity_ && rmc_tod_ms_ == tod_ms) {
      fix.ground_speed_mps = rmc_speed_mps_;
      if (rmc_course_valid_) {
        fix.course_deg = rmc_course_deg_;
        fix.velocity_valid = true;
        fix.vel_north_mps = rmc_speed_mps_ * std::cos(core::deg_to_rad(rmc_course_deg_));
        fix.vel_east_mps = rmc_speed_mps_ * std::sin(core::deg_to_rad(rmc_course_deg_));
      }
    }
    msg_.kind = MessageKind::kFix;
    msg_.fix = fix;
    return true;
  }

  if (type == "ZDA") {
    // Date context only (u-blox emits ZDA after GGA); reported as another NMEA sentence.
    std::int64_t tod_ms = 0;
    unsigned dd = 0;
    unsigned mo = 0;
    unsigned yyyy = 0;
    if (parse_tod_ms(fields.at(1), tod_ms) && parse_uint(fields.at(2), dd) &&
        parse_uint(fields.at(3), mo) && parse_uint(fields.at(4), yyyy) && dd >= 1 && dd <= 31 &&
        mo >= 1 && mo <= 12 && yyyy >= 1980) {
      have_date_ = true;
      date_days_ = unix_days_from_civil(static_cast<int>(yyyy), mo, dd);
      date_tod_ms_ = tod_ms;
    }
  }
  msg_.kind = MessageKind::kOtherNmea;
  ++scanner_.mutable_stats().unsupported;
  return true;
}

// ------------------------------------- Rtcm3Framer ------------------------------------------

DecodeStep Rtcm3Framer::decode(std::span<const std::uint8_t> input) {
  const DecodeStep step = scanner_.next(input);
  if (step.produced) {
    const auto bytes = scanner_.frame();
    frame_ = Rtcm3Frame{rtcm3_message_type(bytes), bytes};
    ++scanner_.mutable_stats().messages_out;
  }
  return step;
}

}  // namespace coxswain::drivers::ublox
