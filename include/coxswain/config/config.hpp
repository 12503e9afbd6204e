// SPDX-License-Identifier: Apache-2.0
#pragma once
// The typed configuration of a run: boat.yaml (the hull and its actuators), devices.yaml (how to
// reach the hardware) and a mission file (what to do), and their loaders. Loaded and validated
// before anything starts; `coxswain config doc` lists every key. The loaders read YAML, but
// nothing here exposes it: this header is safe for any layer above the core.
#include <string>

#include "coxswain/config/boat_config.hpp"
#include "coxswain/config/config_errors.hpp"
#include "coxswain/config/devices_config.hpp"
#include "coxswain/config/mission_config.hpp"
#include "coxswain/guidance/mag_calibration.hpp"
#include "coxswain/perception/vision_params.hpp"

namespace coxswain::config {

/// The camera detectors' colour model and thresholds: the vision file (config/vision.yaml).
struct VisionConfig {
  std::string file;  // where they came from; empty for the built-in defaults
  perception::VisionParams params = perception::VisionParams::defaults();
};

/// Everything a run is configured with.
struct Configuration {
  BoatConfig boat;
  DevicesConfig devices;
  MissionConfig mission;
  VisionConfig vision = {};
};

/// Each reads and validates one file; problems go to `errors` (the returned value then holds
/// defaults where a key was bad and must not be used).
BoatConfig load_boat_config(const std::string& path, ConfigErrors& errors);
DevicesConfig load_devices_config(const std::string& path, ConfigErrors& errors);
MissionConfig load_mission_config(const std::string& path, ConfigErrors& errors);

/// What kind of file a config file is, from its top-level `kind:` key.
enum class ConfigKind : std::uint8_t {
  kBoat,
  kDevices,
  kMission,
  kVision,
  kCourse,
  kSimSensors,
  kUnknown
};
ConfigKind detect_config_kind(const std::string& path, ConfigErrors& errors);

/// The magnetometer calibration the devices file holds, as the mission core takes it.
[[nodiscard]] guidance::MagCalibration magnetometer_of(const ImuDeviceConfig& imu);

/// The effective configuration as YAML (for --print-config and the flight recorder).
std::string to_yaml(const Configuration& config);
/// The mission as a mission file that load_mission_config reads back to the same values (every
/// key written out, doubles to the bit).
std::string mission_to_yaml(const MissionConfig& mission);

}  // namespace coxswain::config
