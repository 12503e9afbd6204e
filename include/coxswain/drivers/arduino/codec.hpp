// SPDX-License-Identifier: Apache-2.0
#pragma once
// Daemon side of the NUC <-> Arduino protocol (spec: tools/arduino/PROTOCOL.md). Wraps the
// portable FrameDecoder/encoders of wire.hpp (shared with the firmware) in the codec convention
// of coxswain/drivers/codec.hpp and converts to and from the core's messages.
#include <array>
#include <cstdint>
#include <span>

#include "coxswain/core/time.hpp"
#include "coxswain/drivers/arduino/wire.hpp"
#include "coxswain/drivers/codec.hpp"
#include "coxswain/msg/actuator_command.hpp"
#include "coxswain/msg/arduino_status.hpp"

namespace coxswain::drivers::arduino {

/// One board -> host message; only the member named by `type` is meaningful.
struct BoardMessage {
  MsgType type = MsgType::kTelemetry;
  std::uint16_t seq = 0;
  Ready ready{};
  Pong pong{};
  Telemetry telemetry{};
};

/// Pure decoder of the board's byte stream (Ready, Pong, Telemetry). Host -> board and unknown
/// types are counted as `unsupported`; known types with a wrong payload length as framing errors.
/// No allocation; not thread-safe (one instance per link).
class ArduinoCodec {
 public:
  /// Codec convention: consumes bytes until one message is produced or the input ends. An empty
  /// span delivers a frame held back by a resync (call it at end of input until !produced).
  [[nodiscard]] DecodeStep decode(std::span<const std::uint8_t> bytes);
  [[nodiscard]] const BoardMessage& message() const { return message_; }
  [[nodiscard]] CodecStats stats() const;

 private:
  FrameDecoder decoder_;
  BoardMessage message_;
  std::uint64_t messages_out_ = 0;
  std::uint64_t malformed_ = 0;
  std::uint64_t unsupported_ = 0;
};

/// Encodes host -> board frames into an internal buffer. SetOutputs frames carry an incrementing
/// sequence number (wrapping at 2^16; the board counts gaps and drops repeats); Hello and Ping
/// carry the current value without advancing it. Not thread-safe.
class CommandEncoder {
 public:
  explicit CommandEncoder(std::uint16_t first_seq = 0) : seq_(first_seq) {}
  /// The returned view is valid until the next encode call.
  std::span<const std::uint8_t> encode(const msg::ActuatorCommand& cmd);
  std::span<const std::uint8_t> encode_hello();
  std::span<const std::uint8_t> encode_ping(std::uint32_t token);
  [[nodiscard]] std::uint16_t next_seq() const { return seq_; }

 private:
  std::array<std::uint8_t, kMaxFrame> buf_{};
  std::uint16_t seq_;
};

/// ActuatorCommand -> SetOutputs payload (active -> kFlagArm; LedColour numbering is shared).
[[nodiscard]] SetOutputs to_set_outputs(const msg::ActuatorCommand& cmd);

/// Telemetry -> ArduinoStatus, stamped with the adapter's receive time. Unknown LED or mode
/// values map to kOff / kManual (the safe reading).
[[nodiscard]] msg::ArduinoStatus to_status(const Telemetry& tel, core::TimeNs stamp_ns);

}  // namespace coxswain::drivers::arduino
