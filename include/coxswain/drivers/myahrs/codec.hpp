// SPDX-License-Identifier: Apache-2.0
#pragma once
// Withrobot myAHRS+ AHRS: pure stream decoder for both output forms the device can interleave
// on one serial line. Protocol: docs/protocols.md section 2 (ASCII framing 2.2,
// responses 2.3, data sentences 2.4, binary frames 2.5) and section 6 (doc errors).
//
// ASCII:  `$NAME,seq,v1,...*CC\r\n` data, `~cmd,OK|ERROR,attr=value,...*CC\r\n` responses,
//         `@cmd...*CC\r\n` requests (ours, if echoed or seen on a tap). CC = XOR of every byte
//         from the start character up to '*', two hex digits. A start character `$ ~ @` restarts
//         the frame (as the vendor SDK does); CR is ignored; LF ends the line.
// Binary: DLE STX body checksum DLE ETX, where 0x10 inside is sent as 0x10 0x10 and checksum =
//         XOR of the unstuffed body. Body = chain of tagged nodes; the decoder reads nodes `s`
//         (sequence), `e` (Euler), `q` (quaternion), `i` (calibrated IMU), `r` (raw IMU) and skips
//         others. Scaled values are int16 / 32767 * range.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "coxswain/drivers/codec.hpp"
#include "coxswain/drivers/myahrs/heading.hpp"
#include "coxswain/msg/imu_sample.hpp"

namespace coxswain::drivers::myahrs {

inline constexpr std::uint8_t kDle = 0x10;
inline constexpr std::uint8_t kStx = 0x02;
inline constexpr std::uint8_t kEtx = 0x03;

/// Longest ASCII line kept (start char to last checksum digit). The longest real line, a
/// `~calib` response with 12 parameters in e-notation, is about 200 bytes.
inline constexpr std::size_t kMaxLineBytes = 512;
/// Longest unstuffed binary frame (body + checksum). A full e+q+i+r frame is under 100 bytes.
inline constexpr std::size_t kMaxFrameBytes = 512;
inline constexpr std::size_t kMaxFields = 48;
inline constexpr std::size_t kMaxAttributes = 32;

/// Binary node scales (value = int16 / 32767 * range), docs/protocols.md 2.5.
inline constexpr double kBinaryFullScale = 32767.0;
inline constexpr double kEulerRangeDeg = 180.0;
inline constexpr double kQuaternionRange = 1.0;
inline constexpr double kAccelRangeG = 16.0;
inline constexpr double kGyroRangeDps = 2000.0;
inline constexpr double kMagRange = 300.0;
inline constexpr double kTemperatureRangeC = 200.0;

/// Binary node tag bits (docs/protocols.md 2.5).
inline constexpr std::uint8_t kTagTypeMask = 0x0F;
inline constexpr std::uint8_t kTagList = 0x20;
inline constexpr std::uint8_t kTagNextNode = 0x40;
inline constexpr std::uint8_t kTagHasLeaves = 0x80;
enum class ValueType : std::uint8_t {
  kNone = 0,
  kI8 = 1,
  kU8 = 2,
  kI16 = 3,
  kU16 = 4,
  kI32 = 5,
  kU32 = 6,
  kI64 = 7,
  kU64 = 8,
  kF32 = 9,
  kF64 = 10,
  kString = 11,
};

/// What the last decode() call produced.
enum class Output : std::uint8_t { kNone, kSample, kResponse };
enum class Encoding : std::uint8_t { kAscii, kBinary };

/// What a sample carries besides msg::ImuSample (which has no room for these).
struct SampleDetail {
  Encoding encoding = Encoding::kAscii;
  bool has_attitude = false;     // roll/pitch/yaw_magnetic/heading valid
  bool from_quaternion = false;  // attitude computed from the quaternion (QUAT-only output)
  bool has_quaternion = false;
  std::array<double, 4> quaternion_xyzw{0.0, 0.0, 0.0, 1.0};
  /// `$RIIMU` / node `r`: uncalibrated integers ax ay az gx gy gz mx my mz temperature (LSB).
  /// They are NOT converted into the calibrated fields of msg::ImuSample.
  bool has_raw = false;
  std::array<std::int32_t, 10> raw_imu{};
};

/// `name=value` of a response. Views into the decoder's buffer.
struct Attribute {
  std::string_view name;   // may contain spaces (`acc range`), docs/protocols.md 2.2
  std::string_view value;  // a list value keeps its commas: `fmt=EULER, IMU`
};

/// One `~cmd,OK|ERROR,...` line. Views stay valid until the next decode() or reset().
struct CommandResponse {
  std::string_view command;  // without '~': "version", "divider", ...
  bool ok = false;
  std::span<const Attribute> attributes;
  std::span<const std::string_view> arguments;  // fields without '=' before any attribute

  /// The value of attribute `name`, if present.
  [[nodiscard]] std::optional<std::string_view> attribute(std::string_view name) const;
};

/// Every error kind, beside the shared CodecStats (which aggregates them).
struct DecoderStats {
  CodecStats codec;
  std::uint64_t ascii_lines_ok = 0;
  std::uint64_t binary_frames_ok = 0;
  std::uint64_t ascii_checksum_errors = 0;
  std::uint64_t binary_checksum_errors = 0;
  std::uint64_t ascii_bad_checksum_field = 0;  // no '*', two '*', not exactly 2 hex digits
  std::uint64_t ascii_overlong = 0;            // line longer than kMaxLineBytes
  std::uint64_t ascii_bad_byte = 0;            // control or non-ASCII byte inside a line
  std::uint64_t ascii_interrupted = 0;         // line restarted by `$ ~ @` or DLE before LF
  std::uint64_t ascii_bad_fields = 0;          // wrong field count, unparsable number, bad status
  std::uint64_t binary_overlong = 0;           // frame longer than kMaxFrameBytes
  std::uint64_t binary_aborted = 0;            // DLE followed by something other than 10/02/03
  std::uint64_t binary_malformed = 0;          // truncated node chain, wrong node type or count
  std::uint64_t unknown_sentences = 0;         // checksummed `$` line of an unknown name
  std::uint64_t binary_without_data = 0;       // checksummed frame with no s/e/q/i/r data node
  std::uint64_t requests_seen = 0;             // checksummed `@` lines (not for us)
  std::uint64_t error_responses = 0;           // `~cmd,ERROR`
};

/// Pure myAHRS+ stream decoder (codec.hpp convention): bytes in, at most one sample or response
/// per decode() call. Fixed buffers, no allocation, no exceptions, no clock: the sample's
/// stamp_ns stays kNeverNs for the adapter to set. The heading is computed here with
/// true_heading_deg() from the configured mount yaw and declination.
/// Thread-safety: none (one instance per stream, used by one thread).
class Decoder {
 public:
  explicit Decoder(const HeadingConfig& heading = {});

  [[nodiscard]] DecodeStep decode(std::span<const std::uint8_t> bytes);

  [[nodiscard]] Output last_output() const { return last_output_; }
  /// Valid after decode() produced Output::kSample.
  [[nodiscard]] const msg::ImuSample& sample() const { return sample_; }
  [[nodiscard]] const SampleDetail& sample_detail() const { return detail_; }
  /// Valid after decode() produced Output::kResponse, until the next decode() or reset().
  [[nodiscard]] const CommandResponse& response() const { return response_; }
  [[nodiscard]] const DecoderStats& stats() const { return stats_; }
  [[nodiscard]] const HeadingConfig& heading_config() const { return heading_; }

  /// Drops any partial frame (e.g. after a reconnect); counters are kept.
  void reset();

 private:
  enum class State : std::uint8_t { kIdle, kIdleDle, kAscii, kBinary, kBinaryDle };

  // Each returns true when a message was produced.
  bool on_byte(std::uint8_t b);
  bool finish_line();
  bool finish_frame();
  bool parse_data_sentence(std::span<const std::string_view> fields);
  bool parse_response(std::span<const std::string_view> fields);
  bool parse_binary_body(std::span<const std::uint8_t> body);
  void start_ascii(std::uint8_t b);
  void start_binary();
  void abort_ascii(std::uint64_t& counter);
  void framing_error(std::uint64_t& counter);
  void finish_sample();

  HeadingConfig heading_;
  State state_ = State::kIdle;
  Output last_output_ = Output::kNone;

  std::array<char, kMaxLineBytes> line_{};
  std::size_t line_len_ = 0;
  std::array<std::uint8_t, kMaxFrameBytes> frame_{};
  std::size_t frame_len_ = 0;

  std::array<std::string_view, kMaxFields> fields_{};
  std::array<Attribute, kMaxAttributes> attributes_{};
  std::array<std::string_view, kMaxFields> arguments_{};

  msg::ImuSample sample_;
  SampleDetail detail_;
  CommandResponse response_;
  DecoderStats stats_;
};

/// XOR of the bytes, the checksum of both forms.
[[nodiscard]] std::uint8_t xor_checksum(std::span<const std::uint8_t> bytes);
[[nodiscard]] std::uint8_t xor_checksum(std::string_view text);

}  // namespace coxswain::drivers::myahrs
