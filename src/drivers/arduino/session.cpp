// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/arduino/session.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>

namespace coxswain::drivers::arduino {
namespace {

CodecStats minus(const CodecStats& a, const CodecStats& b) {
  CodecStats d;
  d.bytes_in = a.bytes_in - b.bytes_in;
  d.frames_ok = a.frames_ok - b.frames_ok;
  d.messages_out = a.messages_out - b.messages_out;
  d.checksum_errors = a.checksum_errors - b.checksum_errors;
  d.framing_errors = a.framing_errors - b.framing_errors;
  d.bytes_skipped = a.bytes_skipped - b.bytes_skipped;
  d.unsupported = a.unsupported - b.unsupported;
  return d;
}

CodecStats plus(const CodecStats& a, const CodecStats& b) {
  CodecStats d;
  d.bytes_in = a.bytes_in + b.bytes_in;
  d.frames_ok = a.frames_ok + b.frames_ok;
  d.messages_out = a.messages_out + b.messages_out;
  d.checksum_errors = a.checksum_errors + b.checksum_errors;
  d.framing_errors = a.framing_errors + b.framing_errors;
  d.bytes_skipped = a.bytes_skipped + b.bytes_skipped;
  d.unsupported = a.unsupported + b.unsupported;
  return d;
}

const char* source_name(std::uint8_t source) {
  switch (static_cast<OutputSource>(source)) {
    case OutputSource::kBootHold:
      return "boot hold";
    case OutputSource::kEstop:
      return "e-stop";
    case OutputSource::kNoRc:
      return "no RC";
    case OutputSource::kRcManual:
      return "RC manual";
    case OutputSource::kHost:
      return "host";
    case OutputSource::kFailsafe:
      return "failsafe";
    case OutputSource::kDisarmed:
      return "disarmed";
  }
  return "unknown";
}

}  // namespace

ArduinoSession::ArduinoSession(const config::ArduinoDeviceConfig& config,
                               const config::ActuatorsConfig& actuators,
                               const core::LatestSlot<msg::ActuatorCommand>& command,
                               core::LatestSlot<msg::ArduinoStatus>& status)
    : config_(config),
      actuators_(actuators),
      command_(command),
      status_(status),
      period_ns_(static_cast<core::TimeNs>(
          std::llround(1e9 / std::clamp(actuators.command_rate_hz, 1.0, 1000.0)))) {
  if (actuators_.layout == msg::ActuatorLayout::kServoThruster) {
    neutral_us_ = {actuators_.servo.center_us, actuators_.thruster.neutral_us};
  } else {
    neutral_us_ = {actuators_.thruster.neutral_us, actuators_.thruster.neutral_us};
  }
  note("not opened yet");
}

void ArduinoSession::note(const char* fmt, ...) {
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(detail_.data(), detail_.size(), fmt, args);
  va_end(args);
}

CodecStats ArduinoSession::counted() const {
  return counting_ ? plus(earlier_, minus(codec_.stats(), baseline_)) : earlier_;
}

void ArduinoSession::on_open(DeviceLink& /*link*/, core::TimeNs now_ns) {
  earlier_ = counted();
  codec_ = ArduinoCodec{};
  baseline_ = CodecStats{};
  counting_ = false;
  step_ = ArduinoStep::kBooting;
  opened_ns_ = now_ns;
  boot_deadline_ns_ = now_ns + core::ms_to_ns(kBootGraceMs);
  hellos_ = 0;
  next_command_ns_ = core::kNeverNs;
  verdict_ = SessionVerdict::kContinue;
  note("opened: the board resets on open; waiting for its first frame (bootloader ~1-2 s)");
}

void ArduinoSession::on_close(core::TimeNs /*now_ns*/) {
  step_ = ArduinoStep::kClosed;
  note("port closed");
}

void ArduinoSession::first_contact(bool was_ready, DeviceLink& link) {
  baseline_ = codec_.stats();
  counting_ = true;
  step_ = ArduinoStep::kRunning;
  if (!was_ready) {
    // A board that did not reset still tracks the sequence of our previous connection.
    (void)link.write(encoder_.encode_hello());
  }
}

void ArduinoSession::on_bytes(std::span<const std::uint8_t> bytes, core::TimeNs arrival_ns,
                              DeviceLink& link) {
  while (!bytes.empty()) {
    const DecodeStep s = codec_.decode(bytes);
    bytes = bytes.subspan(s.consumed);
    if (s.produced) on_message(codec_.message(), arrival_ns, link);
    if (s.consumed == 0) break;
  }
  // Frames held back by a resync.
  for (;;) {
    const DecodeStep s = codec_.decode({});
    if (!s.produced) break;
    on_message(codec_.message(), arrival_ns, link);
  }
}

void ArduinoSession::on_message(const BoardMessage& m, core::TimeNs arrival_ns, DeviceLink& link) {
  if (step_ == ArduinoStep::kClosed) return;
  last_frame_ns_ = arrival_ns;
  if (step_ == ArduinoStep::kBooting) {
    first_contact(m.type == MsgType::kReady, link);
    next_command_ns_ = arrival_ns;
  }
  switch (m.type) {
    case MsgType::kReady:
      ready_ = m.ready;
      ++ready_count_;
      if (ready_.failsafe_ms != config_.failsafe_ms) {
        note(
            "board ready fw %u.%u.%u, protocol %u, reset cause 0x%02X; WARNING its failsafe is "
            "%u ms, config says %u ms",
            ready_.fw_major, ready_.fw_minor, ready_.fw_patch, ready_.protocol_version,
            ready_.reset_cause, ready_.failsafe_ms, static_cast<unsigned>(config_.failsafe_ms));
      } else {
        note("board ready fw %u.%u.%u, protocol %u, reset cause 0x%02X, failsafe %u ms",
             ready_.fw_major, ready_.fw_minor, ready_.fw_patch, ready_.protocol_version,
             ready_.reset_cause, ready_.failsafe_ms);
      }
      return;
    case MsgType::kTelemetry: {
      const Telemetry& t = m.telemetry;
      ++telemetry_;
      tel_stamps_[tel_count_ % kRateRing] = arrival_ns;
      ++tel_count_;
      status_.publish(to_status(t, arrival_ns), arrival_ns);
      const auto lag = static_cast<std::uint16_t>(last_sent_seq() - t.last_seq);
      lag_warning_ = commands_sent_ > kSeqLagWarn && lag > kSeqLagWarn && lag < 0x8000U;
      if (lag_warning_) {
        note(
            "WARNING board's last accepted sequence %u lags ours (%u) by %u: commands lost or "
            "not read; board source %s, failsafe %s, rx crc errors %u",
            t.last_seq, last_sent_seq(), lag, source_name(t.source),
            (t.flags & kTelFailsafe) != 0 ? "yes" : "no", t.rx_crc_errors);
      } else {
        note(
            "running: source %s, mode %s, failsafe %s, e-stop %s, RC %s, supply %.2f V, "
            "last seq %u/%u",
            source_name(t.source), t.mode != 0 ? "auto" : "manual",
            (t.flags & kTelFailsafe) != 0 ? "yes" : "no", (t.flags & kTelEstop) != 0 ? "yes" : "no",
            (t.flags & kTelRcPresent) != 0 ? "present" : "absent",
            static_cast<double>(t.supply_mv) / 1000.0, t.last_seq, last_sent_seq());
      }
      return;
    }
    default:
      return;  // Pong: not used by this session
  }
}

void ArduinoSession::send_command(DeviceLink& link, core::TimeNs now_ns) {
  core::Sample<msg::ActuatorCommand> s;
  command_.read(s);
  msg::ActuatorCommand cmd = s.value;
  const bool fresh = s.valid() && now_ns - s.stamp_ns <= core::ms_to_ns(config_.failsafe_ms);
  if (!fresh || !cmd.active) {
    cmd.pulse_us = neutral_us_;
    cmd.active = false;
    if (!s.valid()) cmd.led = msg::LedColour::kOff;
    ++neutral_sent_;
  }
  if (link.write(encoder_.encode(cmd))) {
    ++commands_sent_;
  } else {
    ++write_failures_;
    ++commands_sent_;  // the sequence number was used: the board will count the gap
  }
}

SessionVerdict ArduinoSession::on_poll(DeviceLink& link, core::TimeNs now_ns) {
  switch (step_) {
    case ArduinoStep::kClosed:
      break;
    case ArduinoStep::kBooting:
      if (now_ns >= boot_deadline_ns_) {
        if (hellos_ < kMaxHellos) {
          ++hellos_;
          (void)link.write(encoder_.encode_hello());
          boot_deadline_ns_ = now_ns + core::ms_to_ns(kHelloPeriodMs);
          note("no frame from the board %lld ms after open: Hello %d/%d",
               static_cast<long long>((now_ns - opened_ns_) / core::kNsPerMs), hellos_, kMaxHellos);
        } else {
          verdict_ = SessionVerdict::kReopen;
          step_ = ArduinoStep::kClosed;
          note("board silent %lld ms after open and %d Hellos: reopening the port",
               static_cast<long long>((now_ns - opened_ns_) / core::kNsPerMs), kMaxHellos);
        }
      }
      break;
    case ArduinoStep::kRunning: {
      const std::int64_t reopen_ms = std::max<std::int64_t>(
          4 * static_cast<std::int64_t>(config_.timeout_ms), kMinReopenSilenceMs);
      if (now_ns - last_frame_ns_ > core::ms_to_ns(reopen_ms)) {
        verdict_ = SessionVerdict::kReopen;
        step_ = ArduinoStep::kClosed;
        note("no frame from the board for %lld ms: reopening the port (resets the board)",
             static_cast<long long>((now_ns - last_frame_ns_) / core::kNsPerMs));
        break;
      }
      if (now_ns >= next_command_ns_) {
        send_command(link, now_ns);
        next_command_ns_ += period_ns_;
        // After a stall, resume the rhythm instead of sending a burst.
        if (next_command_ns_ <= now_ns) next_command_ns_ = now_ns + period_ns_;
      }
      break;
    }
  }
  const SessionVerdict v = verdict_;
  verdict_ = SessionVerdict::kContinue;
  return v;
}

void ArduinoSession::fill_health(msg::DeviceHealth& health, core::TimeNs now_ns) const {
  const CodecStats c = counted();
  health.device = msg::DeviceId::kArduino;
  health.frames_ok = c.frames_ok;
  health.checksum_errors = c.checksum_errors;
  health.framing_errors = c.framing_errors;
  health.dropped_frames = write_failures_;
  health.last_frame_ns = last_frame_ns_;
  health.rate_hz = 0.0;
  const std::size_t n = std::min(tel_count_, kRateRing);
  if (n >= 2) {
    const core::TimeNs newest = tel_stamps_[(tel_count_ - 1) % kRateRing];
    const core::TimeNs oldest = tel_stamps_[(tel_count_ - n) % kRateRing];
    if (newest > oldest && now_ns - newest < core::kNsPerSec) {
      health.rate_hz = static_cast<double>(n - 1) / core::ns_to_sec(newest - oldest);
    }
  }
  health.set_detail(detail());
  switch (step_) {
    case ArduinoStep::kClosed:
      health.state = msg::DeviceState::kOpening;
      return;
    case ArduinoStep::kBooting:
      health.state = msg::DeviceState::kConfiguring;
      return;
    case ArduinoStep::kRunning: {
      const core::TimeNs silence = now_ns - last_frame_ns_;
      if (silence > core::ms_to_ns(config_.timeout_ms)) {
        health.state = msg::DeviceState::kStale;
        char text[64];
        std::snprintf(text, sizeof text, "stale: no frame from the board for %lld ms",
                      static_cast<long long>(silence / core::kNsPerMs));
        health.set_detail(text);
      } else {
        health.state = msg::DeviceState::kRunning;
      }
      return;
    }
  }
}

}  // namespace coxswain::drivers::arduino
