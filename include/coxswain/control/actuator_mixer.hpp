// SPDX-License-Identifier: Apache-2.0
#pragma once
// Turn and thrust demands -> msg::ActuatorCommand pulse widths, for the two layouts of
// msg::ActuatorLayout (boat.yaml `actuators`). Defaults follow docs/simulator.md: ESC 1100-1900
// us, 1500 neutral, the team drove 1550-1880 us forward; servo about +-25 deg around centre.
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "coxswain/core/time.hpp"
#include "coxswain/msg/actuator_command.hpp"

namespace coxswain::control {

/// One ESC. A forward fraction f in (0, 1] maps to forward_start_us + f (forward_max_us -
/// forward_start_us): the span below forward_start_us is the ESC's deadband, skipped.
struct ThrusterConfig {
  std::uint16_t neutral_us = 1500;
  std::uint16_t min_us = 1100;  // absolute limits of the ESC
  std::uint16_t max_us = 1900;
  std::uint16_t forward_start_us = 1550;  // first pulse that really pushes forward
  std::uint16_t forward_max_us = 1880;    // pulse at full forward demand (<= max_us)
  std::uint16_t reverse_start_us = 1450;  // first pulse that really pushes astern
  std::uint16_t reverse_max_us = 1120;    // pulse at full reverse demand (>= min_us)
  bool reverse_allowed = false;           // false: negative demand gives neutral
  double deadband_frac = 0.01;            // |demand| below this is neutral (no creeping)

  [[nodiscard]] std::optional<std::string> validate() const;
};

/// The servo that turns the stern thruster. deflection_deg > 0 = the bow turns to starboard;
/// `sign` maps that onto the servo's direction.
struct ServoConfig {
  std::uint16_t center_us = 1500;
  std::uint16_t min_us = 1250;  // pulse at full negative servo travel
  std::uint16_t max_us = 1750;  // pulse at full positive servo travel
  double max_deflection_deg = 25.0;
  int sign = 1;  // +1 or -1

  [[nodiscard]] std::optional<std::string> validate() const;
};

/// Twin fixed thrusters, differential (the capstone report): v_port = v + r L_w / 2,
/// v_stbd = v - r L_w / 2 with r the yaw rate, + = clockwise (to starboard). The capstone report
/// writes v_left = v - omega L_w / 2 with omega counter-clockwise; the two are the same formula.
struct TwinConfig {
  double track_width_m = 0.6;      // L_w, between the thruster axes
  double max_speed_mps = 1.5;      // surge speed at full forward on both sides
  double max_yaw_rate_dps = 60.0;  // yaw rate asked for by a turn demand of 1
  ThrusterConfig port;
  ThrusterConfig starboard;
};

struct MixerConfig {
  msg::ActuatorLayout layout = msg::ActuatorLayout::kServoThruster;
  ServoConfig servo;        // kServoThruster, channel 0
  ThrusterConfig thruster;  // kServoThruster, channel 1
  TwinConfig twin;          // kTwinThrusters, channels 0 (port) and 1 (starboard)

  [[nodiscard]] std::optional<std::string> validate() const;
};

/// What the controller asks for. turn: [-1, 1], + = to starboard; for the servo layout a fraction
/// of max_deflection_deg, for twin thrusters a fraction of max_yaw_rate_dps. thrust: [-1, 1],
/// fraction of the forward (or reverse) range.
struct MixDemand {
  double turn = 0.0;
  double thrust = 0.0;
};

/// The per-side demands after mixing (twin: fractions after desaturation), for the live view.
struct MixDetail {
  std::array<double, msg::ActuatorCommand::kChannels> channel_frac{};
  bool saturated = false;
};

/// Stateless mixer. Inputs are clamped; pulses are symmetric about the centre/neutral for equal
/// and opposite demands when the limits are (no rounding bias to one side). Thread-safe (const).
class ActuatorMixer {
 public:
  explicit ActuatorMixer(MixerConfig c = {}) : c_(c) {}
  [[nodiscard]] msg::ActuatorCommand mix(MixDemand d, core::TimeNs stamp_ns,
                                         MixDetail* detail = nullptr) const;
  /// All channels at neutral (servo centred, ESCs neutral), active = false.
  [[nodiscard]] msg::ActuatorCommand neutral(core::TimeNs stamp_ns) const;
  /// Servo pulse for a bow-turn deflection in degrees (clamped to +-max_deflection_deg).
  [[nodiscard]] std::uint16_t servo_pulse_us(double deflection_deg) const;
  /// ESC pulse for a thrust fraction in [-1, 1].
  [[nodiscard]] static std::uint16_t thruster_pulse_us(const ThrusterConfig& t, double frac);
  [[nodiscard]] const MixerConfig& config() const { return c_; }

 private:
  MixerConfig c_;
};

}  // namespace coxswain::control
