// SPDX-License-Identifier: Apache-2.0
#pragma once
// One mission sailed in lockstep: course + configuration (boat, devices, mission) + sensor
// config + seed -> score, mission status, transitions, path. The glue `coxswain-sim run`,
// `coxswain-sim batch`, the scenario tests and the benchmark share. Pure apart from allocation:
// no I/O, no clock; one call per thread (the Course may be shared read-only between threads).
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "coxswain/config/config.hpp"
#include "coxswain/record/recorder.hpp"
#include "sim/runner/lockstep_runner.hpp"
#include "sim/runner/mission_pilot.hpp"
#include "sim/sensors/sensor_config.hpp"
#include "sim/world/course.hpp"

namespace coxswain::sim::runner {

/// The mission's geometry taken from the course, its engine parameters, task types, order and
/// time limits kept: the origin (and known start point for the GPS calibration) becomes the
/// course's start; hopping tasks get the course's waypoints; obstacle-course tasks a goal 5 m
/// past the last gate; 2022 docking the slips' entrances and entry heading; 2026 course 1 the
/// first waypoint, course 2 the second. Tasks whose geometry the course lacks keep theirs.
[[nodiscard]] config::MissionConfig fit_mission_to_course(const config::MissionConfig& mission,
                                                          const world::World& world);

/// A sensor going silent for a while (sim time, seconds).
struct SensorOutage {
  bool gnss = false;
  bool lidar = false;
  double from_s = 0.0;
  double to_s = 0.0;
};

struct MissionRunOptions {
  std::uint64_t seed = 1;  // disturbances and sensor noise
  sensors::SensorConfig sensors;
  bool camera = true;
  double max_time_s = 900.0;
  msg::Colour target_colour = msg::Colour::kUnknown;  // overrides the course's target
  msg::Shape target_shape = msg::Shape::kUnknown;
  std::vector<SensorOutage> outages;
  bool record_path = true;
  /// Not empty: write the flight recording the daemon writes (RunRecorder) to this file.
  std::string recording_file;
  /// The hull stops at what it touches (RunnerOptions::collision_response).
  bool collision_response = true;
  /// Once the mission declares itself finished the boat has stopped sailing: the run ends this
  /// long after (what it coasts counts), and the judge settles the score there.
  double finished_grace_s = 5.0;
  /// Called after every tick with the simulated time, the pilot (its core's map and planner)
  /// and the hull's true pose: for tools that draw what the boat believed against the truth.
  std::function<void(double t_s, const MissionPilot& pilot, const core::NavPose& truth)> on_step;
};

struct MissionRunResult {
  RunOutcome outcome;
  mission::MissionStatus status;
  std::vector<TransitionRecord> transitions;
  std::vector<core::NavPose> path;
  std::uint64_t camera_frames = 0;
  bool passed = false;
  /// Why it failed ("" when passed): scoring::failure_reason.
  std::string failure;
  /// With a recording: the recorder's own counters at the end (per channel written/dropped).
  std::optional<record::RecorderStats> recording;
  /// Per outage: seconds from its start to the mission holding (-1 never), and whether the
  /// mission left hold after the sensors came back.
  std::vector<double> hold_delay_s;
  std::vector<bool> resumed;
};

/// The pass condition of each rule book: the scorer's completion (hopping: every waypoint in
/// order; obstacle: the last gate; docking and 2026: in the dock) inside the time limits, and
/// for 2026 also the purple buoy circled.
[[nodiscard]] bool mission_passed(const scoring::ScoreResult& score);

/// Sails `course` with `config` (its mission fitted to the course by the caller or not).
[[nodiscard]] MissionRunResult run_mission(const world::Course& course,
                                           const config::Configuration& config,
                                           const MissionRunOptions& options);

/// result.json: the scoring JSON plus "mission" (status), "transitions", "passed", "failure",
/// "seed", "trajectory_hash", and with a recording "recording": {"written": {topic: n}, "dropped":
/// {topic: n}, "failed", "error"} (the recorder's counters, which the file must match).
/// The judge's verdict as recorded at the end of a run (Metadata "judge", read by
/// `coxswain report`): the score, whether the run passed and, when not, why.
[[nodiscard]] std::string judge_json(const scoring::ScoreResult& score, bool mission_finished);
[[nodiscard]] nlohmann::json result_json(const MissionRunResult& result, std::uint64_t seed);

}  // namespace coxswain::sim::runner
