// SPDX-License-Identifier: Apache-2.0
#pragma once
// The heart of the daemon: a hierarchical state machine run at the fixed tick.
// Levels: safety (wait_for_start, hold, finished) above the mission, the mission a sequence of
// tasks from the mission file (hopping, obstacle_course, course1, course2, docking), each task a
// sequence of phases. Pure: a Snapshot and the tick time in; the actuator command (pulse widths
// through control::ActuatorMixer, LED), the status, this tick's transitions and the
// visualization frame out. No I/O, no clock reads, no allocation in step() once constructed;
// the same inputs give bit-identical outputs.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "coxswain/config/boat_config.hpp"
#include "coxswain/config/mission_config.hpp"
#include "coxswain/control/heading_pid.hpp"
#include "coxswain/control/speed_schedule.hpp"
#include "coxswain/core/frames.hpp"
#include "coxswain/core/latest_store.hpp"
#include "coxswain/core/time.hpp"
#include "coxswain/guidance/avoidance.hpp"
#include "coxswain/guidance/mag_calibration.hpp"
#include "coxswain/msg/actuator_command.hpp"
#include "coxswain/msg/camera_detections.hpp"
#include "coxswain/perception/lidar_clusterer.hpp"
#include "coxswain/perception/vision_params.hpp"

namespace coxswain::mission {

/// NUL-terminated fixed text (state paths, reasons) so every output stays trivially copyable.
template <std::size_t N>
struct FixedText {
  std::array<char, N> chars{};

  void assign(std::string_view text) {
    const std::size_t n = text.size() < N - 1 ? text.size() : N - 1;
    for (std::size_t i = 0; i < n; ++i) chars[i] = text[i];
    chars[n] = '\0';
  }
  [[nodiscard]] std::string_view view() const { return std::string_view(chars.data()); }
  [[nodiscard]] bool empty() const { return chars[0] == '\0'; }
};

inline constexpr std::size_t kPathChars = 48;     // "hold/course2/seek_colour" fits easily
inline constexpr std::size_t kReasonChars = 112;  // one short sentence
using StatePath = FixedText<kPathChars>;
using ReasonText = FixedText<kReasonChars>;

/// Why the core holds (neutral outputs) above whatever task was running.
enum class HoldReason : std::uint8_t {
  kNone = 0,
  kLidarStale,
  kImuStale,
  kGnssStale,  // no fresh fix, or the receiver reports no usable fix
  kArduinoStale,
  kManualMode,  // the Arduino's RC switch is on manual
  kEstop,
  kOperator,  // hold requested through the control interface
};
[[nodiscard]] std::string_view hold_reason_name(HoldReason r);

/// What the host shows and records about the state machine.
struct MissionStatus {
  StatePath state_path;          // e.g. "wait_for_start", "course2/circling", "hold/course1/avoid"
  std::uint32_t task_index = 0;  // index into MissionConfig::tasks (== task_count when finished)
  std::uint32_t task_count = 0;
  bool started = false;
  bool finished = false;
  bool holding = false;
  HoldReason hold_reason = HoldReason::kNone;
  ReasonText waiting_for;  // wait_for_start / refused entry: what is missing
  ReasonText last_transition_reason;
  double mission_elapsed_s = 0.0;  // since the start (0 before)
  double task_elapsed_s = 0.0;     // since the current task was entered
  bool position_valid = false;
  bool heading_valid = false;
  bool gps_calibrated = false;
  double gps_offset_north_m = 0.0;  // subtracted from every fix (measured - true)
  double gps_offset_east_m = 0.0;
  /// The estimator's uncertainty (guidance::NavFilter): the antenna position's covariance
  /// (north/east, m^2) and the heading's standard deviation. Invalid with the raw fixes.
  bool position_cov_valid = false;
  double position_cov_nn_m2 = 0.0;
  double position_cov_ne_m2 = 0.0;
  double position_cov_ee_m2 = 0.0;
  double heading_sigma_deg = 0.0;
  /// The magnetometer's heading disagrees with course over ground on straight runs (the mean
  /// difference, deg, COG - magnetometer): calibrate it (`coxswain calibrate mag`).
  bool mag_disagrees = false;
  double mag_cog_mean_deg = 0.0;
  std::uint32_t gnss_fixes_rejected = 0;  // refused by the filter's chi-square gate
  double course_zero_deg = 0.0;           // true heading of the course frame's 0 deg
  msg::Colour identified_colour = msg::Colour::kUnknown;  // course 2
  std::int32_t docking_slip = -1;                         // chosen slip (2022 docking), -1 none
  std::uint64_t tick_count = 0;
  std::uint64_t transition_count = 0;
  std::uint64_t hold_count = 0;     // times hold was entered
  std::uint64_t refusal_count = 0;  // times a state refused entry
  std::uint32_t waypoints_arrived = 0;
  std::uint32_t waypoints_missed = 0;
  std::uint32_t tasks_timed_out = 0;
};

struct Transition {
  core::TimeNs stamp_ns = core::kNeverNs;
  StatePath from;
  StatePath to;
  ReasonText reason;
};

/// The transitions of one tick, for the host to log (the core does no I/O).
struct TransitionLog {
  static constexpr std::size_t kCapacity = 16;
  std::uint32_t count = 0;
  std::uint32_t dropped = 0;  // more than kCapacity in one tick (should not happen)
  std::array<Transition, kCapacity> entries{};
};

/// An obstacle segment, body frame at the scan's time (x forward, y starboard, metres).
struct VizSegment {
  core::BodyPoint begin;
  core::BodyPoint end;
  bool wall = false;
};

/// What the recorder and the live view draw. Navigation frame unless named otherwise.
struct VizFrame {
  static constexpr std::size_t kMaxSegments = 256;
  static constexpr std::size_t kMaxDangerBins = 720;
  static constexpr std::size_t kMaxPathPoints = 64;
  core::TimeNs stamp_ns = core::kNeverNs;
  bool pose_valid = false;
  core::NavPose pose;  // body origin (bow sensor reference), GPS-offset corrected
  /// Covariance of the position (north/east, m^2): the confidence ellipse around the pose.
  bool position_cov_valid = false;
  double position_cov_nn_m2 = 0.0;
  double position_cov_ne_m2 = 0.0;
  double position_cov_ee_m2 = 0.0;
  bool heading_valid = false;
  bool has_desired_heading = false;
  double desired_heading_deg = 0.0;
  bool has_goal = false;
  core::NavPoint goal;
  double arrival_radius_m = 0.0;
  std::int32_t active_waypoint = -1;  // index in the current task's route, -1 none
  bool has_leg = false;
  core::NavPoint leg_start;
  /// The gate being judged: its buoys as the lidar places them (by_lidar) or the nominal gate.
  bool has_gate = false;
  bool gate_by_lidar = false;
  core::NavPoint gate_port;
  core::NavPoint gate_starboard;
  /// The global planner's path to the goal, thinned to at most kMaxPathPoints (0 = none).
  std::uint32_t path_count = 0;
  std::array<core::NavPoint, kMaxPathPoints> path{};
  double cross_track_m = 0.0;
  double distance_to_go_m = 0.0;
  double turn_command = 0.0;    // [-1, 1], + starboard
  double thrust_command = 0.0;  // [-1, 1]
  std::uint32_t segment_count = 0;
  std::array<VizSegment, kMaxSegments> segments{};
  bool has_avoidance = false;
  double avoidance_bearing_body_deg = 0.0;  // chosen direction relative to the bow
  std::uint8_t avoidance_status = 0;        // guidance::AvoidanceStatus
  std::uint32_t danger_count = 0;           // bins over [danger_min_deg, + count * width)
  double danger_min_deg = 0.0;
  double danger_bin_width_deg = 1.0;
  std::array<float, kMaxDangerBins> danger{};  // 0 free .. 1 blocked
};

/// Everything one step produces. Trivially copyable; reuse one instance across ticks.
struct CoreOutput {
  msg::ActuatorCommand command;
  MissionStatus status;
  TransitionLog transitions;
  VizFrame viz;
};

/// The parameters an operator may retune while the boat sails (live view parameter interface;
/// the named ones are in mission/tunable_parameters.hpp). Trivially copyable so it can cross
/// threads through a core::LatestSlot.
struct TunableParameters {
  control::HeadingPidParams heading_pid;
  perception::LidarClusterParams clustering;
  guidance::AvoidanceParams avoidance;  // the avoidance tasks' engine
  control::SpeedScheduleParams speed;   // thrust by distance to go, and its rise/fall limit
  /// The camera detectors' tunables (the HSV box of each colour is tunable). The camera thread
  /// runs the detectors, not the core: the core only keeps them so the set in force is whole, and
  /// the daemon hands them to the camera driver.
  perception::VisionParams vision = perception::VisionParams::defaults();
};

/// The mission state machine. Construct once from a validated Configuration (throws
/// std::invalid_argument when an engine parameter is invalid); then call step() once per tick
/// with a monotonic `now_ns`. Not thread-safe: one owner, the tick thread.
class MissionCore {
 public:
  /// `magnetometer`: the hard- and soft-iron terms of the IMU's magnetometer (devices file,
  /// `coxswain calibrate mag`); the default is uncalibrated.
  MissionCore(const config::BoatConfig& boat, const config::MissionConfig& mission,
              const guidance::MagCalibration& magnetometer = {});
  ~MissionCore();
  MissionCore(const MissionCore&) = delete;
  MissionCore& operator=(const MissionCore&) = delete;
  MissionCore(MissionCore&&) noexcept;
  MissionCore& operator=(MissionCore&&) noexcept;

  /// One tick. Overwrites `out`: every field, and each array of out.viz up to its count (entries
  /// past a count are left as they were; nothing reads them).
  void step(const core::Snapshot& snapshot, core::TimeNs now_ns, CoreOutput& out);

  /// The work a step leaves for after its commands are out: its scan into the lidar map and the
  /// plan a task asked for (a few hundred microseconds, where the step itself is tens). Call it
  /// after using `out`, before the next step; a caller that does not gets it done as the next
  /// step() or apply_parameters() begins, so the results are the same either way.
  void finish_tick();

  /// Replaces the tunable parameters between two steps (never during one). Only the named
  /// parameters (tunable_specs()) are taken from `params`; the other fields of its structs keep
  /// the values in force. Returns an empty string when applied, else why the set was rejected
  /// (nothing changes then). The heading PID always restarts without integral or rate history;
  /// the clusterer, the avoidance engine of every avoidance task (which forgets its chosen side)
  /// and the speed schedule are rebuilt only when one of their parameters changed (the thrust
  /// ramp keeps its value). Allocates (the clusterer's buffers): an operator action, never a tick.
  [[nodiscard]] std::string apply_parameters(const TunableParameters& params);
  /// The parameters in force.
  [[nodiscard]] TunableParameters parameters() const;
  /// Replaces the camera detectors' parameters kept with the others (the vision file, at start):
  /// live sets then change its named values and keep the rest. Empty when taken, else why not
  /// (VisionParams::validate(); nothing changes then).
  [[nodiscard]] std::string set_vision(const perception::VisionParams& vision);

  /// The mission's lidar map and global planner as the last finish_tick() left them (null when
  /// the mission plans without a map), for viewers and tools that draw what the boat believed.
  [[nodiscard]] const guidance::NavMap* nav_map() const;
  [[nodiscard]] const guidance::MapPlanner* map_planner() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace coxswain::mission
