// SPDX-License-Identifier: Apache-2.0
#include "sim/devices/ublox/emulator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

#include "coxswain/core/angles.hpp"
#include "coxswain/drivers/ublox/config.hpp"

namespace coxswain::sim::devices::ublox {

namespace ub = drivers::ublox;

namespace {

constexpr std::int64_t kMsPerWeek = 7LL * 86400 * 1000;
// GPS time = UTC + 18 s (leap seconds since 2017); GPS epoch 1980-01-06 = Unix 315964800.
constexpr std::int64_t kGpsEpochUnixS = 315'964'800;
constexpr std::int64_t kGpsLeapS = 18;
constexpr double kMpsPerKnot = 1852.0 / 3600.0;
constexpr std::uint8_t kNmeaClass = 0xF0;
constexpr std::uint8_t kNmeaGgaId = 0x00;
constexpr std::uint8_t kNmeaRmcId = 0x04;

// VALSET keys this receiver knows (docs/protocols.md 3.6). Anything else is NAKed.
constexpr std::array<std::uint32_t, 27> kKnownKeys{
    ub::key::kRateMeas,
    ub::key::kRateNav,
    0x20210003,  // TIMEREF
    ub::key::kNavspgDynModel,
    0x10730001,
    0x10730002,  // UART1INPROT
    0x10730004,
    ub::key::kUart1OutProtUbx,
    ub::key::kUart1OutProtNmea,
    0x10740004,
    0x10770001,
    0x10770002,  // USBINPROT
    0x10770004,
    ub::key::kUsbOutProtUbx,
    ub::key::kUsbOutProtNmea,
    0x10780004,
    0x20910006,
    ub::key::kMsgoutNavPvtUart1,
    0x20910008,
    ub::key::kMsgoutNavPvtUsb,
    0x2091000A,
    ub::key::kMsgoutNmeaGgaUart1,
    ub::key::kMsgoutNmeaGgaUsb,
    ub::key::kMsgoutNmeaRmcUart1,
    ub::key::kMsgoutNmeaRmcUsb,
    0x20910034,
    0x20910036,  // HPPOSLLH
};

std::uint32_t get_u4(std::span<const std::uint8_t> p, std::size_t o) {
  return static_cast<std::uint32_t>(p[o]) | (static_cast<std::uint32_t>(p[o + 1]) << 8) |
         (static_cast<std::uint32_t>(p[o + 2]) << 16) |
         (static_cast<std::uint32_t>(p[o + 3]) << 24);
}
std::uint16_t get_u2(std::span<const std::uint8_t> p, std::size_t o) {
  return static_cast<std::uint16_t>(p[o] | (p[o + 1] << 8));
}
void put_le(std::uint8_t* p, std::int64_t v, int n) {
  for (int i = 0; i < n; ++i) {
    p[i] = static_cast<std::uint8_t>((static_cast<std::uint64_t>(v) >> (8 * i)) & 0xFFU);
  }
}

struct Civil {
  int year;
  unsigned month, day, hour, minute, second;
  std::int64_t nano;
};
// Howard Hinnant's civil_from_days, the inverse of ub::unix_days_from_civil.
Civil civil_from_unix_ns(std::int64_t unix_ns) {
  std::int64_t secs = unix_ns / core::kNsPerSec;
  std::int64_t nano = unix_ns % core::kNsPerSec;
  if (nano < 0) {
    nano += core::kNsPerSec;
    --secs;
  }
  std::int64_t days = secs / 86400;
  std::int64_t tod = secs % 86400;
  if (tod < 0) {
    tod += 86400;
    --days;
  }
  const std::int64_t z = days + 719468;
  const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const auto doe = static_cast<unsigned>(z - era * 146097);
  const unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const unsigned mp = (5 * doy + 2) / 153;
  const unsigned d = doy - (153 * mp + 2) / 5 + 1;
  const unsigned m = mp < 10 ? mp + 3 : mp - 9;
  const auto y = static_cast<int>(static_cast<std::int64_t>(yoe) + era * 400 + (m <= 2 ? 1 : 0));
  return Civil{y,
               m,
               d,
               static_cast<unsigned>(tod / 3600),
               static_cast<unsigned>(tod / 60 % 60),
               static_cast<unsigned>(tod % 60),
               nano};
}

/// A sentence being built. Fixed buffer; output beyond it is cut (never happens for our lines).
struct Text {
  std::array<char, 160> buf{};
  std::size_t n = 0;
  __attribute__((format(printf, 2, 3))) void add(const char* fmt, ...) {
    if (n >= buf.size() - 1) return;
    va_list args;
    va_start(args, fmt);
    const int w = std::vsnprintf(buf.data() + n, buf.size() - n, fmt, args);
    va_end(args);
    if (w > 0) n = std::min(buf.size() - 1, n + static_cast<std::size_t>(w));
  }
  /// ddmm.mmmmm,N / dddmm.mmmmm,E (1e-5 minute = 1.8 cm).
  void coord(double deg, bool lat) {
    const auto total = std::llround(std::fabs(deg) * 60.0 * 1e5);  // 1e-5 minutes
    const long long d = total / 6'000'000;
    const long long rest = total % 6'000'000;
    const char hemi = lat ? (deg < 0 ? 'S' : 'N') : (deg < 0 ? 'W' : 'E');
    if (lat) {
      add("%02lld%02lld.%05lld,%c", d, rest / 100'000, rest % 100'000, hemi);
    } else {
      add("%03lld%02lld.%05lld,%c", d, rest / 100'000, rest % 100'000, hemi);
    }
  }
};

/// Time of day (ms) from an NMEA hhmmss[.ss] field; -1 when absent.
std::int64_t nmea_tod_ms(std::span<const std::uint8_t> frame) {
  // Field 1 follows the first comma.
  std::size_t i = 0;
  while (i < frame.size() && frame[i] != ',') ++i;
  ++i;
  if (i + 6 > frame.size()) return -1;
  int v[6];
  for (int k = 0; k < 6; ++k) {
    const std::uint8_t c = frame[i + static_cast<std::size_t>(k)];
    if (c < '0' || c > '9') return -1;
    v[k] = c - '0';
  }
  std::int64_t ms =
      ((v[0] * 10 + v[1]) * 3600LL + (v[2] * 10 + v[3]) * 60LL + v[4] * 10LL + v[5]) * 1000;
  i += 6;
  if (i < frame.size() && frame[i] == '.') {
    std::int64_t scale = 100;
    for (++i; i < frame.size() && frame[i] >= '0' && frame[i] <= '9' && scale > 0; ++i) {
      ms += (frame[i] - '0') * scale;
      scale /= 10;
    }
  }
  return ms;
}

bool nmea_timed(std::span<const std::uint8_t> f) {
  if (f.size() < 7) return false;
  const std::string_view type(reinterpret_cast<const char*>(f.data()) + 3, 3);
  return type == "GGA" || type == "RMC" || type == "ZDA";
}

}  // namespace

// ------------------------------------ Capture --------------------------------------------------

Capture::Capture(std::vector<std::uint8_t> bytes) : bytes_(std::move(bytes)) {
  ub::FrameScanner scanner;
  std::span<const std::uint8_t> rest = bytes_;
  std::size_t consumed = 0;
  // Two clocks: UBX NAV iTOW (GPS time of week) and NMEA UTC time of day. The first one seen
  // paces the replay; frames of the other kind inherit.
  enum class Clock : std::uint8_t { kNone, kItow, kNmea } clock = Clock::kNone;
  std::int64_t first_ms = 0;
  std::int64_t last_ms = 0;
  std::int64_t wrap_ms = 0;  // week or day wrap added so far
  core::TimeNs at_ns = 0;
  while (true) {
    const drivers::DecodeStep step = scanner.next(rest);
    rest = rest.subspan(step.consumed);
    consumed += step.consumed;
    if (step.produced) {
      const auto f = scanner.frame();
      // The frame lies before the `consumed` mark, usually right before it; after a resync the
      // scanner may already hold bytes beyond it, so look back until the content matches.
      std::size_t start = consumed >= f.size() ? consumed - f.size() : 0;
      while (start > 0 &&
             !std::equal(f.begin(), f.end(), bytes_.begin() + static_cast<std::ptrdiff_t>(start))) {
        --start;
      }
      std::int64_t t_ms = -1;
      Clock kind = Clock::kNone;
      const std::size_t itow_off = f.size() > 3 && f[3] == 0x14 ? 4 : 0;  // HPPOSLLH: at 4
      if (scanner.kind() == ub::FrameKind::kUbx && f[2] == 0x01 &&
          f.size() >= 8 + itow_off + 4) {  // header, checksum and iTOW inside the payload
        t_ms = get_u4(f.subspan(6), itow_off);
        kind = Clock::kItow;
      } else if (scanner.kind() == ub::FrameKind::kNmea && nmea_timed(f)) {
        t_ms = nmea_tod_ms(f);
        kind = Clock::kNmea;
      }
      if (t_ms >= 0 && (clock == Clock::kNone || clock == kind)) {
        if (clock == Clock::kNone) {
          clock = kind;
          first_ms = last_ms = t_ms;
        }
        const std::int64_t period = kind == Clock::kItow ? kMsPerWeek : 86'400'000;
        if (t_ms + wrap_ms < last_ms - period / 2) wrap_ms += period;
        last_ms = t_ms + wrap_ms;
        at_ns = core::ms_to_ns(std::max<std::int64_t>(0, last_ms - first_ms));
      }
      frames_.push_back(Frame{start, f.size(), at_ns});
      continue;
    }
    if (rest.empty()) break;
  }
}

std::optional<Capture> Capture::load(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in),
                                  std::istreambuf_iterator<char>()};
  return Capture(std::move(bytes));
}

// ------------------------------------ Emulator -------------------------------------------------

std::optional<std::string> EmulatorFaults::validate() const {
  const auto prob = [](double p) { return std::isfinite(p) && p >= 0.0 && p <= 1.0; };
  if (!prob(garbage_probability)) return "garbage_probability must be in [0, 1]";
  if (!prob(corrupt_checksum_probability)) return "corrupt_checksum_probability must be in [0, 1]";
  return std::nullopt;
}

std::optional<std::string> EmulatorConfig::validate() const {
  if (!std::isfinite(rate_hz) || rate_hz < 0.1 || rate_hz > 40.0) {
    return "rate_hz must be in [0.1, 40]";
  }
  return faults.validate();
}

Emulator::Emulator(const EmulatorConfig& config)
    : config_(config),
      meas_period_ms_(static_cast<std::uint16_t>(
          std::clamp(std::lround(1000.0 / std::clamp(config.rate_hz, 0.1, 40.0)), 25L, 10000L))),
      nav_pvt_rate_(config.nav_pvt ? 1 : 0),
      nmea_out_(config.nmea),
      rng_state_(config.faults.seed) {}

void Emulator::set_rate_hz(double rate_hz) {
  if (!std::isfinite(rate_hz) || rate_hz <= 0.0) return;
  meas_period_ms_ =
      static_cast<std::uint16_t>(std::clamp(std::lround(1000.0 / rate_hz), 25L, 10000L));
}

void Emulator::play_capture(const Capture* capture) {
  capture_ = capture;
  capture_next_ = 0;
  capture_start_ns_ = core::kNeverNs;
}

bool Emulator::capture_finished() const {
  return capture_ != nullptr && capture_next_ >= capture_->frames().size();
}

std::uint64_t Emulator::next_random() {  // splitmix64
  std::uint64_t z = (rng_state_ += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

double Emulator::uniform() {
  return static_cast<double>(next_random() >> 11) * (1.0 / 9007199254740992.0);
}

void Emulator::put(std::span<const std::uint8_t> bytes) {
  if (config_.faults.silent) return;
  const std::size_t room = kOutputCapacity - out_len_;
  const std::size_t n = std::min(room, bytes.size());
  std::memcpy(out_.data() + out_len_, bytes.data(), n);
  out_len_ += n;
  stats_.dropped_bytes += bytes.size() - n;
}

void Emulator::send_ubx(std::uint8_t cls, std::uint8_t id, std::span<const std::uint8_t> payload,
                        bool may_corrupt) {
  const std::array<std::uint8_t, 6> head{ub::kUbxSync1,
                                         ub::kUbxSync2,
                                         cls,
                                         id,
                                         static_cast<std::uint8_t>(payload.size() & 0xFF),
                                         static_cast<std::uint8_t>(payload.size() >> 8)};
  // Fletcher over class, id, length and payload, continued across the two parts.
  std::uint8_t a = 0;
  std::uint8_t b = 0;
  const auto add = [&](std::uint8_t x) {
    a = static_cast<std::uint8_t>(a + x);
    b = static_cast<std::uint8_t>(b + a);
  };
  for (std::size_t i = 2; i < head.size(); ++i) add(head[i]);
  for (const std::uint8_t x : payload) add(x);
  if (may_corrupt && config_.faults.corrupt_checksum_probability > 0.0 &&
      uniform() < config_.faults.corrupt_checksum_probability) {
    b ^= 0x5A;
    ++stats_.corrupted_messages;
  }
  put(head);
  put(payload);
  const std::array<std::uint8_t, 2> ck{a, b};
  put(ck);
}

void Emulator::send_nmea(const char* body, std::size_t n) {
  // body is "$...": checksum over everything after '$'.
  std::uint8_t x = 0;
  for (std::size_t i = 1; i < n; ++i) x ^= static_cast<std::uint8_t>(body[i]);
  if (config_.faults.corrupt_checksum_probability > 0.0 &&
      uniform() < config_.faults.corrupt_checksum_probability) {
    x ^= 0x5A;
    ++stats_.corrupted_messages;
  }
  put({reinterpret_cast<const std::uint8_t*>(body), n});
  char tail[8];
  const int w = std::snprintf(tail, sizeof tail, "*%02X\r\n", static_cast<unsigned>(x));
  put({reinterpret_cast<const std::uint8_t*>(tail), static_cast<std::size_t>(w)});
  ++stats_.nmea_sent;
}

void Emulator::send_ack(std::uint8_t cls, std::uint8_t id, bool ack) {
  const std::array<std::uint8_t, 2> p{cls, id};
  send_ubx(0x05, ack ? 0x01 : 0x00, p, false);
  ++(ack ? stats_.acks : stats_.naks);
}

void Emulator::set_msg_rate(std::uint8_t cls, std::uint8_t id, std::uint8_t rate) {
  if (cls == ub::kNavPvt.msg_class && id == ub::kNavPvt.msg_id) nav_pvt_rate_ = rate;
  if (cls == kNmeaClass && id == kNmeaGgaId) gga_rate_ = rate;
  if (cls == kNmeaClass && id == kNmeaRmcId) rmc_rate_ = rate;
}

std::uint8_t Emulator::msg_rate(std::uint8_t cls, std::uint8_t id) const {
  if (cls == ub::kNavPvt.msg_class && id == ub::kNavPvt.msg_id) return nav_pvt_rate_;
  if (cls == kNmeaClass && id == kNmeaGgaId) return gga_rate_;
  if (cls == kNmeaClass && id == kNmeaRmcId) return rmc_rate_;
  return 0;
}

bool Emulator::handle_valset(std::span<const std::uint8_t> p) {
  if (config_.model != Model::kF9) return false;  // protocol < 27: unknown message
  if (p.size() < 4 || p[0] != 0 || (p[1] & 0x07) == 0) return false;
  // Validate every item first: a NAKed VALSET changes nothing.
  for (std::size_t pass = 0; pass < 2; ++pass) {
    std::size_t o = 4;
    while (o < p.size()) {
      if (o + 4 > p.size()) return false;
      const std::uint32_t key = get_u4(p, o);
      const std::size_t size = ub::valset_value_size(key);
      if (size == 0 || o + 4 + size > p.size()) return false;
      if (std::find(kKnownKeys.begin(), kKnownKeys.end(), key) == kKnownKeys.end()) return false;
      std::uint64_t v = 0;
      for (std::size_t i = 0; i < size; ++i)
        v |= static_cast<std::uint64_t>(p[o + 4 + i]) << (8 * i);
      o += 4 + size;
      if (key == ub::key::kRateMeas && (v < 25 || v > 10000)) return false;
      if (key == ub::key::kRateNav && v == 0) return false;
      if (pass == 0) continue;
      const bool usb = config_.port == HostPort::kUsb;
      const auto u8 = static_cast<std::uint8_t>(std::min<std::uint64_t>(v, 255));
      if (key == ub::key::kRateMeas) meas_period_ms_ = static_cast<std::uint16_t>(v);
      if (key == ub::key::kNavspgDynModel) dyn_model_ = u8;
      if (key == (usb ? ub::key::kUsbOutProtUbx : ub::key::kUart1OutProtUbx)) ubx_out_ = v != 0;
      if (key == (usb ? ub::key::kUsbOutProtNmea : ub::key::kUart1OutProtNmea)) nmea_out_ = v != 0;
      if (key == (usb ? ub::key::kMsgoutNavPvtUsb : ub::key::kMsgoutNavPvtUart1))
        nav_pvt_rate_ = u8;
      if (key == (usb ? ub::key::kMsgoutNmeaGgaUsb : ub::key::kMsgoutNmeaGgaUart1)) gga_rate_ = u8;
      if (key == (usb ? ub::key::kMsgoutNmeaRmcUsb : ub::key::kMsgoutNmeaRmcUart1)) rmc_rate_ = u8;
    }
  }
  return true;
}

bool Emulator::handle_cfg_msg(std::span<const std::uint8_t> p) {
  if (p.size() == 2) {  // poll: answer with the 8-byte form
    std::array<std::uint8_t, 8> r{p[0], p[1]};
    r[config_.port == HostPort::kUsb ? 5 : 3] = msg_rate(p[0], p[1]);
    send_ubx(ub::kCfgMsg.msg_class, ub::kCfgMsg.msg_id, r, false);
    return true;
  }
  if (p.size() == 3) {  // rate on the port the message arrived on
    set_msg_rate(p[0], p[1], p[2]);
    return true;
  }
  if (p.size() == 8) {  // rates for DDC, UART1, UART2, USB, SPI, reserved
    set_msg_rate(p[0], p[1], p[config_.port == HostPort::kUsb ? 5 : 3]);
    return true;
  }
  return false;
}

bool Emulator::handle_cfg_rate(std::span<const std::uint8_t> p) {
  if (p.empty()) {  // poll
    std::array<std::uint8_t, 6> r{};
    put_le(&r[0], meas_period_ms_, 2);
    put_le(&r[2], 1, 2);
    put_le(&r[4], 1, 2);
    send_ubx(ub::kCfgRate.msg_class, ub::kCfgRate.msg_id, r, false);
    return true;
  }
  if (p.size() != 6) return false;
  const std::uint16_t meas = get_u2(p, 0);
  const std::uint16_t nav = get_u2(p, 2);
  const std::uint16_t ref = get_u2(p, 4);
  if (meas < 25 || nav == 0 || ref > 4) return false;
  meas_period_ms_ = meas;
  return true;
}

bool Emulator::handle_cfg_prt(std::span<const std::uint8_t> p) {
  const std::uint8_t our_port = config_.port == HostPort::kUsb ? 3 : 1;
  if (p.empty() || p.size() == 1) {  // poll (current port / given port)
    std::array<std::uint8_t, 20> r{};
    r[0] = p.empty() ? our_port : p[0];
    if (r[0] == 1) {
      put_le(&r[4], 0x08D0, 4);
      put_le(&r[8], 38400, 4);
    }
    put_le(&r[12], 0x0023, 2);
    put_le(&r[14], (ubx_out_ ? 1 : 0) | (nmea_out_ ? 2 : 0), 2);
    send_ubx(0x06, 0x00, r, false);
    return true;
  }
  if (p.size() != 20 || p[0] > 4) return false;
  if (p[0] == our_port) {
    const std::uint16_t out_mask = get_u2(p, 14);
    ubx_out_ = (out_mask & 0x01) != 0;
    nmea_out_ = (out_mask & 0x02) != 0;
  }
  return true;
}

void Emulator::handle_ubx(std::span<const std::uint8_t> frame) {
  ++stats_.host_frames;
  const std::uint8_t cls = frame[2];
  const std::uint8_t id = frame[3];
  if (cls != 0x06) return;  // only CFG input is acknowledged (docs/protocols.md 3.5)
  const auto p = frame.subspan(6, frame.size() - 8);
  bool ok = false;
  switch (id) {
    case 0x8A:
      ok = handle_valset(p);
      break;
    case 0x01:
      ok = handle_cfg_msg(p);
      break;
    case 0x08:
      ok = handle_cfg_rate(p);
      break;
    case 0x00:
      ok = handle_cfg_prt(p);
      break;
    case 0x24:  // CFG-NAV5: dynModel applied when mask bit0 is set
      ok = p.size() == 36;
      if (ok && (get_u2(p, 0) & 0x01) != 0) dyn_model_ = p[2];
      break;
    default:
      ok = false;
      break;
  }
  send_ack(cls, id, ok);
}

void Emulator::receive(std::span<const std::uint8_t> host_bytes, core::TimeNs /*now_ns*/) {
  const std::uint64_t bad_before =
      host_scanner_.stats().checksum_errors + host_scanner_.stats().framing_errors;
  while (true) {
    const drivers::DecodeStep step = host_scanner_.next(host_bytes);
    host_bytes = host_bytes.subspan(step.consumed);
    if (step.produced) {
      if (host_scanner_.kind() == ub::FrameKind::kRtcm3) {
        ++stats_.rtcm_frames;
        stats_.rtcm_bytes += host_scanner_.frame().size();
      } else if (host_scanner_.kind() == ub::FrameKind::kUbx) {
        handle_ubx(host_scanner_.frame());
      }
      continue;
    }
    if (host_bytes.empty()) break;
  }
  stats_.host_bad_frames +=
      host_scanner_.stats().checksum_errors + host_scanner_.stats().framing_errors - bad_before;
}

std::uint32_t Emulator::itow_ms() const {
  if (truth_.itow_ms != 0 || truth_.utc_ns == 0) return truth_.itow_ms;
  const std::int64_t gps_ms = truth_.utc_ns / core::kNsPerMs - (kGpsEpochUnixS - kGpsLeapS) * 1000;
  return static_cast<std::uint32_t>(((gps_ms % kMsPerWeek) + kMsPerWeek) % kMsPerWeek);
}

void Emulator::emit_nav_pvt() {
  const msg::GnssFix& t = truth_;
  std::array<std::uint8_t, 92> p{};
  put_le(&p[0], itow_ms(), 4);
  if (t.utc_ns != 0) {
    const Civil c = civil_from_unix_ns(t.utc_ns);
    put_le(&p[4], c.year, 2);
    p[6] = static_cast<std::uint8_t>(c.month);
    p[7] = static_cast<std::uint8_t>(c.day);
    p[8] = static_cast<std::uint8_t>(c.hour);
    p[9] = static_cast<std::uint8_t>(c.minute);
    p[10] = static_cast<std::uint8_t>(c.second);
    p[11] = 0x07;           // validDate, validTime, fullyResolved
    put_le(&p[12], 25, 4);  // tAcc ns
    put_le(&p[16], c.nano, 4);
  }
  p[20] = static_cast<std::uint8_t>(t.fix_type);
  const unsigned carr = t.rtk == msg::RtkSolution::kFixed   ? 2U
                        : t.rtk == msg::RtkSolution::kFloat ? 1U
                                                            : 0U;
  p[21] =
      static_cast<std::uint8_t>((t.fix_ok ? 0x01U : 0U) | (t.diff_soln ? 0x02U : 0U) | (carr << 6));
  p[22] = t.utc_ns != 0 ? 0xE0 : 0x00;  // confirmedAvai/Date/Time
  p[23] = t.satellites;
  put_le(&p[24], std::llround(t.lon_deg * 1e7), 4);
  put_le(&p[28], std::llround(t.lat_deg * 1e7), 4);
  put_le(&p[32], std::llround(t.height_msl_m * 1e3), 4);  // no geoid model: height = hMSL
  put_le(&p[36], std::llround(t.height_msl_m * 1e3), 4);
  put_le(&p[40], std::llround(std::max(0.0, t.h_acc_m) * 1e3), 4);
  put_le(&p[44], std::llround(std::max(0.0, t.v_acc_m) * 1e3), 4);
  put_le(&p[48], std::llround(t.vel_north_mps * 1e3), 4);
  put_le(&p[52], std::llround(t.vel_east_mps * 1e3), 4);
  put_le(&p[56], std::llround(t.vel_down_mps * 1e3), 4);
  put_le(&p[60], std::llround(t.ground_speed_mps * 1e3), 4);
  double head = std::fmod(t.course_deg, 360.0);  // the receiver reports 0..360
  if (head < 0.0) head += 360.0;
  put_le(&p[64], std::llround(head * 1e5), 4);
  put_le(&p[68], t.s_acc_mps >= 0.0 ? std::llround(t.s_acc_mps * 1e3) : 100, 4);  // sAcc mm/s
  put_le(&p[72], 100000, 4);                                                      // headAcc 1 deg
  put_le(&p[76], std::llround(std::max(0.0, t.hdop) * 150.0), 2);                 // pDOP ~ 1.5 HDOP
  send_ubx(ub::kNavPvt.msg_class, ub::kNavPvt.msg_id, p, true);
  ++stats_.nav_pvt_sent;
}

void Emulator::emit_rmc() {
  const msg::GnssFix& f = truth_;
  Text t;
  const Civil c = civil_from_unix_ns(f.utc_ns);
  t.add("$GNRMC,");
  if (f.utc_ns != 0) {
    t.add("%02u%02u%02u.%02lld", c.hour, c.minute, c.second,
          static_cast<long long>(c.nano / 10'000'000));
  }
  const bool ok = f.usable();
  t.add(",%c,", ok ? 'A' : 'V');
  if (ok) {
    t.coord(f.lat_deg, true);
    t.add(",");
    t.coord(f.lon_deg, false);
    double course = std::fmod(f.course_deg, 360.0);
    if (course < 0.0) course += 360.0;
    t.add(",%.3f,%.2f,", f.ground_speed_mps / kMpsPerKnot, course);
  } else {
    t.add(",,,,,,");
  }
  if (f.utc_ns != 0) t.add("%02u%02u%02d", c.day, c.month, c.year % 100);
  const char mode = !ok                                          ? 'N'
                    : f.rtk == msg::RtkSolution::kFixed          ? 'R'
                    : f.rtk == msg::RtkSolution::kFloat          ? 'F'
                    : f.fix_type == msg::FixType::kDeadReckoning ? 'E'
                    : f.diff_soln                                ? 'D'
                                                                 : 'A';
  t.add(",,,%c", mode);
  if (config_.model == Model::kF9) t.add(",V");  // NMEA 4.1 navigational status
  send_nmea(t.buf.data(), t.n);
}

void Emulator::emit_gga() {
  const msg::GnssFix& f = truth_;
  Text t;
  const Civil c = civil_from_unix_ns(f.utc_ns);
  t.add("$GNGGA,");
  if (f.utc_ns != 0) {
    t.add("%02u%02u%02u.%02lld", c.hour, c.minute, c.second,
          static_cast<long long>(c.nano / 10'000'000));
  }
  unsigned quality = 0;
  if (f.usable()) {
    quality = f.rtk == msg::RtkSolution::kFixed            ? 4
              : f.rtk == msg::RtkSolution::kFloat          ? 5
              : f.fix_type == msg::FixType::kDeadReckoning ? 6
              : f.diff_soln                                ? 2
                                                           : 1;
  }
  t.add(",");
  if (quality != 0) {
    t.coord(f.lat_deg, true);
    t.add(",");
    t.coord(f.lon_deg, false);
    t.add(",%u,%02u,%.2f,%.1f,M,0.0,M,,", quality, static_cast<unsigned>(f.satellites),
          f.hdop >= 0.0 ? f.hdop : 99.99, f.height_msl_m);
  } else {
    t.add(",,,,0,%02u,99.99,,,,,,", static_cast<unsigned>(f.satellites));
  }
  send_nmea(t.buf.data(), t.n);
}

void Emulator::emit_epoch() {
  ++stats_.epochs;
  ++epoch_counter_;
  const EmulatorFaults& f = config_.faults;
  if (f.garbage_probability > 0.0 && uniform() < f.garbage_probability) {
    std::array<std::uint8_t, 16> junk{};
    const std::size_t n = 1 + static_cast<std::size_t>(next_random() % junk.size());
    for (std::size_t k = 0; k < n; ++k) junk[k] = static_cast<std::uint8_t>(next_random());
    put({junk.data(), n});
    ++stats_.garbage_bursts;
  }
  const auto due = [this](std::uint8_t rate) { return rate != 0 && epoch_counter_ % rate == 0; };
  if (ubx_out_ && due(nav_pvt_rate_)) emit_nav_pvt();
  if (nmea_out_ && due(rmc_rate_)) emit_rmc();
  if (nmea_out_ && due(gga_rate_)) emit_gga();
}

std::span<const std::uint8_t> Emulator::poll(core::TimeNs now_ns) {
  if (returned_ > 0) {
    std::memmove(out_.data(), out_.data() + returned_, out_len_ - returned_);
    out_len_ -= returned_;
    returned_ = 0;
  }
  if (capture_ != nullptr) {
    if (capture_start_ns_ == core::kNeverNs) capture_start_ns_ = now_ns;
    const auto frames = capture_->frames();
    while (capture_next_ < frames.size() &&
           capture_start_ns_ + frames[capture_next_].at_ns <= now_ns &&
           out_len_ + frames[capture_next_].size <= kOutputCapacity) {
      put(capture_->bytes(frames[capture_next_]));
      ++capture_next_;
      ++stats_.capture_frames_sent;
    }
  } else {
    const core::TimeNs period = core::ms_to_ns(meas_period_ms_);
    if (next_epoch_ns_ == core::kNeverNs) next_epoch_ns_ = now_ns;
    if (now_ns >= next_epoch_ns_) {
      const std::int64_t due = (now_ns - next_epoch_ns_) / period + 1;
      if (due > kMaxCatchUpEpochs) {
        stats_.skipped_epochs += static_cast<std::uint64_t>(due - kMaxCatchUpEpochs);
        next_epoch_ns_ += (due - kMaxCatchUpEpochs) * period;
      }
    }
    while (next_epoch_ns_ <= now_ns) {
      emit_epoch();
      next_epoch_ns_ += period;
    }
  }
  returned_ = out_len_;
  return {out_.data(), out_len_};
}

}  // namespace coxswain::sim::devices::ublox
