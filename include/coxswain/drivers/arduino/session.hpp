// SPDX-License-Identifier: Apache-2.0
#pragma once
// The Arduino's device session (drivers/device_session.hpp): sends the tick's ActuatorCommand
// at actuators.command_rate_hz as SetOutputs frames with increasing sequence numbers, decodes
// the board's telemetry into msg::ArduinoStatus, keeps the device health. Protocol:
// tools/arduino/PROTOCOL.md.
//
// Opening the port toggles DTR and resets the board; its bootloader runs ~1-2 s and drops
// whatever arrives meanwhile. So after on_open the session sends nothing and counts nothing as an
// error until the board's first valid frame (Ready after boot, or telemetry from a board that did
// not reset); the bootloader's silence is "configuring", not a fault. If the board stays silent
// for kBootGraceMs it is asked with Hello (a board without auto-reset answers Ready) up to
// kMaxHellos times a second apart, then the port is reopened. Once the board has spoken, a Hello
// restarts its sequence tracking (unless it just sent Ready) and commands flow.
//
// Stale or inactive commands: when the command slot was never written, is older than
// arduino.failsafe_ms, or says active = false, the session keeps sending at the same rate but a
// neutral, DISARMED SetOutputs (neutral pulses, arm flag clear). It does not simply stop sending:
// silence would reach neutral only after the board's own failsafe_ms, whereas a disarmed frame
// makes the board neutral on the next frame, keeps the LED under control, and keeps the link's
// sequence/health meaningful; the telemetry then says "disarmed" (the daemon's tick is the
// problem) rather than "failsafe" (the link or this thread is the problem), which tells the two
// failures apart. The board's 300 ms failsafe stays the backstop when this thread or the cable
// dies.
//
// Health: stale after timeout_ms without a valid frame; kReopen after max(4 x timeout_ms,
// kMinReopenSilenceMs) of silence (a reopen resets the board, whose boot hold keeps the outputs
// neutral). The detail carries a warning when the board's last accepted sequence lags ours by
// more than kSeqLagWarn (commands lost on the way or the board not reading them).
//
// Thread-safety: none; called from the Arduino's device thread only. Reads the command slot
// (lock-free) and is the single writer of the status slot. No allocation.
#include <array>
#include <cstdint>
#include <span>
#include <string_view>

#include "coxswain/config/boat_config.hpp"
#include "coxswain/config/devices_config.hpp"
#include "coxswain/core/latest_store.hpp"
#include "coxswain/drivers/arduino/codec.hpp"
#include "coxswain/drivers/device_session.hpp"

namespace coxswain::drivers::arduino {

enum class ArduinoStep : std::uint8_t { kClosed, kBooting, kRunning };

class ArduinoSession final : public DeviceSession {
 public:
  static constexpr std::int64_t kBootGraceMs = 2500;  // bootloader ~1-2 s, then setup()
  static constexpr std::int64_t kHelloPeriodMs = 1000;
  static constexpr int kMaxHellos = 3;
  static constexpr std::int64_t kMinReopenSilenceMs = 2000;
  static constexpr std::uint16_t kSeqLagWarn = 10;

  ArduinoSession(const config::ArduinoDeviceConfig& config,
                 const config::ActuatorsConfig& actuators,
                 const core::LatestSlot<msg::ActuatorCommand>& command,
                 core::LatestSlot<msg::ArduinoStatus>& status);

  [[nodiscard]] msg::DeviceId device() const override { return msg::DeviceId::kArduino; }
  void on_open(DeviceLink& link, core::TimeNs now_ns) override;
  void on_bytes(std::span<const std::uint8_t> bytes, core::TimeNs arrival_ns,
                DeviceLink& link) override;
  SessionVerdict on_poll(DeviceLink& link, core::TimeNs now_ns) override;
  void on_close(core::TimeNs now_ns) override;
  void fill_health(msg::DeviceHealth& health, core::TimeNs now_ns) const override;

  // Observation (tests, diagnostics).
  [[nodiscard]] ArduinoStep step() const { return step_; }
  [[nodiscard]] std::uint64_t commands_sent() const { return commands_sent_; }
  [[nodiscard]] std::uint64_t neutral_commands_sent() const { return neutral_sent_; }
  /// Sequence number of the last SetOutputs sent (meaningful once commands_sent() > 0).
  [[nodiscard]] std::uint16_t last_sent_seq() const {
    return static_cast<std::uint16_t>(encoder_.next_seq() - 1U);
  }
  [[nodiscard]] std::uint64_t telemetry_received() const { return telemetry_; }
  [[nodiscard]] std::uint32_t board_resets_seen() const { return ready_count_; }
  [[nodiscard]] const Ready& last_ready() const { return ready_; }
  [[nodiscard]] bool sequence_lag_warning() const { return lag_warning_; }
  [[nodiscard]] std::string_view detail() const { return {detail_.data()}; }
  [[nodiscard]] core::TimeNs command_period_ns() const { return period_ns_; }

 private:
  void send_command(DeviceLink& link, core::TimeNs now_ns);
  void on_message(const BoardMessage& m, core::TimeNs arrival_ns, DeviceLink& link);
  void first_contact(bool was_ready, DeviceLink& link);
  [[nodiscard]] CodecStats counted() const;
  void note(const char* fmt, ...) __attribute__((format(printf, 2, 3)));

  config::ArduinoDeviceConfig config_;
  config::ActuatorsConfig actuators_;
  const core::LatestSlot<msg::ActuatorCommand>& command_;
  core::LatestSlot<msg::ArduinoStatus>& status_;
  core::TimeNs period_ns_;
  std::array<std::uint16_t, msg::ActuatorCommand::kChannels> neutral_us_{};

  ArduinoCodec codec_;
  CommandEncoder encoder_;
  ArduinoStep step_ = ArduinoStep::kClosed;
  core::TimeNs opened_ns_ = core::kNeverNs;
  core::TimeNs boot_deadline_ns_ = core::kNeverNs;
  int hellos_ = 0;
  core::TimeNs next_command_ns_ = core::kNeverNs;
  core::TimeNs last_frame_ns_ = core::kNeverNs;
  SessionVerdict verdict_ = SessionVerdict::kContinue;

  // Error counters: bytes before the board's first frame after an open (bootloader noise) are
  // not counted; totals of earlier opens are kept.
  CodecStats baseline_{};
  CodecStats earlier_{};
  bool counting_ = false;

  std::uint64_t commands_sent_ = 0;
  std::uint64_t neutral_sent_ = 0;
  std::uint64_t write_failures_ = 0;
  std::uint64_t telemetry_ = 0;
  std::uint32_t ready_count_ = 0;
  Ready ready_{};
  bool lag_warning_ = false;
  static constexpr std::size_t kRateRing = 16;
  std::array<core::TimeNs, kRateRing> tel_stamps_{};
  std::size_t tel_count_ = 0;
  std::array<char, 192> detail_{};
};

}  // namespace coxswain::drivers::arduino
