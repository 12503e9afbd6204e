// SPDX-License-Identifier: Apache-2.0
#pragma once
// Configuration of every simulated sensor, and its loader from a `sensors:` YAML block (sample
// with every key: config/sim/sensors.yaml). Errors carry file:line:key (config::MapReader).
#include <optional>
#include <string>

#include "coxswain/config/yaml_reader.hpp"
#include "sim/sensors/camera_sim.hpp"
#include "sim/sensors/gnss_sim.hpp"
#include "sim/sensors/imu_sim.hpp"
#include "sim/sensors/lidar_sim.hpp"
#include "sim/world/world.hpp"

namespace coxswain::sim::sensors {

struct SensorConfig {
  std::uint64_t seed = 1;  // master seed; each sensor derives its own stream from it
  LidarSimConfig lidar;
  GnssSimConfig gnss;
  ImuSimConfig imu;
  CameraSimConfig camera;

  /// Empty when valid, else the first problem found.
  [[nodiscard]] std::optional<std::string> validate() const;
};

/// Applies a course's sensor conditions over `config` (each value the course gives wins). A bias
/// mean given without a cap raises the cap to the mean plus twice the wander when it was lower,
/// so a course's bias is never silently clamped by another source's cap.
void apply_conditions(const world::SensorConditions& conditions, SensorConfig& config);

/// Reads the map of a `sensors:` block (its keys: seed, lidar, gnss, imu, camera; every key
/// optional, defaults as in the structs). Problems are added to reader.errors(); unknown keys are
/// reported. Per-sensor seeds are derived from `seed` unless a sensor sets its own.
SensorConfig load_sensor_config(config::MapReader& reader);
/// Same from the node of a `sensors:` block; `file` names it in error messages. Calls finish().
SensorConfig load_sensor_config(const YAML::Node& node, const std::string& file,
                                config::ConfigErrors& errors);
/// Loads `sensors:` from a YAML file (the block at the top level under key `sensors`); nullopt
/// and `errors` filled when anything is wrong.
std::optional<SensorConfig> load_sensor_config_file(const std::string& path,
                                                    config::ConfigErrors& errors);

}  // namespace coxswain::sim::sensors
