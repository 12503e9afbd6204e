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
#include "coxswain/control/heading_pid.hpp"
#include "coxswain/control/speed_schedule.hpp"
#include "coxswain/core/frames.hpp"
#include "coxswain/core/geodesy.hpp"
#include "coxswain/guidance/avoidance.hpp"
#include "coxswain/guidance/buoy_circling.hpp"
#include "coxswain/guidance/docking_approach.hpp"
#include "coxswain/guidance/gps_calibration.hpp"
#include "coxswain/guidance/waypoint_follower.hpp"
#include "coxswain/msg/actuator_command.hpp"
#include "coxswain/msg/camera_detections.hpp"
#include "coxswain/perception/lidar_clusterer.hpp"
#include "coxswain/perception/marker_vote.hpp"

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
  // ---- BEGIN magnetometer calibration (`coxswain calibrate mag`; port to the config tables) ----
  // Hard iron (board x forward, y starboard, microtesla) and the soft-iron map (row-major 2x2)
  // fitted from a slow turn in place; identity/zero = uncalibrated.
  double mag_hard_iron_x_ut = 0.0;
  double mag_hard_iron_y_ut = 0.0;
  double mag_soft_iron_xx = 1.0;
  double mag_soft_iron_xy = 0.0;
  double mag_soft_iron_yx = 0.0;
  double mag_soft_iron_yy = 1.0;
  // ---- END magnetometer calibration ----
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

/// The local control interface and live view (src/live): control socket, status page and the
/// Foxglove WebSocket server.
struct LiveConfig {
  std::string control_socket;  // "" = <run directory>/control.sock
  bool http_enabled = true;    // status page + Foxglove WebSocket
  std::string http_address = "127.0.0.1";
  std::uint16_t http_port = 8765;  // 0 = any free port (written to <run directory>/live.port)
  double viz_rate_hz = 10.0;       // Foxglove messageData per channel at most this often
  std::string token;               // status page buttons; "" = buttons refused
};

struct DevicesConfig {
  std::string file;
  LidarDeviceConfig lidar;
  ImuDeviceConfig imu;
  GnssDeviceConfig gnss;
  ArduinoDeviceConfig arduino;
  CameraDeviceConfig camera;
  LiveConfig live;
};

enum class StartMode : std::uint8_t { kImmediate = 0, kArduinoSwitch, kControl };
enum class TaskType : std::uint8_t { kHopping = 0, kObstacleCourse, kCourse1, kCourse2, kDocking };

/// What happens when a task's time limit runs out: the 2026 contest moves on to the next course.
enum class TimeoutOutcome : std::uint8_t { kNextTask = 0, kFinish };
/// Docking: KABOAT 2022 (visit the slips, vote on their markers, enter the target by ray
/// pursuit) or 2026 course 3 (most open direction in the course's forward half-plane).
enum class DockingStyle : std::uint8_t { kKaboat2022 = 0, kCourse3 };

struct TaskConfig {
  TaskType type = TaskType::kHopping;
  std::string name;
  double time_limit_s = 300.0;
  TimeoutOutcome on_timeout = TimeoutOutcome::kNextTask;
  std::vector<core::GeoPoint> waypoints;
  msg::Colour target_colour = msg::Colour::kUnknown;
  msg::Shape target_shape = msg::Shape::kUnknown;
  DockingStyle docking_style = DockingStyle::kKaboat2022;
  std::vector<core::GeoPoint> slips;  // 2022 docking: slip entrances, in visiting order
  double dock_heading_deg = 0.0;      // 2022 docking: true heading pointing into the slips
};

/// Course 1 (2026): after the first waypoint, turn to starboard until the camera sees the buoy.
struct Course1Config {
  double turn_deg = 45.0;           // relative to the heading at the waypoint, + starboard
  double search_timeout_s = 3.0;    // then move on to course 2 anyway
  double search_thrust_frac = 0.4;  // thrust while turning
  msg::Colour buoy_colour = msg::Colour::kPurple;
};

/// Course 2 (2026): circle the buoy once on the camera side, find the target colour, go on.
struct Course2Config {
  guidance::BuoyCirclingParams circling;
  double circling_thrust_frac = 0.4;
  double exit_course_deg = -90.0;  // course-frame heading held while looking for the colour
  double exit_align_deg = 180.0;   // after the full turn, circle on until the heading is this
                                   // near it (leave on the circle's tangent, not across it)
  double colour_timeout_s = 30.0;  // no colour by then: go to the waypoint with the LED off
  double seek_thrust_frac = 0.4;
  double buoy_range_window_deg = 3.0;  // lidar bins either side of the camera bearing
  double buoy_memory_s = 0.25;         // a camera bearing older than this is not steered on
  // Once the camera has found the buoy, the lidar tracks it all the way round (a camera looking
  // ahead, or a side camera in a tight turn, loses it for most of the circle).
  bool lidar_tracking = true;
  double buoy_radius_m = 0.3;    // the buoy's radius: the lidar sees its near side
  double track_gate_m = 1.0;     // a lidar obstacle this near the predicted buoy is the buoy
  double track_timeout_s = 2.0;  // unseen by the lidar this long: lost, search with the camera
  std::vector<msg::Colour> colours{msg::Colour::kRed, msg::Colour::kGreen, msg::Colour::kBlue};
  msg::Colour buoy_colour = msg::Colour::kPurple;
};

/// Docking, both styles.
struct DockingConfig {
  guidance::DockingApproachParams approach;
  double decision_distance_m = 6.0;   // 2022: where the boat stops to look, before each slip
  double face_time_s = 8.0;           // 2022: longest look at one slip before moving on
  double face_tolerance_deg = 15.0;   // 2022: votes count only when facing within this
  double marker_window_deg = 15.0;    // 2022: only markers this near the bow are the slip's
  double approach_thrust_frac = 0.5;  // both: thrust while entering (slower crabs in a current)
  double open_window_deg = 10.0;      // 2026: a direction's range is the minimum over +- this
  double open_max_range_m = 15.0;     // 2026: ranges are capped here (no return = this far)
  double survey_distance_m = 10.0;    // 2022: look at every marker from this far before the slips
  double slip_depth_m = 2.0;          // 2022: markers hang on the back wall this far inside
  double turn_thrust_frac = 0.3;      // 2022: thrust while turning to face a slip (the rudder
                                      // acts on the thruster's stream: no thrust, no turn)
  double line_up_distance_m = 2.0;    // 2022: approach a decision point from this far behind it
                                      // on the slip's axis, so the boat arrives facing the slip
  double axis_lookahead_m = 6.0;      // 2022: line of sight along a slip's axis toward its
                                      // decision point (shorter joins the axis steeper and
                                      // overshoots it toward the pool wall)
  double marker_fix_gain = 0.3;       // 2022: weight of each frame's camera fix of the axis
  double marker_fix_max_range_m = 15.0;  // 2022: markers farther ahead do not fix the axis
  double max_marker_fix_m = 1.5;         // 2022: largest sideways correction of the slip's axis
  double slip_match_m = 1.2;             // 2022: a lidar mouth this near where the map puts the
                                         // chosen slip is that slip (neighbours are farther)
  double commit_range_m = 1.5;           // 2026: mouth nearer than this: hold the slip's axis
  double sweep_wall_range_m = 5.0;       // 2026: far wall this near and no slip: sweep along it
  double sweep_standoff_m = 4.5;         // 2026: distance kept from the far wall while sweeping
  double sweep_turn_back_m = 3.0;        // 2026: a side wall this near turns the sweep back
  guidance::SlipFinderParams slip;       // 2026: the slip mouth in the lidar profile
};

/// Navigation estimate (inside the core).
struct NavigationConfig {
  double heading_filter_tau_s = 0.1;  // wrap-safe low-pass of the IMU heading
  /// Weight of each GNSS fix against the estimate dead-reckoned with the receiver's velocity
  /// (guidance::PositionFilter); 1 = the raw fixes, held between fixes.
  double position_gain = 0.3;
  /// The start point marks the body origin (the bow reference), not the antenna: remove the
  /// antenna's mount offset before the GPS offset is taken. false = the 2022 code (off by it).
  bool start_lever_arm = true;
  /// The boat drifts off the start point while it waits: take each calibration fix back by the
  /// distance the receiver's velocity says the boat moved since the first fix.
  bool start_drift = true;
  /// True heading of the course frame's 0 deg; empty = the heading when the mission starts.
  std::optional<double> course_zero_deg;
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
  std::uint32_t gnss_stale_ms = 450;  // 5 Hz fixes: one may be lost; hold within 0.5 s
  std::uint32_t arduino_stale_ms = 500;
  /// Autonomy needs a live Arduino in autonomous mode; false only for bench runs without one.
  bool require_arduino = true;
  std::vector<TaskConfig> tasks;

  // Engine parameters (every one in the mission file; see config/missions/*.yaml).
  NavigationConfig navigation;
  guidance::GpsCalibrationParams gps_calibration;
  guidance::WaypointFollowerParams waypoints;
  control::HeadingPidParams heading_pid;
  control::SpeedScheduleParams speed;
  double cruise_thrust_frac = 0.7;  // avoidance tasks, before the avoidance speed factor
  guidance::AvoidanceParams avoidance;
  perception::LidarClusterParams clustering;
  perception::MarkerVoteParams vision_vote;
  Course1Config course1;
  Course2Config course2;
  DockingConfig docking;
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
enum class ConfigKind : std::uint8_t { kBoat, kDevices, kMission, kCourse, kSimSensors, kUnknown };
ConfigKind detect_config_kind(const std::string& path, ConfigErrors& errors);

/// The effective configuration as YAML (for --print-config and the flight recorder).
std::string to_yaml(const Configuration& config);

std::string_view task_type_name(TaskType type);

}  // namespace coxswain::config
