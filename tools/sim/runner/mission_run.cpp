// SPDX-License-Identifier: Apache-2.0
#include "sim/runner/mission_run.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "coxswain/core/angles.hpp"
#include "coxswain/core/geodesy.hpp"
#include "sim/runner/realistic_sensors.hpp"
#include "sim/runner/recording.hpp"

namespace coxswain::sim::runner {

config::MissionConfig fit_mission_to_course(const config::MissionConfig& mission,
                                            const world::World& world) {
  config::MissionConfig m = mission;
  const core::LocalFrame frame(world.origin);
  const auto geo = [&frame](core::NavPoint p) { return frame.to_geo(p); };
  m.origin = geo(world.start.position);
  std::size_t course_wp = 0;  // next world waypoint for the 2026 courses
  // The field's corners, as the organisers publish them: the bounding rectangle of the course's
  // regions and the start (with room to turn there), unless the mission file gives its own.
  if (m.planning.boundary.empty() && !world.regions.empty()) {
    constexpr double kStartRoomM = 2.0;
    double n0 = world.start.position.north_m - kStartRoomM;
    double n1 = world.start.position.north_m + kStartRoomM;
    double e0 = world.start.position.east_m - kStartRoomM;
    double e1 = world.start.position.east_m + kStartRoomM;
    for (const auto& r : world.regions) {
      for (const core::NavPoint& p : r.polygon) {
        n0 = std::min(n0, p.north_m);
        n1 = std::max(n1, p.north_m);
        e0 = std::min(e0, p.east_m);
        e1 = std::max(e1, p.east_m);
      }
    }
    if (n1 > n0 && e1 > e0) {
      m.planning.boundary = {geo({n0, e0}), geo({n1, e0}), geo({n1, e1}), geo({n0, e1})};
    }
  }
  for (auto& task : m.tasks) {
    switch (task.type) {
      case config::TaskType::kHopping:
        if (!world.waypoints.empty()) {
          task.waypoints.clear();
          for (const auto& w : world.waypoints) task.waypoints.push_back(geo(w.position));
        }
        break;
      case config::TaskType::kObstacleCourse:
        if (!world.gates.empty()) {
          // Through the centre of every gate in order: the task judges each as a line the
          // track must cross between its ends, so the last crossing ends it.
          task.waypoints.clear();
          for (const auto& g : world.gates) {
            task.waypoints.push_back(geo({(g.left.north_m + g.right.north_m) / 2.0,
                                          (g.left.east_m + g.right.east_m) / 2.0}));
          }
        }
        break;
      case config::TaskType::kDocking:
        if (task.docking_style == config::DockingStyle::kKaboat2022 && !world.docks.empty()) {
          task.slips.clear();
          for (const auto& d : world.docks) task.slips.push_back(geo(d.entrance));
          task.dock_heading_deg = world.docks.front().entry_heading_deg;
          if (world.target_colour != msg::Colour::kUnknown) {
            task.target_colour = world.target_colour;
          }
          if (world.target_shape != msg::Shape::kUnknown) task.target_shape = world.target_shape;
        }
        break;
      case config::TaskType::kCourse1:
      case config::TaskType::kCourse2:
        if (course_wp < world.waypoints.size()) {
          task.waypoints = {geo(world.waypoints[course_wp++].position)};
        }
        break;
    }
  }
  return m;
}

bool mission_passed(const scoring::ScoreResult& score) {
  if (!score.completed || score.timed_out) return false;
  if (score.rules == scoring::Rules::k2026) return score.circled;
  return true;
}

MissionRunResult run_mission(const world::Course& course, const config::Configuration& config,
                             const MissionRunOptions& options) {
  MissionPilot pilot(config);
  RealisticSensorOptions so;
  so.camera = options.camera;
  so.camera_wanted = [&pilot] { return pilot.camera_wanted(); };
  so.target_colour = options.target_colour != msg::Colour::kUnknown ? options.target_colour
                                                                    : course.world.target_colour;
  so.target_shape = options.target_shape != msg::Shape::kUnknown ? options.target_shape
                                                                 : course.world.target_shape;
  // The course's own sensor conditions win over the sensors file and the drawn disturbances.
  sensors::SensorConfig sensor_config =
      fitted_sensor_config(options.sensors, course.world, config, options.seed);
  sensors::apply_conditions(course.world.conditions, sensor_config);
  if (const auto why = sensor_config.validate()) {
    throw std::invalid_argument("sensors: " + *why);
  }
  RealisticSensorSuite suite(course.world, config, sensor_config, so);
  RunnerOptions ro;
  ro.seed = options.seed;
  ro.tick_rate_hz = config.mission.tick_rate_hz;
  ro.max_time_s = options.max_time_s;
  ro.failsafe_ms = static_cast<std::uint16_t>(config.devices.arduino.failsafe_ms);
  ro.collision_response = options.collision_response;
  // The judge scores the target the run was given (--target), not the course file's default.
  world::Course judged = course;
  judged.world.target_colour = so.target_colour;
  judged.world.target_shape = so.target_shape;
  LockstepRunner runner(judged, config.boat, ro, &suite, &pilot);
  std::unique_ptr<RunRecorder> recorder;
  if (!options.recording_file.empty()) {
    recorder = std::make_unique<RunRecorder>(options.recording_file, config, runner.store(),
                                             runner.clock(), course_json(course.world),
                                             "coxswain-sim lockstep");
    if (!recorder->start()) {
      throw std::runtime_error("cannot record to " + options.recording_file + ": " +
                               recorder->error());
    }
    pilot.set_recorder(recorder.get());
    runner.set_step_observer([rec = recorder.get()] { rec->sample(); });
  }

  MissionRunResult r;
  r.hold_delay_s.assign(options.outages.size(), -1.0);
  r.resumed.assign(options.outages.size(), false);
  double finished_at_s = -1.0;
  while (runner.step()) {
    const double t = core::ns_to_sec(runner.now_ns());
    if (options.on_step) options.on_step(t, pilot, runner.truth().pose);
    if (pilot.status().finished) {
      if (finished_at_s < 0.0) finished_at_s = t;
      if (t - finished_at_s >= options.finished_grace_s) {
        runner.stop();
        break;
      }
    }
    bool gnss_off = false;
    bool lidar_off = false;
    for (std::size_t i = 0; i < options.outages.size(); ++i) {
      const SensorOutage& o = options.outages[i];
      const bool in = t >= o.from_s && t < o.to_s;
      gnss_off = gnss_off || (in && o.gnss);
      lidar_off = lidar_off || (in && o.lidar);
      if (in && r.hold_delay_s[i] < 0.0 && pilot.status().holding) {
        r.hold_delay_s[i] = t - o.from_s;
      }
      if (t >= o.to_s && r.hold_delay_s[i] >= 0.0 && !r.resumed[i] && !pilot.status().holding) {
        r.resumed[i] = true;
      }
    }
    suite.set_gnss_publishing(!gnss_off);
    suite.set_lidar_publishing(!lidar_off);
  }
  r.outcome = runner.run();  // already over: collects the outcome
  r.status = pilot.status();
  r.transitions = pilot.transitions();
  if (options.record_path) r.path = runner.path();
  r.camera_frames = suite.frames_processed();
  r.passed = mission_passed(r.outcome.score);
  r.failure = r.passed ? "" : scoring::failure_reason(r.outcome.score, r.status.finished);
  if (recorder) r.recording = recorder->stop(judge_json(r.outcome.score, r.status.finished));
  return r;
}

std::string judge_json(const scoring::ScoreResult& score, bool mission_finished) {
  nlohmann::json judge = scoring::to_json(score);
  const bool passed = mission_passed(score);
  judge["passed"] = passed;
  judge["failure"] = passed ? "" : scoring::failure_reason(score, mission_finished);
  return judge.dump();
}

nlohmann::json result_json(const MissionRunResult& result, std::uint64_t seed) {
  nlohmann::json j = scoring::to_json(result.outcome.score);
  const auto& s = result.status;
  j["passed"] = result.passed;
  j["failure"] = result.failure;
  j["seed"] = seed;
  std::ostringstream hash;
  hash << std::hex << result.outcome.trajectory_hash;
  j["trajectory_hash"] = hash.str();
  j["sim_time_s"] = core::ns_to_sec(result.outcome.end_ns);
  j["camera_frames"] = result.camera_frames;
  j["mission"] = {{"state", std::string(s.state_path.view())},
                  {"started", s.started},
                  {"finished", s.finished},
                  {"holding", s.holding},
                  {"hold_reason", std::string(mission::hold_reason_name(s.hold_reason))},
                  {"task_index", s.task_index},
                  {"task_count", s.task_count},
                  {"mission_elapsed_s", s.mission_elapsed_s},
                  {"waypoints_arrived", s.waypoints_arrived},
                  {"waypoints_missed", s.waypoints_missed},
                  {"tasks_timed_out", s.tasks_timed_out},
                  {"hold_count", s.hold_count},
                  {"gps_offset_m", {s.gps_offset_north_m, s.gps_offset_east_m}},
                  {"identified_colour", static_cast<int>(s.identified_colour)},
                  {"docking_slip", s.docking_slip},
                  {"waiting_for", std::string(s.waiting_for.view())}};
  nlohmann::json tr = nlohmann::json::array();
  for (const auto& t : result.transitions) {
    tr.push_back({{"t_s", t.t_s}, {"from", t.from}, {"to", t.to}, {"reason", t.reason}});
  }
  j["transitions"] = tr;
  if (result.recording) {
    nlohmann::json written = nlohmann::json::object();
    nlohmann::json dropped = nlohmann::json::object();
    for (std::size_t i = 0; i < record::kRecordChannelCount; ++i) {
      const auto c = static_cast<record::RecordChannel>(i);
      const std::string topic(record::channel_topic(c));
      written[topic] = (*result.recording)[c].written;
      dropped[topic] = (*result.recording)[c].dropped;
    }
    j["recording"] = {{"written", written},
                      {"dropped", dropped},
                      {"failed", result.recording->failed},
                      {"error", result.recording->error}};
  }
  return j;
}

}  // namespace coxswain::sim::runner
