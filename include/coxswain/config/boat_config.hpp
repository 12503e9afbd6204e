// SPDX-License-Identifier: Apache-2.0
#pragma once
// The boat: its hull, where its sensors are mounted and how its actuators are driven
// (boat.yaml). Plain data, no file format: the core, the drivers and the simulator all read it.
#include <cstdint>
#include <string>

#include "coxswain/core/frames.hpp"
#include "coxswain/msg/actuator_command.hpp"

namespace coxswain::config {

struct HullConfig {
  double length_m = 1.2;
  double beam_m = 0.8;
  /// Body origin (the sensor reference at the bow) to the tip of the bow; the hull extends from
  /// +bow_overhang_m to -(length_m - bow_overhang_m) along the body x axis.
  double bow_overhang_m = 0.1;
};

struct MountsConfig {
  core::MountTransform lidar;
  core::MountTransform imu;
  core::MountTransform gnss;
  core::MountTransform camera;
};

struct ServoConfig {
  std::uint16_t center_us = 1500;
  std::uint16_t min_us = 1100;
  std::uint16_t max_us = 1900;
  double max_deflection_deg = 25.0;  // deflection at min_us/max_us
  double rate_deg_per_s = 180.0;     // slew rate of the real servo
  std::uint16_t deadband_us = 4;
  bool reversed = false;  // true: a larger pulse turns the bow to port
};

struct ThrusterConfig {
  std::uint16_t neutral_us = 1500;
  std::uint16_t min_us = 1100;            // full reverse
  std::uint16_t max_us = 1900;            // full forward
  std::uint16_t forward_start_us = 1550;  // thrust starts above this (ESC deadband)
  std::uint16_t reverse_start_us = 1450;
  bool reverse_allowed = true;
};

struct ActuatorsConfig {
  msg::ActuatorLayout layout = msg::ActuatorLayout::kServoThruster;
  double command_rate_hz = 20.0;
  ServoConfig servo;
  ThrusterConfig thruster;          // the single thruster, or each of the twin thrusters
  double twin_track_width_m = 0.6;  // distance between the twin thrusters
};

struct BoatConfig {
  std::string file;
  std::string name = "boat";
  HullConfig hull;
  MountsConfig mounts;
  ActuatorsConfig actuators;
};

}  // namespace coxswain::config
