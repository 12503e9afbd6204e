// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstdint>

#include "coxswain/core/time.hpp"

namespace coxswain::msg {

enum class LedColour : std::uint8_t { kOff = 0, kRed, kGreen, kBlue, kYellow, kPurple, kWhite };

/// Actuator layouts (boat.yaml `actuators.layout`). Channel meaning per layout:
/// - kServoThruster: channel 0 = servo turning the stern thruster, channel 1 = thruster ESC;
/// - kTwinThrusters: channel 0 = port ESC, channel 1 = starboard ESC.
enum class ActuatorLayout : std::uint8_t { kServoThruster = 0, kTwinThrusters = 1 };

/// What the core asks of the Arduino each tick, in pulse widths (microseconds).
struct ActuatorCommand {
  static constexpr std::size_t kChannels = 2;
  core::TimeNs stamp_ns = core::kNeverNs;
  std::array<std::uint16_t, kChannels> pulse_us{1500, 1500};
  LedColour led = LedColour::kOff;
  /// False = the core wants neutral outputs (hold, finished, shutdown).
  bool active = false;
};

}  // namespace coxswain::msg
