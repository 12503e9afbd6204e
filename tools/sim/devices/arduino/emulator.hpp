// SPDX-License-Identifier: Apache-2.0
#pragma once
// Byte-level Arduino (coxswain firmware) emulator core for the simulator (docs/architecture.md).
// Protocol: tools/arduino/PROTOCOL.md. It runs the firmware's own decision core
// (drivers::arduino::FirmwareLogic, the very header the sketch compiles) and the sketch's frame
// handling, so the 300 ms failsafe, the RC-absent rule, the boot hold and the sequence counting
// behave exactly as on the board. Pure: no I/O, no clock (time is passed in), no allocation after
// construction, deterministic for a seed.
//
// Behaviour emulated:
// - reset (power-on, or DTR toggled by opening the port: reset()): the bootloader runs for
//   bootloader_ms, during which the board sends nothing and host bytes are lost; then setup()
//   sends Ready and starts the boot hold. The board powers on at the first receive()/poll().
// - loop(): one FirmwareLogic::step per emulated millisecond; RC frames every 20 ms while RC is
//   present (steering, throttle, mode switch at 1900 us for auto, 1100 us for manual);
//   telemetry every telemetry_period_ms (50 ms = 20 Hz, as the sketch).
// - host frames: SetOutputs, Ping (-> Pong), Hello (-> Ready, sequence tracking restarts).
// - inputs settable at any time: RC present, mode switch, e-stop, start switch, supply voltage,
//   RC stick pulses; outputs (the applied pulses the simulator's boat sees): outputs().
// - faults: garbage bytes before telemetry frames, corrupted telemetry frames (a bit flipped
//   after the CRC was computed), total silence.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "coxswain/core/time.hpp"
#include "coxswain/drivers/arduino/firmware_logic.hpp"
#include "sim/devices/device_emulator.hpp"

namespace coxswain::sim::devices::arduino {

namespace fw = drivers::arduino;

/// The board's physical inputs.
struct BoardInputs {
  bool rc_present = true;  // receiver bound and sending pulses
  bool mode_auto = true;   // RC mode switch in the autonomous position
  bool estop = false;
  bool start_switch = false;
  std::uint16_t supply_mv = 12000;
  std::uint16_t rc_steering_us = 1500;
  std::uint16_t rc_throttle_us = 1500;
};

struct EmulatorFaults {
  double garbage_probability = 0.0;  // per telemetry frame: 1..16 random bytes before it
  double corrupt_probability = 0.0;  // per telemetry frame: one bit flipped after the CRC
  bool silent = false;               // sends nothing (dead board, cut cable)
  std::uint64_t seed = 1;

  [[nodiscard]] std::optional<std::string> validate() const;
};

struct EmulatorConfig {
  fw::LogicConfig logic{};
  std::int64_t bootloader_ms = 1500;
  std::uint16_t telemetry_period_ms = 50;  // the sketch's kTelemetryPeriodMs
  std::uint8_t reset_cause = 0x02;         // MCUSR EXTRF: reset by DTR
  BoardInputs inputs{};
  EmulatorFaults faults{};

  [[nodiscard]] std::optional<std::string> validate() const;
};

struct EmulatorStats {
  std::uint64_t resets = 0;
  std::uint64_t bytes_lost_in_bootloader = 0;
  std::uint64_t host_frames = 0;
  std::uint64_t set_outputs = 0;
  std::uint64_t hellos = 0;
  std::uint64_t pings = 0;
  std::uint64_t ready_sent = 0;
  std::uint64_t telemetry_sent = 0;
  std::uint64_t garbage_bursts = 0;
  std::uint64_t corrupted_frames = 0;
  std::uint64_t dropped_bytes = 0;
  std::uint64_t skipped_ms = 0;  // loop milliseconds not emulated after a large time jump
};

class Emulator final : public DeviceEmulator {
 public:
  static constexpr std::size_t kOutputCapacity = 16384;
  static constexpr std::uint32_t kRcFramePeriodMs = 20;
  static constexpr std::uint32_t kMaxCatchUpMs = 10000;
  static constexpr std::uint8_t kFwMajor = 1;
  static constexpr std::uint8_t kFwMinor = 0;
  static constexpr std::uint8_t kFwPatch = 0;

  explicit Emulator(const EmulatorConfig& config = {});

  void receive(std::span<const std::uint8_t> host_bytes, core::TimeNs now_ns) override;
  [[nodiscard]] std::span<const std::uint8_t> poll(core::TimeNs now_ns) override;

  /// Resets the board at `now_ns` (DTR toggled by a port open, or power cycle).
  void reset(core::TimeNs now_ns);
  void set_inputs(const BoardInputs& inputs) { inputs_ = inputs; }
  [[nodiscard]] const BoardInputs& inputs() const { return inputs_; }
  void set_faults(const EmulatorFaults& faults) { config_.faults = faults; }

  /// What the PWM outputs carry now; pulse_us 0 = no signal (bootloader).
  [[nodiscard]] const fw::LogicOutputs& outputs() const { return outputs_; }
  [[nodiscard]] bool in_bootloader(core::TimeNs now_ns) const;
  [[nodiscard]] const fw::FirmwareLogic& logic() const { return logic_; }
  [[nodiscard]] const EmulatorStats& stats() const { return stats_; }

 private:
  void power_on_if_needed(core::TimeNs now_ns);
  void advance(core::TimeNs now_ns);
  void setup(std::uint32_t now_ms);
  void loop_once(std::uint32_t now_ms);
  void handle_frame(const fw::Frame& f, std::uint32_t now_ms);
  void send_frame(std::size_t n, bool telemetry);
  void put(std::span<const std::uint8_t> bytes);
  [[nodiscard]] std::uint32_t millis(core::TimeNs now_ns) const;
  [[nodiscard]] std::uint64_t next_random();
  [[nodiscard]] double uniform();

  EmulatorConfig config_;
  BoardInputs inputs_;
  fw::FirmwareLogic logic_;
  fw::FrameDecoder rx_;
  fw::LogicOutputs outputs_{};
  EmulatorStats stats_;
  std::uint64_t rng_state_;

  bool powered_ = false;
  bool booted_ = false;  // setup() ran
  core::TimeNs reset_ns_ = 0;
  std::uint32_t last_loop_ms_ = 0;
  std::uint32_t last_telemetry_ms_ = 0;
  std::uint16_t tx_seq_ = 0;
  std::array<std::uint8_t, fw::kMaxFrame> tx_{};

  std::array<std::uint8_t, kOutputCapacity> out_{};
  std::size_t out_len_ = 0;
  std::size_t returned_ = 0;
};

}  // namespace coxswain::sim::devices::arduino
