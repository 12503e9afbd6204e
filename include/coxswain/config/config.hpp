// SPDX-License-Identifier: Apache-2.0
#pragma once
// The typed configuration of a run: boat.yaml (the hull and its actuators), devices.yaml (how to
// reach the hardware) and a mission file (what to do). Loaded and validated before anything
// starts; see config/*.yaml for every key with its meaning.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "coxswain/config/yaml_reader.hpp"
#include "coxswain/core/frames.hpp"
#include "coxswain/core/geodesy.hpp"
#include "coxswain/msg/actuator_command.hpp"
#include "coxswain/msg/camera_detections.hpp"

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

enum class LidarScanMode : std::uint8_t { kAuto = 0, kStandard, kExpress };
enum class GnssReceiver : std::uint8_t { kF9 = 0, kM8 };
enum class GnssPort : std::uint8_t { kUsb = 0, kUart1 };
enum class ImuOutput : std::uint8_t { kAscii = 0, kBinary };

struct SerialDeviceConfig {
  bool enabled = true;
  std::string path;
  std::uint32_t baud = 115200;
  std::uint32_t timeout_ms = 500;  // silence longer than this = stale
};

struct LidarDeviceConfig : SerialDeviceConfig {
  LidarScanMode scan_mode = LidarScanMode::kAuto;
  std::uint16_t motor_pwm = 660;  // A2/A3 accessory board PWM
  std::uint16_t motor_rpm = 600;  // S-series
};

struct ImuDeviceConfig : SerialDeviceConfig {
  ImuOutput output = ImuOutput::kAscii;
  double rate_hz = 100.0;
  double declination_deg = 0.0;  // magnetic declination at the site, east positive
};

struct GnssDeviceConfig : SerialDeviceConfig {
  GnssReceiver receiver = GnssReceiver::kF9;
  GnssPort port = GnssPort::kUsb;
  double rate_hz = 5.0;
  bool nmea_output = false;
  std::string rtcm_input;  // "", a file or pipe path, or tcp://host:port
};

struct ArduinoDeviceConfig : SerialDeviceConfig {
  std::uint32_t failsafe_ms = 300;
};

struct CameraDeviceConfig {
  bool enabled = true;
  std::string source = "/dev/videoCAM";  // a V4L2 device, a video file or an image directory
  bool loop = true;  // video file / image directory: start again at the end (desk work)
  std::uint32_t width_px = 640;
  std::uint32_t height_px = 480;
  double fps = 30.0;
  double hfov_deg = 80.0;
  bool auto_exposure = false;
  double exposure = 100.0;
  double saturation = 128.0;
  double contrast = 128.0;
  double brightness = 128.0;
  std::uint32_t timeout_ms = 1000;
};

struct DevicesConfig {
  std::string file;
  LidarDeviceConfig lidar;
  ImuDeviceConfig imu;
  GnssDeviceConfig gnss;
  ArduinoDeviceConfig arduino;
  CameraDeviceConfig camera;
};

enum class StartMode : std::uint8_t { kImmediate = 0, kArduinoSwitch, kControl };
enum class TaskType : std::uint8_t { kHopping = 0, kObstacleCourse, kCourse1, kCourse2, kDocking };

struct TaskConfig {
  TaskType type = TaskType::kHopping;
  std::string name;
  double time_limit_s = 300.0;
  std::vector<core::GeoPoint> waypoints;
  msg::Colour target_colour = msg::Colour::kUnknown;
  msg::Shape target_shape = msg::Shape::kUnknown;
};

struct MissionConfig {
  std::string file;
  std::string name = "mission";
  double tick_rate_hz = 50.0;
  core::GeoPoint origin;
  StartMode start_mode = StartMode::kImmediate;
  bool calibrate_gps_at_start = true;
  std::uint32_t lidar_stale_ms = 300;
  std::uint32_t imu_stale_ms = 200;
  std::uint32_t gnss_stale_ms = 1500;
  std::uint32_t arduino_stale_ms = 500;
  std::vector<TaskConfig> tasks;
};

/// Everything a run is configured with.
struct Configuration {
  BoatConfig boat;
  DevicesConfig devices;
  MissionConfig mission;
};

/// Each reads and validates one file; problems go to `errors` (the returned value then holds
/// defaults where a key was bad and must not be used).
BoatConfig load_boat_config(const std::string& path, ConfigErrors& errors);
DevicesConfig load_devices_config(const std::string& path, ConfigErrors& errors);
MissionConfig load_mission_config(const std::string& path, ConfigErrors& errors);

/// What kind of file a config file is, from its top-level `kind:` key.
enum class ConfigKind : std::uint8_t { kBoat, kDevices, kMission, kCourse, kUnknown };
ConfigKind detect_config_kind(const std::string& path, ConfigErrors& errors);

/// The effective configuration as YAML (for --print-config and the flight recorder).
std::string to_yaml(const Configuration& config);

std::string_view task_type_name(TaskType type);

}  // namespace coxswain::config
