// SPDX-License-Identifier: Apache-2.0
#include "sim/devices/myahrs/emulator.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <utility>

#include "coxswain/core/angles.hpp"
#include "coxswain/drivers/myahrs/codec.hpp"

namespace coxswain::sim::devices::myahrs {
namespace {

namespace codec = drivers::myahrs;

// Sensitivities printed by `@sensitivity` and used for `$RIIMU` / node r
// (docs/protocols.md 2.3-2.4).
constexpr double kAccelGPerLsb = 4.882813e-4;
constexpr double kGyroDpsPerLsb = 6.097561e-2;
constexpr double kMagUtPerLsb = 0.3;

constexpr std::array<std::string_view, 6> kAsciiNames{"RPY",     "QUAT", "RPYIMU",
                                                      "QUATIMU", "IMU",  "RIIMU"};

// Fixed-capacity text builder for one line.
struct Text {
  std::array<char, 320> buf{};
  std::size_t n = 0;
  __attribute__((format(printf, 2, 3))) void add(const char* fmt, ...) {
    if (n >= buf.size()) return;
    va_list args;
    va_start(args, fmt);
    const int w = std::vsnprintf(buf.data() + n, buf.size() - n, fmt, args);
    va_end(args);
    if (w > 0) n = std::min(buf.size() - 1, n + static_cast<std::size_t>(w));
  }
};

std::array<double, 4> quaternion_xyzw(double roll_deg, double pitch_deg, double yaw_deg) {
  const double hr = core::deg_to_rad(roll_deg) / 2.0;
  const double hp = core::deg_to_rad(pitch_deg) / 2.0;
  const double hy = core::deg_to_rad(yaw_deg) / 2.0;
  const double cr = std::cos(hr), sr = std::sin(hr), cp = std::cos(hp), sp = std::sin(hp);
  const double cy = std::cos(hy), sy = std::sin(hy);
  return {sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy,
          cr * cp * cy + sr * sp * sy};
}

std::int16_t to_i16(double v) {
  const double r = std::round(v);
  if (!(r > -32768.0)) return -32768;  // also catches NaN
  if (r > 32767.0) return 32767;
  return static_cast<std::int16_t>(r);
}

std::int16_t scale_i16(double value, double range) {
  return to_i16(value / range * codec::kBinaryFullScale);
}

std::string_view trim(std::string_view s) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  return s;
}

bool parse_int(std::string_view s, int& out) {
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc{} && ptr == s.data() + s.size() && !s.empty();
}

}  // namespace

std::optional<std::string> EmulatorFaults::validate() const {
  const auto prob_ok = [](double p) { return std::isfinite(p) && p >= 0.0 && p <= 1.0; };
  if (!prob_ok(garbage_probability)) return std::string("garbage_probability must be in [0, 1]");
  if (!prob_ok(corrupt_checksum_probability)) {
    return std::string("corrupt_checksum_probability must be in [0, 1]");
  }
  return std::nullopt;
}

std::optional<std::string> EmulatorConfig::validate() const {
  if (divider < 1 || divider > 1000) return std::string("divider must be in [1, 1000]");
  return faults.validate();
}

Emulator::Emulator(const EmulatorConfig& config)
    : config_(config),
      binary_(config.binary),
      continuous_(config.continuous),
      ascii_format_(config.ascii_format),
      binary_format_(config.binary_format),
      divider_(std::clamp(config.divider, 1, 1000)),
      rng_state_(config.faults.seed) {}

void Emulator::apply_config(const EmulatorConfig& c) {
  binary_ = c.binary;
  continuous_ = c.continuous;
  ascii_format_ = c.ascii_format;
  binary_format_ = c.binary_format;
  divider_ = std::clamp(c.divider, 1, 1000);
  id_ = 0;
  next_data_ns_ = core::kNeverNs;
}

double Emulator::sensor_yaw_for_heading(double true_heading_deg,
                                        const drivers::myahrs::HeadingConfig& cfg) {
  return core::wrap_deg(true_heading_deg + cfg.mount_yaw_deg - cfg.declination_deg);
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

void Emulator::put_line(const char* body, std::size_t n, bool may_corrupt) {
  std::uint8_t cs = codec::xor_checksum(std::string_view(body, n));
  if (may_corrupt && corrupt_next_) {
    cs ^= 0x5A;
    ++stats_.corrupted_messages;
  }
  put({reinterpret_cast<const std::uint8_t*>(body), n});
  char tail[8];
  const int w = std::snprintf(tail, sizeof tail, "*%02X\r\n", static_cast<unsigned>(cs));
  put({reinterpret_cast<const std::uint8_t*>(tail), static_cast<std::size_t>(w)});
}

void Emulator::respond(const char* text) { put_line(text, std::strlen(text), false); }

void Emulator::respond_error(std::string_view name) {
  Text t;
  t.add("~%.*s,ERROR", static_cast<int>(name.size()), name.data());
  ++stats_.error_responses;
  put_line(t.buf.data(), t.n, false);
}

void Emulator::receive(std::span<const std::uint8_t> host_bytes, core::TimeNs /*now_ns*/) {
  receive(host_bytes);
}

void Emulator::set_divider(int divider) { divider_ = std::clamp(divider, 1, 1000); }

void Emulator::receive(std::span<const std::uint8_t> host_bytes) {
  for (const std::uint8_t b : host_bytes) {
    if (b == '@') {
      line_[0] = '@';
      line_len_ = 1;
      in_line_ = true;
    } else if (!in_line_ || b == '\r') {
      continue;
    } else if (b == '\n') {
      in_line_ = false;
      handle_line();
    } else if (line_len_ < kLineCapacity) {
      line_[line_len_++] = static_cast<char>(b);
    } else {
      in_line_ = false;  // overlong: ignored like any garbage
    }
  }
}

void Emulator::handle_line() {
  const std::string_view line(line_.data(), line_len_);
  const std::size_t star = line.find('*');
  unsigned cs = 0;
  if (star == std::string_view::npos || line.size() - star != 3 ||
      std::from_chars(line.data() + star + 1, line.data() + line.size(), cs, 16).ptr !=
          line.data() + line.size() ||
      cs != codec::xor_checksum(line.substr(0, star))) {
    ++stats_.requests_bad_checksum;
    return;
  }
  ++stats_.requests_ok;
  const std::string_view body = line.substr(1, star - 1);
  const std::size_t comma = body.find(',');
  const std::string_view name = body.substr(0, comma);
  const bool has_args = comma != std::string_view::npos;
  const std::string_view args = has_args ? body.substr(comma + 1) : std::string_view{};

  Text t;
  if (name == "version" && !has_args) {
    respond(
        "~version,OK,product=myAHRS+,platform=myAHRS+m3,sn=EMU0000000001,ver=1.6,"
        "build=coxswain-emulator");
  } else if (name == "sn" && !has_args) {
    respond("~sn,OK,sn=EMU0000000001");
  } else if (name == "ping" && !has_args) {
    respond("~ping,OK");
  } else if (name == "id") {
    int id = id_;
    if (has_args && (!parse_int(args, id) || id < 0 || id > 65535)) return respond_error(name);
    id_ = id;
    t.add("~id,OK,id=%d", id_);
    put_line(t.buf.data(), t.n, false);
  } else if (name == "sensitivity" && !has_args) {
    respond(
        "~sensitivity,OK,acc range=16,gyro range=2000,acc sensitivity=4.882813e-04,"
        "gyro sensitivity=6.097561e-02");
  } else if (name == "mode") {
    if (has_args) {
      bool a = false, b = false, c = false, tr = false;
      for (const char ch : args) {
        a |= ch == 'A';
        b |= ch == 'B';
        c |= ch == 'C';
        tr |= ch == 'T';
        if (ch != 'A' && ch != 'B' && ch != 'C' && ch != 'T') return respond_error(name);
      }
      if (args.empty() || args.size() > 2 || (a && b) || (c && tr)) return respond_error(name);
      if (a || b) binary_ = b;
      if (c || tr) {
        if (c && !continuous_) next_data_ns_ = core::kNeverNs;  // restart the data clock
        continuous_ = c;
      }
    }
    t.add("~mode,OK,mode=%c%c", binary_ ? 'B' : 'A', continuous_ ? 'C' : 'T');
    put_line(t.buf.data(), t.n, false);
  } else if (name == "asc_out") {
    if (has_args) {
      const auto it = std::find(kAsciiNames.begin(), kAsciiNames.end(), args);
      if (it == kAsciiNames.end()) return respond_error(name);
      ascii_format_ = static_cast<AsciiFormat>(it - kAsciiNames.begin());
    }
    const std::string_view f = kAsciiNames[static_cast<std::size_t>(ascii_format_)];
    t.add("~asc_out,OK,fmt=%.*s", static_cast<int>(f.size()), f.data());
    put_line(t.buf.data(), t.n, false);
  } else if (name == "bin_out") {
    if (has_args) {
      BinaryFormat f{false, false, false, false};
      std::string_view rest = args;
      while (true) {
        const std::size_t c = rest.find(',');
        const std::string_view item = trim(rest.substr(0, c));
        if (item == "EULER") {
          f.euler = true;
        } else if (item == "QUATERNION") {
          f.quaternion = true;
        } else if (item == "RIIMU") {
          f.raw_imu = true;
        } else if (item == "IMU") {
          f.imu = true;
        } else {
          return respond_error(name);
        }
        if (c == std::string_view::npos) break;
        rest.remove_prefix(c + 1);
      }
      binary_format_ = f;
    }
    // The SDK splits this value on spaces, so the device lists the items space-separated.
    t.add("~bin_out,OK,fmt=");
    const char* sep = "";
    if (binary_format_.euler) t.add("%sEULER", std::exchange(sep, " "));
    if (binary_format_.quaternion) t.add("%sQUATERNION", std::exchange(sep, " "));
    if (binary_format_.raw_imu) t.add("%sRIIMU", std::exchange(sep, " "));
    if (binary_format_.imu) t.add("%sIMU", std::exchange(sep, " "));
    put_line(t.buf.data(), t.n, false);
  } else if (name == "divider") {
    int d = divider_;
    if (has_args && (!parse_int(args, d) || d < 1 || d > 1000)) return respond_error(name);
    divider_ = d;
    t.add("~divider,OK,divider=%d,max rate=100", divider_);
    put_line(t.buf.data(), t.n, false);
  } else if (name == "trig" && !has_args) {
    if (continuous_) return respond_error(name);
    emit_data();  // trigger mode answers with one data message, not a `~trig`
  } else if (name == "save" && !has_args) {
    respond("~save,OK");
  } else if (name == "factory" && !has_args) {
    apply_config(EmulatorConfig{});
    respond("~factory,OK");
  } else {
    respond_error(name);
  }
}

std::span<const std::uint8_t> Emulator::poll(core::TimeNs now_ns) {
  if (returned_ > 0) {
    std::memmove(out_.data(), out_.data() + returned_, out_len_ - returned_);
    out_len_ -= returned_;
    returned_ = 0;
  }
  if (continuous_) {
    const std::int64_t period = kBasePeriodNs * divider_;
    if (next_data_ns_ == core::kNeverNs) next_data_ns_ = now_ns;
    if (now_ns >= next_data_ns_) {
      const std::int64_t due = (now_ns - next_data_ns_) / period + 1;
      if (due > kMaxCatchUpTicks) {
        stats_.skipped_ticks += static_cast<std::uint64_t>(due - kMaxCatchUpTicks);
        next_data_ns_ += (due - kMaxCatchUpTicks) * period;
      }
    }
    while (next_data_ns_ <= now_ns) {
      emit_data();
      next_data_ns_ += period;
    }
  }
  returned_ = out_len_;
  return {out_.data(), out_len_};
}

void Emulator::emit_data() {
  const EmulatorFaults& f = config_.faults;
  if (f.garbage_probability > 0.0 && uniform() < f.garbage_probability) {
    std::array<std::uint8_t, 16> junk{};
    const std::size_t n = 1 + static_cast<std::size_t>(next_random() % junk.size());
    for (std::size_t k = 0; k < n; ++k) junk[k] = static_cast<std::uint8_t>(next_random());
    put({junk.data(), n});
    ++stats_.garbage_bursts;
  }
  corrupt_next_ =
      f.corrupt_checksum_probability > 0.0 && uniform() < f.corrupt_checksum_probability;
  if (binary_) {
    emit_binary();
  } else {
    emit_ascii();
  }
  ++stats_.data_messages;
  ++sequence_;
}

void Emulator::emit_ascii() {
  const msg::ImuSample& s = truth_;
  const auto q = quaternion_xyzw(s.roll_deg, s.pitch_deg, s.yaw_magnetic_deg);
  const std::string_view name = kAsciiNames[static_cast<std::size_t>(ascii_format_)];
  Text t;
  t.add("$%.*s,%02u", static_cast<int>(name.size()), name.data(), static_cast<unsigned>(sequence_));
  const bool euler = ascii_format_ == AsciiFormat::kRpy || ascii_format_ == AsciiFormat::kRpyImu;
  const bool quat = ascii_format_ == AsciiFormat::kQuat || ascii_format_ == AsciiFormat::kQuatImu;
  const bool imu = ascii_format_ == AsciiFormat::kRpyImu ||
                   ascii_format_ == AsciiFormat::kQuatImu || ascii_format_ == AsciiFormat::kImu;
  if (euler) t.add(",%.2f,%.2f,%.2f", s.roll_deg, s.pitch_deg, s.yaw_magnetic_deg);
  if (quat) t.add(",%.4f,%.4f,%.4f,%.4f", q[0], q[1], q[2], q[3]);
  if (imu) {
    for (const double v : s.accel_g) t.add(",%.4f", v);
    for (const double v : s.gyro_dps) t.add(",%.4f", v);
    for (const double v : s.mag_ut) t.add(",%.4f", v);
    t.add(",%.1f", s.temperature_c);
  }
  if (ascii_format_ == AsciiFormat::kRiImu) {
    for (const double v : s.accel_g) t.add(",%d", static_cast<int>(to_i16(v / kAccelGPerLsb)));
    for (const double v : s.gyro_dps) t.add(",%d", static_cast<int>(to_i16(v / kGyroDpsPerLsb)));
    for (const double v : s.mag_ut) t.add(",%d", static_cast<int>(to_i16(v / kMagUtPerLsb)));
    t.add(",0");  // raw temperature scale is undocumented (docs/protocols.md 2.4)
  }
  put_line(t.buf.data(), t.n, true);
}

void Emulator::emit_binary() {
  const msg::ImuSample& s = truth_;
  std::array<std::uint8_t, 160> body{};
  std::size_t n = 0;
  const auto byte = [&](std::uint8_t b) { body[n++] = b; };
  const auto i16 = [&](std::int16_t v) {
    const auto u = static_cast<std::uint16_t>(v);
    byte(static_cast<std::uint8_t>(u & 0xFF));
    byte(static_cast<std::uint8_t>(u >> 8));
  };
  const BinaryFormat& f = binary_format_;
  const int nodes = int{f.euler} + int{f.quaternion} + int{f.raw_imu} + int{f.imu};
  int written = 0;
  const auto list_node = [&](char name, std::uint8_t count) {
    ++written;
    byte(static_cast<std::uint8_t>(codec::kTagList | static_cast<std::uint8_t>(3) |
                                   (written < nodes ? codec::kTagNextNode : 0)));
    byte(static_cast<std::uint8_t>(name));
    byte(0);
    byte(count);
    byte(0);
  };
  byte(codec::kTagHasLeaves);  // root "d": no value, leaves follow
  byte('d');
  byte(0);
  byte(static_cast<std::uint8_t>(2 | (nodes > 0 ? codec::kTagNextNode : 0)));  // "s": u8
  byte('s');
  byte(0);
  byte(sequence_);
  if (f.euler) {
    list_node('e', 3);
    i16(scale_i16(s.roll_deg, codec::kEulerRangeDeg));
    i16(scale_i16(s.pitch_deg, codec::kEulerRangeDeg));
    i16(scale_i16(s.yaw_magnetic_deg, codec::kEulerRangeDeg));
  }
  if (f.quaternion) {
    list_node('q', 4);
    for (const double v : quaternion_xyzw(s.roll_deg, s.pitch_deg, s.yaw_magnetic_deg)) {
      i16(scale_i16(v, codec::kQuaternionRange));
    }
  }
  if (f.raw_imu) {
    list_node('r', 10);
    for (const double v : s.accel_g) i16(to_i16(v / kAccelGPerLsb));
    for (const double v : s.gyro_dps) i16(to_i16(v / kGyroDpsPerLsb));
    for (const double v : s.mag_ut) i16(to_i16(v / kMagUtPerLsb));
    i16(0);  // raw temperature scale is undocumented
  }
  if (f.imu) {
    list_node('i', 10);
    for (const double v : s.accel_g) i16(scale_i16(v, codec::kAccelRangeG));
    for (const double v : s.gyro_dps) i16(scale_i16(v, codec::kGyroRangeDps));
    for (const double v : s.mag_ut) i16(scale_i16(v, codec::kMagRange));
    i16(scale_i16(s.temperature_c, codec::kTemperatureRangeC));
  }
  std::uint8_t cs = codec::xor_checksum(std::span<const std::uint8_t>(body.data(), n));
  if (corrupt_next_) {
    cs ^= 0x5A;
    ++stats_.corrupted_messages;
  }
  body[n++] = cs;

  std::array<std::uint8_t, 2 * 160 + 4> wire{};
  std::size_t w = 0;
  wire[w++] = codec::kDle;
  wire[w++] = codec::kStx;
  for (std::size_t k = 0; k < n; ++k) {
    wire[w++] = body[k];
    if (body[k] == codec::kDle) wire[w++] = codec::kDle;
  }
  wire[w++] = codec::kDle;
  wire[w++] = codec::kEtx;
  put({wire.data(), w});
}

}  // namespace coxswain::sim::devices::myahrs
