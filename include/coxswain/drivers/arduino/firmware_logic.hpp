// SPDX-License-Identifier: Apache-2.0
#pragma once
// The Arduino firmware's decision core: which pulses reach the servo/ESCs. Shared by the sketch
// (tools/arduino/coxswain_firmware) and the host tests/fuzzer; same portability rules as
// wire.hpp (C++11, no STL, no allocation, no floating point). Behaviour: tools/arduino/PROTOCOL.md
// section "Firmware behaviour".
#include "wire.hpp"

namespace coxswain {  // NOLINT(modernize-concat-nested-namespaces)
namespace drivers {
namespace arduino {

/// Firmware tunables. Times in ms, pulses in us. Defaults suit a Blue Robotics type bidirectional
/// ESC (1100-1900 us, 1500 us stop, must see neutral for ~3 s at power-up).
struct LogicConfig {
  uint16_t neutral_us[kChannels] = {1500, 1500};
  uint16_t min_us[kChannels] = {1100, 1100};
  uint16_t max_us[kChannels] = {1900, 1900};
  uint16_t failsafe_ms = 300;      // host command older than this -> neutral
  uint16_t rc_timeout_ms = 200;    // an RC channel without a valid pulse this long is lost
  uint16_t rc_valid_min_us = 800;  // pulses outside [min, max] are noise, not RC
  uint16_t rc_valid_max_us = 2200;
  uint16_t mode_auto_above_us = 1700;    // mode switch: autonomous at or above
  uint16_t mode_manual_below_us = 1300;  // manual at or below; in between keeps the last state
  uint16_t boot_neutral_ms = 3000;       // ESC arming hold after reset

  /// NULL when consistent, else a static message naming the first problem.
  const char* validate() const {
    for (uint8_t c = 0; c < kChannels; ++c) {
      if (min_us[c] > neutral_us[c] || neutral_us[c] > max_us[c]) {
        return "need min_us <= neutral_us <= max_us on every channel";
      }
      if (min_us[c] < 500 || max_us[c] > 2500) {
        return "pulse limits must lie within 500..2500 us";
      }
    }
    if (failsafe_ms == 0 || rc_timeout_ms == 0) {
      return "failsafe_ms and rc_timeout_ms must be > 0";
    }
    if (rc_valid_min_us >= rc_valid_max_us) {
      return "rc_valid_min_us must be < rc_valid_max_us";
    }
    if (mode_manual_below_us >= mode_auto_above_us) {
      return "mode_manual_below_us must be < mode_auto_above_us";
    }
    return NULL;  // NOLINT(modernize-use-nullptr)
  }
};

/// Digital inputs sampled by the sketch each loop.
struct SwitchInputs {
  bool estop;         // true = stop (the sketch maps its fail-safe wiring to this)
  bool start_switch;  // true = pressed / on
};

/// What the firmware applies this loop.
struct LogicOutputs {
  uint16_t pulse_us[kChannels];
  uint8_t led;
  Mode mode;
  OutputSource source;
  bool failsafe;  // no fresh host command
  bool rc_present;
  bool estop;
  bool start_switch;
  bool armed;  // last fresh host command had kFlagArm
  bool boot_hold;
};

/// Counters kept by the logic (16-bit, wrapping, as sent in Telemetry).
struct LogicCounters {
  uint16_t commands_accepted;
  uint16_t seq_gaps;
  uint16_t seq_duplicates;
  uint16_t failsafe_events;  // fresh -> stale transitions of the host command
  uint16_t rc_invalid_pulses;
  uint16_t rc_loss_events;
};

/// Decision core. Time is a wrapping millisecond counter (Arduino millis()); every age is an
/// unsigned difference, and freshness is latched off as soon as it lapses so a 49-day wrap
/// cannot revive an old command as long as step() runs more often than every 32 s.
/// Priority: boot hold > e-stop > RC lost > RC manual (pass-through) > host failsafe > disarmed >
/// host pulses. All pulses are clamped to [min_us, max_us]. Not thread-safe: call from the
/// sketch's loop() only (the RC interrupt hands pulses over through the sketch).
class FirmwareLogic {
 public:
  explicit FirmwareLogic(const LogicConfig& config) : config_(config) { reset(0); }

  /// Restart as after a reset at `now_ms` (starts the boot hold).
  void reset(uint32_t now_ms) {
    boot_ms_ = now_ms;
    boot_hold_ = config_.boot_neutral_ms > 0;
    cmd_fresh_ = false;
    cmd_ms_ = now_ms;
    have_seq_ = false;
    last_seq_ = 0;
    memset(&cmd_, 0, sizeof(cmd_));
    for (uint8_t c = 0; c < kRcChannels; ++c) {
      rc_fresh_[c] = false;
      rc_ms_[c] = now_ms;
      rc_pulse_us_[c] = 0;
    }
    rc_was_present_ = false;
    mode_auto_ = false;
    memset(&counters_, 0, sizeof(counters_));
  }

  /// Host said Hello: it restarted, so its sequence numbering restarts too.
  void on_hello() { have_seq_ = false; }

  /// A decoded SetOutputs. Returns false (and ignores it) when its sequence repeats the last
  /// accepted one. Serial links do not reorder, so any other sequence is accepted; the jump
  /// size minus one is counted as missed commands (mod 2^16, so 65535 -> 0 is no gap).
  bool on_set_outputs(uint32_t now_ms, uint16_t seq, const SetOutputs& cmd) {
    if (have_seq_) {
      if (seq == last_seq_) {
        ++counters_.seq_duplicates;
        return false;
      }
      const uint16_t missed = static_cast<uint16_t>(static_cast<uint16_t>(seq - last_seq_) - 1U);
      counters_.seq_gaps = static_cast<uint16_t>(counters_.seq_gaps + missed);
    }
    have_seq_ = true;
    last_seq_ = seq;
    cmd_ = cmd;
    cmd_ms_ = now_ms;
    cmd_fresh_ = true;
    ++counters_.commands_accepted;
    return true;
  }

  /// One measured RC pulse (high time) on `channel` (0 steering, 1 throttle, 2 mode switch).
  void on_rc_pulse(uint32_t now_ms, uint8_t channel, uint16_t pulse_us) {
    if (channel >= kRcChannels) {
      return;
    }
    if (pulse_us < config_.rc_valid_min_us || pulse_us > config_.rc_valid_max_us) {
      ++counters_.rc_invalid_pulses;
      return;
    }
    rc_pulse_us_[channel] = pulse_us;
    rc_ms_[channel] = now_ms;
    rc_fresh_[channel] = true;
  }

  /// Decides the outputs at `now_ms` (call every loop, at least every few ms).
  LogicOutputs step(uint32_t now_ms, const SwitchInputs& in) {
    update_freshness(now_ms);
    LogicOutputs out{};
    out.led = cmd_.led;
    out.failsafe = !cmd_fresh_;
    out.armed = cmd_fresh_ && (cmd_.flags & kFlagArm) != 0;
    out.estop = in.estop;
    out.start_switch = in.start_switch;
    out.boot_hold = boot_hold_;
    out.rc_present = rc_present();
    if (out.rc_present) {
      const uint16_t sw = rc_pulse_us_[2];
      if (sw >= config_.mode_auto_above_us) {
        mode_auto_ = true;
      } else if (sw <= config_.mode_manual_below_us) {
        mode_auto_ = false;
      }
    } else {
      mode_auto_ = false;  // after RC returns, autonomy needs the switch seen in auto again
    }
    out.mode = (out.rc_present && mode_auto_ && !in.estop) ? Mode::kAutonomous : Mode::kManual;

    if (boot_hold_) {
      set_neutral(&out, OutputSource::kBootHold);
    } else if (in.estop) {
      set_neutral(&out, OutputSource::kEstop);
    } else if (!out.rc_present) {
      set_neutral(&out, OutputSource::kNoRc);
    } else if (!mode_auto_) {
      for (uint8_t c = 0; c < kChannels; ++c) {
        out.pulse_us[c] = clamp(c, rc_pulse_us_[c]);
      }
      out.source = OutputSource::kRcManual;
    } else if (!cmd_fresh_) {
      set_neutral(&out, OutputSource::kFailsafe);
    } else if (!out.armed) {
      set_neutral(&out, OutputSource::kDisarmed);
    } else {
      for (uint8_t c = 0; c < kChannels; ++c) {
        out.pulse_us[c] = clamp(c, cmd_.pulse_us[c]);
      }
      out.source = OutputSource::kHost;
    }
    return out;
  }

  /// Fills a Telemetry frame body from the last outputs and the link counters.
  void fill_telemetry(uint32_t now_ms, const LogicOutputs& out, const DecoderStats& rx,
                      uint16_t supply_mv, Telemetry* tel) const {
    tel->uptime_ms = static_cast<uint32_t>(now_ms - boot_ms_);
    for (uint8_t c = 0; c < kChannels; ++c) {
      tel->applied_pulse_us[c] = out.pulse_us[c];
    }
    for (uint8_t c = 0; c < kRcChannels; ++c) {
      tel->rc_pulse_us[c] = rc_fresh_[c] ? rc_pulse_us_[c] : 0;
    }
    tel->led = out.led;
    tel->mode = static_cast<uint8_t>(out.mode);
    uint8_t flags = 0;
    flags = static_cast<uint8_t>(flags | (out.estop ? kTelEstop : 0U));
    flags = static_cast<uint8_t>(flags | (out.rc_present ? kTelRcPresent : 0U));
    flags = static_cast<uint8_t>(flags | (out.failsafe ? kTelFailsafe : 0U));
    flags = static_cast<uint8_t>(flags | (out.start_switch ? kTelStartSwitch : 0U));
    flags = static_cast<uint8_t>(flags | (out.armed ? kTelArmed : 0U));
    flags = static_cast<uint8_t>(flags | (out.boot_hold ? kTelBootHold : 0U));
    tel->flags = flags;
    tel->source = static_cast<uint8_t>(out.source);
    tel->supply_mv = supply_mv;
    tel->last_seq = last_seq_;
    tel->rx_frames_ok = static_cast<uint16_t>(rx.frames_ok & 0xFFFFU);
    tel->rx_crc_errors = static_cast<uint16_t>(rx.crc_errors & 0xFFFFU);
    tel->rx_framing_errors = static_cast<uint16_t>(rx.framing_errors & 0xFFFFU);
    tel->rx_bytes_skipped = static_cast<uint16_t>(rx.bytes_skipped & 0xFFFFU);
    tel->seq_gaps = counters_.seq_gaps;
    tel->seq_duplicates = counters_.seq_duplicates;
    tel->failsafe_events = counters_.failsafe_events;
  }

  const LogicConfig& config() const { return config_; }
  const LogicCounters& counters() const { return counters_; }
  uint16_t last_seq() const { return last_seq_; }

 private:
  void update_freshness(uint32_t now_ms) {
    if (boot_hold_ && static_cast<uint32_t>(now_ms - boot_ms_) >= config_.boot_neutral_ms) {
      boot_hold_ = false;
    }
    if (cmd_fresh_ && static_cast<uint32_t>(now_ms - cmd_ms_) >= config_.failsafe_ms) {
      cmd_fresh_ = false;
      ++counters_.failsafe_events;
    }
    for (uint8_t c = 0; c < kRcChannels; ++c) {
      if (rc_fresh_[c] && static_cast<uint32_t>(now_ms - rc_ms_[c]) >= config_.rc_timeout_ms) {
        rc_fresh_[c] = false;
      }
    }
    const bool present = rc_present();
    if (rc_was_present_ && !present) {
      ++counters_.rc_loss_events;
    }
    rc_was_present_ = present;
  }

  bool rc_present() const {
    for (uint8_t c = 0; c < kRcChannels; ++c) {
      if (!rc_fresh_[c]) {
        return false;
      }
    }
    return true;
  }

  uint16_t clamp(uint8_t channel, uint16_t pulse_us) const {
    if (pulse_us < config_.min_us[channel]) {
      return config_.min_us[channel];
    }
    if (pulse_us > config_.max_us[channel]) {
      return config_.max_us[channel];
    }
    return pulse_us;
  }

  void set_neutral(LogicOutputs* out, OutputSource source) const {
    for (uint8_t c = 0; c < kChannels; ++c) {
      out->pulse_us[c] = config_.neutral_us[c];
    }
    out->source = source;
  }

  LogicConfig config_;
  uint32_t boot_ms_ = 0;
  bool boot_hold_ = false;
  bool cmd_fresh_ = false;
  uint32_t cmd_ms_ = 0;
  bool have_seq_ = false;
  uint16_t last_seq_ = 0;
  SetOutputs cmd_{};
  bool rc_fresh_[kRcChannels]{};
  uint32_t rc_ms_[kRcChannels]{};
  uint16_t rc_pulse_us_[kRcChannels]{};
  bool rc_was_present_ = false;
  bool mode_auto_ = false;
  LogicCounters counters_{};
};

}  // namespace arduino
}  // namespace drivers
}  // namespace coxswain
