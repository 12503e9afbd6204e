// SPDX-License-Identifier: Apache-2.0
#pragma once
// What to do (a mission file): the tasks, their waypoints and targets, and every engine's
// parameters. Plain data, no file format: the mission core is built from this and the boat.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "coxswain/control/heading_pid.hpp"
#include "coxswain/control/speed_schedule.hpp"
#include "coxswain/core/geodesy.hpp"
#include "coxswain/guidance/avoidance.hpp"
#include "coxswain/guidance/buoy_circling.hpp"
#include "coxswain/guidance/docking_approach.hpp"
#include "coxswain/guidance/gps_calibration.hpp"
#include "coxswain/guidance/nav_filter_params.hpp"
#include "coxswain/guidance/nav_map.hpp"
#include "coxswain/guidance/waypoint_follower.hpp"
#include "coxswain/msg/camera_detections.hpp"
#include "coxswain/perception/lidar_clusterer.hpp"
#include "coxswain/perception/marker_vote.hpp"

namespace coxswain::config {

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
  double stage_distance_m = 9.0;         // 2026: a slip seen off its axis, or missed, is
                                         // approached again from this far out on its axis
  double turn_radius_m = 1.9;            // 2026: the boat's turning circle (to line up on it)
  double approach_funnel_deg = 30.0;     // 2026: straight in from where the slip is first seen
                                         // only within this of its axis, seen from the mouth
  double entry_tolerance_m = 0.3;        // 2026: at the commit range the boat is this near the
  double entry_tolerance_deg = 15.0;     // slip's axis and its track runs along it within this,
                                         // or it backs off and lines up again
  double back_off_s = 10.0;              // 2026: astern at most this long before lining up again
  double back_off_thrust_frac = 0.5;     // 2026: thrust astern while backing off
  double finger_side_m = 1.2;            // 2026: docked only with a finger this near each side
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
  /// The GNSS + IMU Kalman filter (used when position_gain < 1).
  guidance::NavFilterParams filter;
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
  std::uint32_t camera_stale_ms = 1000;  // detections older than this are not used
  /// Autonomy needs a live Arduino in autonomous mode; false only for bench runs without one.
  bool require_arduino = true;
  std::vector<TaskConfig> tasks;

  // Engine parameters (every one in the mission file; see config/missions/*.yaml).
  NavigationConfig navigation;
  guidance::GpsCalibrationParams gps_calibration;
  guidance::WaypointFollowerParams waypoints;
  control::HeadingPidParams heading_pid;
  control::SpeedScheduleParams speed;
  guidance::AvoidanceParams avoidance;
  perception::LidarClusterParams clustering;
  perception::MarkerVoteParams vision_vote;
  Course1Config course1;
  Course2Config course2;
  DockingConfig docking;
  guidance::PlanningConfig planning;  // map, global planner, lidar-judged gates
};

std::string_view task_type_name(TaskType type);

}  // namespace coxswain::config
