// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/myahrs/codec.hpp"

#include <charconv>
#include <cmath>
#include <system_error>

namespace coxswain::drivers::myahrs {
namespace {

bool is_start_char(std::uint8_t b) { return b == '$' || b == '~' || b == '@'; }

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  // The device prints upper case; lower case is accepted like the vendor SDK (strtoul) does.
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

bool parse_double(std::string_view s, double& out) {
  if (s.empty()) return false;
  const char* first = s.data();
  const char* last = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(first, last, out);
  return ec == std::errc{} && ptr == last && std::isfinite(out);
}

template <typename Int>
bool parse_int(std::string_view s, Int& out) {
  if (s.empty()) return false;
  const char* last = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), last, out);
  return ec == std::errc{} && ptr == last;
}

std::size_t value_size(ValueType t) {
  switch (t) {
    case ValueType::kI8:
    case ValueType::kU8:
      return 1;
    case ValueType::kI16:
    case ValueType::kU16:
      return 2;
    case ValueType::kI32:
    case ValueType::kU32:
    case ValueType::kF32:
      return 4;
    case ValueType::kI64:
    case ValueType::kU64:
    case ValueType::kF64:
      return 8;
    case ValueType::kNone:
    case ValueType::kString:
      return 0;
  }
  return 0;
}

bool is_integer(ValueType t) { return t >= ValueType::kI8 && t <= ValueType::kU64; }

std::int16_t read_i16(const std::uint8_t* p) {
  return static_cast<std::int16_t>(static_cast<std::uint16_t>(p[0] | (p[1] << 8)));
}

double scaled(const std::uint8_t* p, double range) {
  return static_cast<double>(read_i16(p)) / kBinaryFullScale * range;
}

// One ASCII data sentence layout: attitude values (0, 3 = RPY, 4 = QUAT), then 10 IMU values.
struct SentenceLayout {
  std::string_view name;
  std::size_t attitude_values;
  bool calibrated_imu;
  bool raw_imu;
};

constexpr std::array<SentenceLayout, 6> kSentences{{
    {"RPY", 3, false, false},
    {"QUAT", 4, false, false},
    {"RPYIMU", 3, true, false},
    {"QUATIMU", 4, true, false},
    {"IMU", 0, true, false},
    {"RIIMU", 0, false, true},
}};

}  // namespace

std::uint8_t xor_checksum(std::span<const std::uint8_t> bytes) {
  std::uint8_t x = 0;
  for (const std::uint8_t b : bytes) x = static_cast<std::uint8_t>(x ^ b);
  return x;
}

std::uint8_t xor_checksum(std::string_view text) {
  std::uint8_t x = 0;
  for (const char c : text) x = static_cast<std::uint8_t>(x ^ static_cast<std::uint8_t>(c));
  return x;
}

std::optional<std::string_view> CommandResponse::attribute(std::string_view name) const {
  for (const Attribute& a : attributes) {
    if (a.name == name) return a.value;
  }
  return std::nullopt;
}

Decoder::Decoder(const HeadingConfig& heading) : heading_(heading) {}

void Decoder::reset() {
  state_ = State::kIdle;
  line_len_ = 0;
  frame_len_ = 0;
  last_output_ = Output::kNone;
  response_ = CommandResponse{};
}

DecodeStep Decoder::decode(std::span<const std::uint8_t> bytes) {
  last_output_ = Output::kNone;
  DecodeStep step;
  while (step.consumed < bytes.size()) {
    const bool produced = on_byte(bytes[step.consumed]);
    ++step.consumed;
    if (produced) {
      step.produced = true;
      ++stats_.codec.messages_out;
      break;
    }
  }
  stats_.codec.bytes_in += step.consumed;
  return step;
}

void Decoder::framing_error(std::uint64_t& counter) {
  ++counter;
  ++stats_.codec.framing_errors;
}

void Decoder::abort_ascii(std::uint64_t& counter) {
  framing_error(counter);
  line_len_ = 0;
  state_ = State::kIdle;
}

void Decoder::start_ascii(std::uint8_t b) {
  line_[0] = static_cast<char>(b);
  line_len_ = 1;
  state_ = State::kAscii;
}

void Decoder::start_binary() {
  frame_len_ = 0;
  state_ = State::kBinary;
}

bool Decoder::on_byte(std::uint8_t b) {
  switch (state_) {
    case State::kIdle:
      if (is_start_char(b)) {
        start_ascii(b);
      } else if (b == kDle) {
        state_ = State::kIdleDle;
      } else {
        ++stats_.codec.bytes_skipped;
      }
      return false;

    case State::kIdleDle:
      if (b == kStx) {
        start_binary();
        return false;
      }
      ++stats_.codec.bytes_skipped;  // the lone DLE; look at `b` afresh
      state_ = State::kIdle;
      return on_byte(b);

    case State::kAscii:
      if (b == '\n') return finish_line();
      if (b == '\r') return false;  // ignored anywhere, like the vendor SDK
      if (is_start_char(b)) {
        abort_ascii(stats_.ascii_interrupted);
        start_ascii(b);
        return false;
      }
      if (b == kDle) {
        abort_ascii(stats_.ascii_interrupted);
        state_ = State::kIdleDle;
        return false;
      }
      if (b < 0x20 || b > 0x7E) {
        abort_ascii(stats_.ascii_bad_byte);
        return false;
      }
      if (line_len_ >= kMaxLineBytes) {
        abort_ascii(stats_.ascii_overlong);
        return false;
      }
      line_[line_len_++] = static_cast<char>(b);
      return false;

    case State::kBinary:
      if (b == kDle) {
        state_ = State::kBinaryDle;
        return false;
      }
      if (frame_len_ >= kMaxFrameBytes) {
        framing_error(stats_.binary_overlong);
        state_ = State::kIdle;
        return false;
      }
      frame_[frame_len_++] = b;
      return false;

    case State::kBinaryDle:
      if (b == kDle) {
        if (frame_len_ >= kMaxFrameBytes) {
          framing_error(stats_.binary_overlong);
          state_ = State::kIdle;
          return false;
        }
        frame_[frame_len_++] = kDle;
        state_ = State::kBinary;
        return false;
      }
      if (b == kEtx) {
        state_ = State::kIdle;
        return finish_frame();
      }
      framing_error(stats_.binary_aborted);
      if (b == kStx) {
        start_binary();  // a new frame began before this one ended
        return false;
      }
      state_ = State::kIdle;
      return on_byte(b);
  }
  return false;
}

bool Decoder::finish_line() {
  state_ = State::kIdle;
  const std::string_view line(line_.data(), line_len_);
  line_len_ = 0;

  const std::size_t star = line.find('*');
  if (star == std::string_view::npos || line.size() - star != 3) {
    framing_error(stats_.ascii_bad_checksum_field);
    return false;
  }
  const int hi = hex_value(line[star + 1]);
  const int lo = hex_value(line[star + 2]);
  if (hi < 0 || lo < 0) {
    framing_error(stats_.ascii_bad_checksum_field);
    return false;
  }
  const std::string_view body = line.substr(0, star);
  if (xor_checksum(body) != static_cast<std::uint8_t>(hi * 16 + lo)) {
    ++stats_.ascii_checksum_errors;
    ++stats_.codec.checksum_errors;
    return false;
  }
  ++stats_.codec.frames_ok;
  ++stats_.ascii_lines_ok;

  std::size_t n = 0;
  std::size_t begin = 0;
  while (true) {
    const std::size_t comma = body.find(',', begin);
    if (n >= kMaxFields) {
      framing_error(stats_.ascii_bad_fields);
      return false;
    }
    fields_[n++] = body.substr(begin, comma == std::string_view::npos ? body.npos : comma - begin);
    if (comma == std::string_view::npos) break;
    begin = comma + 1;
  }
  const std::span<const std::string_view> fields(fields_.data(), n);

  switch (body[0]) {
    case '$':
      return parse_data_sentence(fields);
    case '~':
      return parse_response(fields);
    default:  // '@': a request, not for us
      ++stats_.requests_seen;
      ++stats_.codec.unsupported;
      return false;
  }
}

bool Decoder::parse_data_sentence(std::span<const std::string_view> fields) {
  const std::string_view name = fields[0].substr(1);
  const SentenceLayout* layout = nullptr;
  for (const SentenceLayout& l : kSentences) {
    if (l.name == name) layout = &l;
  }
  if (layout == nullptr) {
    ++stats_.unknown_sentences;
    ++stats_.codec.unsupported;
    return false;
  }
  const bool has_imu = layout->calibrated_imu || layout->raw_imu;
  const std::size_t expected = 2 + layout->attitude_values + (has_imu ? 10 : 0);
  if (fields.size() != expected) {
    framing_error(stats_.ascii_bad_fields);
    return false;
  }

  sample_ = msg::ImuSample{};
  detail_ = SampleDetail{};
  detail_.encoding = Encoding::kAscii;
  if (!parse_int(fields[1], sample_.sequence)) {
    framing_error(stats_.ascii_bad_fields);
    return false;
  }
  std::array<double, 4> att{};
  for (std::size_t k = 0; k < layout->attitude_values; ++k) {
    if (!parse_double(fields[2 + k], att[k])) {
      framing_error(stats_.ascii_bad_fields);
      return false;
    }
  }
  const std::size_t imu_first = 2 + layout->attitude_values;
  if (layout->calibrated_imu) {
    std::array<double, 10> v{};
    for (std::size_t k = 0; k < 10; ++k) {
      if (!parse_double(fields[imu_first + k], v[k])) {
        framing_error(stats_.ascii_bad_fields);
        return false;
      }
    }
    sample_.accel_g = {v[0], v[1], v[2]};
    sample_.gyro_dps = {v[3], v[4], v[5]};
    sample_.mag_ut = {v[6], v[7], v[8]};
    sample_.temperature_c = v[9];
    sample_.has_inertial = true;
  } else if (layout->raw_imu) {
    for (std::size_t k = 0; k < 10; ++k) {
      if (!parse_int(fields[imu_first + k], detail_.raw_imu[k])) {
        framing_error(stats_.ascii_bad_fields);
        return false;
      }
    }
    detail_.has_raw = true;
  }
  if (layout->attitude_values == 3) {
    sample_.roll_deg = att[0];
    sample_.pitch_deg = att[1];
    sample_.yaw_magnetic_deg = att[2];
    detail_.has_attitude = true;
  } else if (layout->attitude_values == 4) {
    const auto e = quaternion_to_euler_deg(att[0], att[1], att[2], att[3]);
    if (!e) {
      framing_error(stats_.ascii_bad_fields);
      return false;
    }
    detail_.has_quaternion = true;
    detail_.quaternion_xyzw = att;
    detail_.from_quaternion = true;
    detail_.has_attitude = true;
    sample_.roll_deg = e->roll_deg;
    sample_.pitch_deg = e->pitch_deg;
    sample_.yaw_magnetic_deg = e->yaw_deg;
  }
  finish_sample();
  return true;
}

void Decoder::finish_sample() {
  if (detail_.has_attitude) {
    sample_.heading_deg = true_heading_deg(sample_.yaw_magnetic_deg, heading_);
  }
  sample_.stamp_ns = core::kNeverNs;
  last_output_ = Output::kSample;
}

bool Decoder::parse_response(std::span<const std::string_view> fields) {
  const std::string_view command = fields[0].substr(1);
  if (command.empty() || fields.size() < 2 || (fields[1] != "OK" && fields[1] != "ERROR")) {
    framing_error(stats_.ascii_bad_fields);
    return false;
  }
  std::size_t n_attr = 0;
  std::size_t n_arg = 0;
  for (std::size_t k = 2; k < fields.size(); ++k) {
    const std::string_view f = fields[k];
    const std::size_t eq = f.find('=');
    if (eq != std::string_view::npos) {
      if (n_attr >= kMaxAttributes) {
        framing_error(stats_.ascii_bad_fields);
        return false;
      }
      attributes_[n_attr++] = Attribute{f.substr(0, eq), f.substr(eq + 1)};
    } else if (n_attr > 0) {
      // A list value (`fmt=EULER, IMU`): the fields are contiguous in the line, so widen the view.
      Attribute& prev = attributes_[n_attr - 1];
      prev.value = std::string_view(
          prev.value.data(), static_cast<std::size_t>(f.data() + f.size() - prev.value.data()));
    } else {
      arguments_[n_arg++] = f;  // n_arg < fields.size() <= kMaxFields
    }
  }
  response_.command = command;
  response_.ok = fields[1] == "OK";
  response_.attributes = std::span<const Attribute>(attributes_.data(), n_attr);
  response_.arguments = std::span<const std::string_view>(arguments_.data(), n_arg);
  if (!response_.ok) ++stats_.error_responses;
  last_output_ = Output::kResponse;
  return true;
}

bool Decoder::finish_frame() {
  const std::size_t len = frame_len_;
  frame_len_ = 0;
  if (len < 2) {  // at least one body byte and the checksum
    framing_error(stats_.binary_malformed);
    return false;
  }
  const std::span<const std::uint8_t> body(frame_.data(), len - 1);
  if (xor_checksum(body) != frame_[len - 1]) {
    ++stats_.binary_checksum_errors;
    ++stats_.codec.checksum_errors;
    return false;
  }
  ++stats_.codec.frames_ok;
  ++stats_.binary_frames_ok;
  return parse_binary_body(body);
}

bool Decoder::parse_binary_body(std::span<const std::uint8_t> body) {
  sample_ = msg::ImuSample{};
  detail_ = SampleDetail{};
  detail_.encoding = Encoding::kBinary;
  const std::uint8_t* e_values = nullptr;
  const std::uint8_t* q_values = nullptr;
  const std::uint8_t* i_values = nullptr;
  const std::uint8_t* r_values = nullptr;

  const std::size_t size = body.size();
  std::size_t pos = 0;
  while (pos < size) {
    const std::uint8_t tag = body[pos++];
    const std::uint8_t type_bits = tag & kTagTypeMask;
    if (type_bits > static_cast<std::uint8_t>(ValueType::kString)) {
      framing_error(stats_.binary_malformed);
      return false;
    }
    const auto type = static_cast<ValueType>(type_bits);
    const std::size_t name_begin = pos;
    while (pos < size && body[pos] != 0) ++pos;
    if (pos >= size) {
      framing_error(stats_.binary_malformed);
      return false;
    }
    const std::string_view name(reinterpret_cast<const char*>(body.data() + name_begin),
                                pos - name_begin);
    ++pos;  // NUL
    const bool list = (tag & kTagList) != 0;
    std::size_t count = 0;
    if (type != ValueType::kNone) {
      count = 1;
      if (list) {
        if (size - pos < 2) {
          framing_error(stats_.binary_malformed);
          return false;
        }
        count = static_cast<std::size_t>(body[pos] | (body[pos + 1] << 8));
        pos += 2;
      }
    }
    const std::uint8_t* values = body.data() + pos;
    if (type == ValueType::kString) {
      for (std::size_t k = 0; k < count; ++k) {
        while (pos < size && body[pos] != 0) ++pos;
        if (pos >= size) {
          framing_error(stats_.binary_malformed);
          return false;
        }
        ++pos;
      }
    } else {
      const std::size_t bytes = count * value_size(type);
      if (size - pos < bytes) {
        framing_error(stats_.binary_malformed);
        return false;
      }
      pos += bytes;
    }

    const auto expect_i16_list = [&](std::size_t n) {
      return type == ValueType::kI16 && list && count == n;
    };
    bool shape_ok = true;
    if (name == "s") {
      shape_ok = is_integer(type) && count == 1;
      if (shape_ok) {
        std::uint64_t v = 0;
        for (std::size_t k = value_size(type); k > 0; --k) v = (v << 8) | values[k - 1];
        sample_.sequence = static_cast<unsigned>(v);
      }
    } else if (name == "e") {
      shape_ok = expect_i16_list(3);
      e_values = values;
    } else if (name == "q") {
      shape_ok = expect_i16_list(4);
      q_values = values;
    } else if (name == "i") {
      shape_ok = expect_i16_list(10);
      i_values = values;
    } else if (name == "r") {
      shape_ok = expect_i16_list(10);
      r_values = values;
    }
    if (!shape_ok) {
      framing_error(stats_.binary_malformed);
      return false;
    }
    if ((tag & (kTagNextNode | kTagHasLeaves)) == 0) break;  // trailing bytes are ignored (SDK)
  }

  if (e_values == nullptr && q_values == nullptr && i_values == nullptr && r_values == nullptr) {
    ++stats_.binary_without_data;
    ++stats_.codec.unsupported;
    return false;
  }
  if (q_values != nullptr) {
    for (std::size_t k = 0; k < 4; ++k) {
      detail_.quaternion_xyzw[k] = scaled(q_values + 2 * k, kQuaternionRange);
    }
    detail_.has_quaternion = true;
  }
  if (e_values != nullptr) {
    sample_.roll_deg = scaled(e_values, kEulerRangeDeg);
    sample_.pitch_deg = scaled(e_values + 2, kEulerRangeDeg);
    sample_.yaw_magnetic_deg = scaled(e_values + 4, kEulerRangeDeg);
    detail_.has_attitude = true;
  } else if (q_values != nullptr) {
    const auto& q = detail_.quaternion_xyzw;
    const auto e = quaternion_to_euler_deg(q[0], q[1], q[2], q[3]);
    if (!e) {
      framing_error(stats_.binary_malformed);
      return false;
    }
    sample_.roll_deg = e->roll_deg;
    sample_.pitch_deg = e->pitch_deg;
    sample_.yaw_magnetic_deg = e->yaw_deg;
    detail_.has_attitude = true;
    detail_.from_quaternion = true;
  }
  if (i_values != nullptr) {
    for (std::size_t k = 0; k < 3; ++k) {
      sample_.accel_g[k] = scaled(i_values + 2 * k, kAccelRangeG);
      sample_.gyro_dps[k] = scaled(i_values + 6 + 2 * k, kGyroRangeDps);
      sample_.mag_ut[k] = scaled(i_values + 12 + 2 * k, kMagRange);
    }
    sample_.temperature_c = scaled(i_values + 18, kTemperatureRangeC);
    sample_.has_inertial = true;
  }
  if (r_values != nullptr) {
    for (std::size_t k = 0; k < 10; ++k) detail_.raw_imu[k] = read_i16(r_values + 2 * k);
    detail_.has_raw = true;
  }
  finish_sample();
  return true;
}

}  // namespace coxswain::drivers::myahrs
