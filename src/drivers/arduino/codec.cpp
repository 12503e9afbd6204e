// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/arduino/codec.hpp"

namespace coxswain::drivers::arduino {

DecodeStep ArduinoCodec::decode(std::span<const std::uint8_t> bytes) {
  DecodeStep step;
  for (;;) {
    bool produced = false;
    const std::size_t used = decoder_.decode(bytes.data(), bytes.size(), &produced);
    step.consumed += used;
    bytes = bytes.subspan(used);
    if (!produced) {
      return step;
    }
    const Frame& f = decoder_.frame();
    bool ok = false;
    bool known = true;
    switch (static_cast<MsgType>(f.type)) {
      case MsgType::kReady:
        ok = parse(f, &message_.ready);
        break;
      case MsgType::kPong:
        ok = parse(f, &message_.pong);
        break;
      case MsgType::kTelemetry:
        ok = parse(f, &message_.telemetry);
        break;
      default:
        known = false;
        break;
    }
    if (ok) {
      message_.type = static_cast<MsgType>(f.type);
      message_.seq = f.seq;
      ++messages_out_;
      step.produced = true;
      return step;
    }
    if (known) {
      ++malformed_;
    } else {
      ++unsupported_;
    }
    // A frame that yields no message: keep scanning (with empty input this drains frames held
    // back by a resync).
  }
}

CodecStats ArduinoCodec::stats() const {
  const DecoderStats& d = decoder_.stats();
  CodecStats s;
  s.bytes_in = d.bytes_in;
  s.frames_ok = d.frames_ok;
  s.messages_out = messages_out_;
  s.checksum_errors = d.crc_errors;
  s.framing_errors = d.framing_errors + malformed_;
  s.bytes_skipped = d.bytes_skipped;
  s.unsupported = unsupported_;
  return s;
}

std::span<const std::uint8_t> CommandEncoder::encode(const msg::ActuatorCommand& cmd) {
  const std::size_t n = arduino::encode(to_set_outputs(cmd), seq_, buf_.data(), buf_.size());
  ++seq_;
  return {buf_.data(), n};
}

std::span<const std::uint8_t> CommandEncoder::encode_hello() {
  const Hello hello{kProtocolVersion};
  return {buf_.data(), arduino::encode(hello, seq_, buf_.data(), buf_.size())};
}

std::span<const std::uint8_t> CommandEncoder::encode_ping(std::uint32_t token) {
  const Ping ping{token};
  return {buf_.data(), arduino::encode(ping, seq_, buf_.data(), buf_.size())};
}

SetOutputs to_set_outputs(const msg::ActuatorCommand& cmd) {
  SetOutputs out{};
  for (std::size_t c = 0; c < kChannels; ++c) {
    out.pulse_us[c] = cmd.pulse_us[c];
  }
  out.led = static_cast<std::uint8_t>(cmd.led);
  out.flags = cmd.active ? kFlagArm : std::uint8_t{0};
  return out;
}

msg::ArduinoStatus to_status(const Telemetry& tel, core::TimeNs stamp_ns) {
  msg::ArduinoStatus s;
  s.stamp_ns = stamp_ns;
  for (std::size_t c = 0; c < kChannels; ++c) {
    s.applied_pulse_us[c] = tel.applied_pulse_us[c];
  }
  s.led = tel.led <= static_cast<std::uint8_t>(msg::LedColour::kWhite)
              ? static_cast<msg::LedColour>(tel.led)
              : msg::LedColour::kOff;
  s.mode = tel.mode == static_cast<std::uint8_t>(Mode::kAutonomous) ? msg::ControlMode::kAutonomous
                                                                    : msg::ControlMode::kManual;
  s.estop = (tel.flags & kTelEstop) != 0;
  s.rc_present = (tel.flags & kTelRcPresent) != 0;
  s.failsafe = (tel.flags & kTelFailsafe) != 0;
  s.start_switch = (tel.flags & kTelStartSwitch) != 0;
  s.supply_v = static_cast<double>(tel.supply_mv) / 1000.0;
  s.last_sequence_seen = tel.last_seq;
  return s;
}

}  // namespace coxswain::drivers::arduino
