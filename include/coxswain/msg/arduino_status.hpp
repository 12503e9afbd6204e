// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>

#include "coxswain/core/time.hpp"
#include "coxswain/msg/actuator_command.hpp"

namespace coxswain::msg {

enum class ControlMode : std::uint8_t { kManual = 0, kAutonomous = 1 };

/// Telemetry from the Arduino: what it is really driving and whether autonomy is allowed.
struct ArduinoStatus {
  core::TimeNs stamp_ns = core::kNeverNs;
  std::array<std::uint16_t, ActuatorCommand::kChannels> applied_pulse_us{1500, 1500};
  LedColour led = LedColour::kOff;
  ControlMode mode = ControlMode::kManual;
  bool estop = false;
  bool rc_present = false;
  bool failsafe = false;  // no valid command within the failsafe timeout: outputs neutral
  bool start_switch = false;
  double supply_v = 0.0;
  std::uint16_t last_sequence_seen = 0;
};

}  // namespace coxswain::msg
