// SPDX-License-Identifier: Apache-2.0
#include "coxswain/report/report.hpp"

#include <bit>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "coxswain/core/angles.hpp"
#include "coxswain/host/step_record.hpp"
#include "coxswain/mission/tunable_parameters.hpp"
#include "coxswain/msg/device_health.hpp"
#include "coxswain/replay/info.hpp"
#include "page_text.hpp"

namespace coxswain::report {
namespace {

using nlohmann::json;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Plots keep at most about this many points per series (long runs are decimated evenly).
constexpr std::size_t kMaxPoints = 6000;
// Obstacle segments drawn for runs without a course: at most this many, sampled once a second.
constexpr std::size_t kMaxSegments = 20000;
// The planner's paths kept for the map: a new one at most every half second, at most this many.
constexpr std::size_t kMaxPlans = 2000;
constexpr core::TimeNs kPlanPeriodNs = core::kNsPerSec / 2;

double num(bool valid, double v) { return valid ? v : kNaN; }

// Escapes text for HTML element content.
std::string html_escape(std::string_view s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '<':
        o += "&lt;";
        break;
      case '>':
        o += "&gt;";
        break;
      case '&':
        o += "&amp;";
        break;
      case '"':
        o += "&quot;";
        break;
      default:
        o += c;
    }
  }
  return o;
}

std::string plot(const char* id, const char* title, int width, int height) {
  return std::string("<h2>") + title + "</h2><div class=\"legend\" id=\"" + id +
         "-legend\"></div><svg class=\"plot\" id=\"" + id +
         "\" xmlns=\"http://www.w3.org/2000/svg\" width=\"" + std::to_string(width) +
         "\" height=\"" + std::to_string(height) + "\"></svg>\n";
}

std::string fixed(double v, int digits) {
  char buf[48];
  (void)std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

// The mission's geometry in the navigation frame: marks and closed areas.
json map_json(const record::MapGeometry& geometry) {
  json marks = json::array();
  for (const record::MapMark& m : geometry.marks) {
    marks.push_back({{"label", m.label},
                     {"kind", m.kind == record::MapMark::Kind::kSlip ? "slip" : "waypoint"},
                     {"n", m.at.nav.north_m},
                     {"e", m.at.nav.east_m}});
  }
  json areas = json::array();
  for (const record::MapArea& a : geometry.areas) {
    json points = json::array();
    for (const record::MapVertex& v : a.corners) points.push_back({v.nav.north_m, v.nav.east_m});
    areas.push_back({{"label", a.label},
                     {"kind", a.kind == record::MapArea::Kind::kNoGo ? "no-go" : "boundary"},
                     {"points", std::move(points)}});
  }
  return {{"marks", std::move(marks)}, {"areas", std::move(areas)}};
}

using MetadataMap = std::map<std::string, std::string>;

// What the top of the page says: the date, the result and the score, in words.
struct RunSummary {
  std::string date;
  std::string headline;  // short: the title and the heading
  std::string result;
  std::string score;
  bool good = false;    // finished (and, with a judge, passed)
  bool judged = false;  // the simulator's judge scored the run
};

RunSummary summarise(const MetadataMap& coxswain_metadata,
                     const std::map<std::string, MetadataMap>& metadata,
                     const mission::MissionStatus& status, double finish_t) {
  RunSummary s;
  s.date = "date not recorded";
  if (const auto v = coxswain_metadata.find("utc_ns_at_start"); v != coxswain_metadata.end()) {
    const long long utc_ns = std::strtoll(v->second.c_str(), nullptr, 10);
    if (utc_ns > 0) s.date = replay::format_utc(utc_ns);
  }
  if (status.finished) {
    s.result = "finished in " + fixed(status.mission_elapsed_s, 1) + " s";
    if (!std::isnan(finish_t)) s.result += " (at " + fixed(finish_t, 1) + " s of the recording)";
  } else if (status.started) {
    s.result = "not finished: " + std::string(status.state_path.view()) + " after " +
               fixed(status.mission_elapsed_s, 1) + " s";
    if (status.holding) {
      s.result += ", holding (" + std::string(mission::hold_reason_name(status.hold_reason)) + ")";
    }
  } else {
    s.result = "never started";
    if (!status.waiting_for.view().empty()) {
      s.result += " (waiting for " + std::string(status.waiting_for.view()) + ")";
    }
  }
  s.good = status.finished;
  s.headline = status.finished ? "finished in " + fixed(status.mission_elapsed_s, 1) + " s"
                               : std::string(status.started ? "not finished" : "never started");
  const std::string own_count = std::to_string(status.waypoints_arrived) + " waypoints reached, " +
                                std::to_string(status.waypoints_missed) + " missed, " +
                                std::to_string(status.tasks_timed_out) + " tasks timed out, " +
                                std::to_string(status.hold_count) + " holds";
  json judge;
  if (const auto it = metadata.find("judge"); it != metadata.end()) {
    if (const auto j = it->second.find("json"); j != it->second.end()) {
      judge = json::parse(j->second, nullptr, /*allow_exceptions=*/false);
    }
  }
  if (judge.is_object() && judge.contains("score_s")) {
    const bool passed = judge.value("passed", false);
    const std::string collisions = std::to_string(judge.value("collisions", 0)) + " collisions";
    s.score =
        (passed ? fixed(judge.value("score_s", 0.0), 2) + " s (run " +
                      fixed(judge.value("elapsed_s", 0.0), 2) + " s + penalties " +
                      fixed(judge.value("penalty_s", 0.0), 2) + " s, " + collisions + "), passed"
                : "none, failed: " + judge.value("failure", std::string("not completed")) + " (" +
                      collisions + ")") +
        "; the simulator's judge. The boat's own count: " + own_count;
    // The judge's verdict leads: the simulator ends a run once the judge has seen it complete,
    // which may come before the mission declares itself finished.
    s.good = passed;
    s.judged = true;
    if (passed && !status.finished) {
      s.result += "; the simulator ended the run when its judge saw the course completed";
    }
    s.headline = passed ? "passed, score " + fixed(judge.value("score_s", 0.0), 2) + " s"
                        : "failed: " + judge.value("failure", std::string("not completed"));
  } else {
    s.score =
        "no judge in this recording (the simulator's judge writes one; on the water the referees "
        "score); the boat's own count: " +
        own_count;
  }
  return s;
}

}  // namespace

ReportResult build_report(const replay::Recording& recording, const config::Configuration& config,
                          const std::string& title) {
  ReportResult result;
  const std::size_t n_ticks = recording.ticks.size();
  const std::size_t stride = n_ticks > kMaxPoints ? (n_ticks + kMaxPoints - 1) / kMaxPoints : 1;
  json t = json::array(), north = json::array(), east = json::array(), heading = json::array(),
       desired = json::array(), pulse0 = json::array(), pulse1 = json::array(),
       speed = json::array(), tick_dt = json::array(), h_acc = json::array(), sats = json::array(),
       fix_type = json::array(), transitions = json::array(), paths = json::array(),
       segments = json::array(), goal_n = json::array(), goal_e = json::array(),
       supply_v = json::array(), estop = json::array(), rc_present = json::array(),
       autonomous = json::array(), failsafe = json::array(), plans = json::array();
  // Moments of the run (seconds from the first tick; null when they never came).
  json start_t = nullptr, calibration_t = nullptr, finish_t = nullptr;
  mission::MissionStatus last_status;
  std::uint32_t last_plan_count = 0;
  core::NavPoint last_plan_end;
  core::TimeNs next_plan_ns = core::kNeverNs;
  struct HealthSeries {
    std::vector<std::string> states;
    msg::DeviceHealth last;
    bool seen = false;
  };
  std::array<HealthSeries, msg::kDeviceCount> health;
  // Measured input rates: new samples per second the core saw, over 1 s windows.
  struct RateWindow {
    core::TimeNs start_ns = core::kNeverNs;
    std::uint64_t start_sequence = 0;
    double rate_hz = kNaN;
    json series = json::array();
  };
  constexpr std::size_t kInputs = 5;
  static constexpr const char* kInputNames[kInputs] = {"lidar", "imu", "gnss", "camera", "arduino"};
  std::array<RateWindow, kInputs> rates;
  std::array<std::uint64_t, kInputs> first_sequence{};
  std::array<std::uint64_t, kInputs> last_sequence{};
  std::uint64_t index = 0;
  core::TimeNs t0 = 0;
  core::TimeNs prev_ns = core::kNeverNs;
  double max_dt_ms = 0.0;
  core::TimeNs next_segments_ns = core::kNeverNs;
  std::string last_path;

  auto on_tick = [&](const record::TickRecordData& tick, const mission::CoreOutput& out) {
    if (index == 0) t0 = tick.now_ns;
    const double ts = static_cast<double>(tick.now_ns - t0) / 1e9;
    const double dt_ms =
        prev_ns == core::kNeverNs ? kNaN : static_cast<double>(tick.now_ns - prev_ns) / 1e6;
    if (!std::isnan(dt_ms)) max_dt_ms = std::max(max_dt_ms, dt_ms);  // worst between samples
    prev_ns = tick.now_ns;
    for (std::uint32_t i = 0; i < out.transitions.count && i < mission::TransitionLog::kCapacity;
         ++i) {
      const mission::Transition& tr = out.transitions.entries[i];
      transitions.push_back({{"t", ts},
                             {"from", std::string(tr.from.view())},
                             {"to", std::string(tr.to.view())},
                             {"reason", std::string(tr.reason.view())}});
    }
    const mission::MissionStatus& status = out.status;
    last_status = status;
    if (status.started && start_t.is_null()) start_t = ts;
    if (status.gps_calibrated && calibration_t.is_null()) calibration_t = ts;
    if (status.finished && finish_t.is_null()) finish_t = ts;
    const std::string_view path = out.status.state_path.view();
    if (paths.empty() || path != last_path) {
      last_path = std::string(path);
      paths.push_back({{"t", ts}, {"path", last_path}});
    }
    for (std::size_t d = 0; d < msg::kDeviceCount; ++d) {
      const auto& h = tick.snapshot.health[d];
      if (!h.valid()) continue;
      auto& hs = health[d];
      hs.seen = true;
      hs.last = h.value;
      const std::string st(msg::device_state_name(h.value.state));
      if (hs.states.empty() || hs.states.back() != st) hs.states.push_back(st);
    }
    const std::uint64_t sequences[kInputs] = {
        tick.snapshot.lidar.sequence, tick.snapshot.imu.sequence, tick.snapshot.gnss.sequence,
        tick.snapshot.camera.sequence, tick.snapshot.arduino.sequence};
    for (std::size_t i = 0; i < kInputs; ++i) {
      if (index == 0) first_sequence[i] = sequences[i];
      last_sequence[i] = sequences[i];
      RateWindow& w = rates[i];
      if (w.start_ns == core::kNeverNs) {
        w.start_ns = tick.now_ns;
        w.start_sequence = sequences[i];
      } else if (tick.now_ns - w.start_ns >= core::kNsPerSec) {
        w.rate_hz = static_cast<double>(sequences[i] - w.start_sequence) /
                    (static_cast<double>(tick.now_ns - w.start_ns) / 1e9);
        w.start_ns = tick.now_ns;
        w.start_sequence = sequences[i];
      }
    }
    const mission::VizFrame& v = out.viz;
    if (v.pose_valid && out.viz.segment_count > 0 &&
        (next_segments_ns == core::kNeverNs || tick.now_ns >= next_segments_ns) &&
        segments.size() < kMaxSegments) {
      next_segments_ns = tick.now_ns + core::kNsPerSec;
      const double h = core::deg_to_rad(v.pose.heading_deg);
      const double c = std::cos(h);
      const double s = std::sin(h);
      auto to_nav = [&](const core::BodyPoint& p) {
        return std::pair{v.pose.position.north_m + p.forward_m * c - p.starboard_m * s,
                         v.pose.position.east_m + p.forward_m * s + p.starboard_m * c};
      };
      for (std::uint32_t i = 0; i < v.segment_count && i < mission::VizFrame::kMaxSegments; ++i) {
        const auto a = to_nav(v.segments[i].begin);
        const auto b = to_nav(v.segments[i].end);
        segments.push_back({a.first, a.second, b.first, b.second});
      }
    }
    // The plan as it changes (a new count or a new end), so the map can show the one in force.
    const std::uint32_t plan_count =
        std::min<std::uint32_t>(v.path_count, mission::VizFrame::kMaxPathPoints);
    const core::NavPoint plan_end = plan_count > 0 ? v.path[plan_count - 1] : core::NavPoint{};
    const bool plan_changed = plan_count != last_plan_count ||
                              plan_end.north_m != last_plan_end.north_m ||
                              plan_end.east_m != last_plan_end.east_m;
    if (plan_changed && plans.size() < kMaxPlans &&
        (next_plan_ns == core::kNeverNs || tick.now_ns >= next_plan_ns || plan_count == 0)) {
      next_plan_ns = tick.now_ns + kPlanPeriodNs;
      last_plan_count = plan_count;
      last_plan_end = plan_end;
      json points = json::array();
      for (std::uint32_t i = 0; i < plan_count; ++i) {
        points.push_back({v.path[i].north_m, v.path[i].east_m});
      }
      plans.push_back({{"t", ts}, {"points", std::move(points)}});
    }
    if (index++ % stride != 0) return;
    t.push_back(ts);
    north.push_back(num(v.pose_valid, v.pose.position.north_m));
    east.push_back(num(v.pose_valid, v.pose.position.east_m));
    heading.push_back(num(v.heading_valid, v.pose.heading_deg));
    desired.push_back(num(v.has_desired_heading, v.desired_heading_deg));
    pulse0.push_back(tick.command.pulse_us[0]);
    pulse1.push_back(tick.command.pulse_us[1]);
    const auto& g = tick.snapshot.gnss;
    speed.push_back(num(g.valid() && g.value.velocity_valid, g.value.ground_speed_mps));
    h_acc.push_back(num(g.valid(), g.value.h_acc_m));
    sats.push_back(num(g.valid(), g.value.satellites));
    fix_type.push_back(num(g.valid(), static_cast<double>(g.value.fix_type)));
    goal_n.push_back(num(v.has_goal, v.goal.north_m));
    goal_e.push_back(num(v.has_goal, v.goal.east_m));
    const auto& a = tick.snapshot.arduino;
    const auto flag = [&a](bool on) { return num(a.valid(), on ? 1.0 : 0.0); };
    supply_v.push_back(num(a.valid(), a.value.supply_v));
    estop.push_back(flag(a.value.estop));
    rc_present.push_back(flag(a.value.rc_present));
    autonomous.push_back(flag(a.value.mode == msg::ControlMode::kAutonomous));
    failsafe.push_back(flag(a.value.failsafe));
    tick_dt.push_back(stride == 1 ? dt_ms : max_dt_ms);
    max_dt_ms = 0.0;
    for (RateWindow& w : rates) w.series.push_back(w.rate_hz);
  };
  try {
    result.replay = replay::replay(recording, config, {}, on_tick);
  } catch (const std::invalid_argument& e) {
    result.error = std::string("invalid configuration: ") + e.what();
    return result;
  }
  if (!result.replay.ok) {
    result.error = result.replay.error;
    return result;
  }
  json health_json = json::array();
  for (std::size_t d = 0; d < msg::kDeviceCount; ++d) {
    const HealthSeries& hs = health[d];
    if (!hs.seen) continue;
    health_json.push_back({{"device", std::string(msg::device_name(static_cast<msg::DeviceId>(d)))},
                           {"states", hs.states},
                           {"final_state", std::string(msg::device_state_name(hs.last.state))},
                           {"frames_ok", hs.last.frames_ok},
                           {"checksum_errors", hs.last.checksum_errors},
                           {"framing_errors", hs.last.framing_errors},
                           {"reopen_count", hs.last.reopen_count}});
  }
  const double duration_s = static_cast<double>(prev_ns - t0) / 1e9;
  json rates_json = json::array();
  std::string mean_rates;
  for (std::size_t i = 0; i < kInputs; ++i) {
    rates_json.push_back({{"device", kInputNames[i]}, {"rate_hz", rates[i].series}});
    const double mean_hz =
        duration_s > 0.0 ? static_cast<double>(last_sequence[i] - first_sequence[i]) / duration_s
                         : 0.0;
    mean_rates += std::string(mean_rates.empty() ? "" : ", ") + kInputNames[i] + " " +
                  fixed(mean_hz, 1) + " Hz";
  }
  json data = {
      {"t", t},
      {"track", {{"north", north}, {"east", east}}},
      {"heading", heading},
      {"desired", desired},
      {"pulse0", pulse0},
      {"pulse1", pulse1},
      {"speed", speed},
      {"tick_dt_ms", tick_dt},
      {"h_acc", h_acc},
      {"sats", sats},
      {"fix_type", fix_type},
      {"transitions", transitions},
      {"paths", paths},
      {"segments", segments},
      {"health", health_json},
      {"rates", rates_json},
      {"goal_n", goal_n},
      {"goal_e", goal_e},
      {"power",
       {{"supply_v", supply_v},
        {"estop", estop},
        {"rc_present", rc_present},
        {"autonomous", autonomous},
        {"failsafe", failsafe}}},
      {"plans", plans},
      {"events", {{"start_t", start_t}, {"calibration_t", calibration_t}, {"finish_t", finish_t}}},
      {"map", map_json(host::map_geometry(config.mission))}};
  if (const auto it = recording.file.metadata.find("course"); it != recording.file.metadata.end()) {
    if (const auto j = it->second.find("json"); j != it->second.end()) {
      data["course"] = json::parse(j->second, nullptr, /*allow_exceptions=*/false);
      if (data["course"].is_discarded()) data.erase("course");
    }
  }
  // "</" inside a script element would end it: JSON allows "<\/".
  std::string data_text = data.dump(-1, ' ', false, json::error_handler_t::replace);
  std::string safe;
  safe.reserve(data_text.size());
  for (std::size_t i = 0; i < data_text.size(); ++i) {
    if (data_text[i] == '<' && i + 1 < data_text.size() && data_text[i + 1] == '/') {
      safe += "<\\/";
      ++i;
    } else {
      safe += data_text[i];
    }
  }
  // The operator's live parameter changes: each applied set's values that differ from those in
  // force before it (the first set against the configuration's).
  std::string parameter_rows;
  if (!recording.parameter_sets.empty()) {
    const mission::MissionCore initial(config.boat, config.mission);
    std::map<std::string, double> in_force;
    for (const mission::TunableSpec& spec : mission::tunable_specs()) {
      in_force[spec.name] = spec.get(initial.parameters());
    }
    char cell[64];
    const auto number = [&cell](double v) {
      (void)std::snprintf(cell, sizeof cell, "%.10g", v);
      return std::string(cell);
    };
    for (const record::ParameterSetRecord& set : recording.parameter_sets) {
      for (const auto& [name, value] : set.values) {
        const auto it = in_force.find(name);
        // Bit for bit: a value set again unchanged is no change, whatever its sign or NaN-ness.
        if (it != in_force.end() &&
            std::bit_cast<std::uint64_t>(it->second) == std::bit_cast<std::uint64_t>(value)) {
          continue;
        }
        parameter_rows += "<tr><td>" + number(static_cast<double>(set.stamp_ns - t0) / 1e9) +
                          "</td><td>" + std::to_string(set.tick_index) + "</td><td>" +
                          html_escape(name) + "</td><td>" +
                          (it == in_force.end() ? std::string("?") : number(it->second)) +
                          "</td><td>" + number(value) + "</td></tr>";
        in_force[name] = value;
      }
    }
  }
  const replay::ReplayReport& r = result.replay;
  const auto coxswain_metadata = recording.file.metadata.find("coxswain");
  const RunSummary summary = summarise(
      coxswain_metadata != recording.file.metadata.end() ? coxswain_metadata->second
                                                         : MetadataMap{},
      recording.file.metadata, last_status, finish_t.is_null() ? kNaN : finish_t.get<double>());
  std::string html = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>" +
                     html_escape("coxswain: " + config.mission.name + ", " + summary.date + ", " +
                                 summary.headline) +
                     "</title>\n<style>" + kPageStyle + "</style></head><body>\n";
  html += "<h1>" + html_escape(config.mission.name) + ": " + html_escape(summary.headline) +
          "</h1>\n<table id=\"summary\">";
  const auto row = [&html](const char* name, const std::string& value, const char* cls = "") {
    html += std::string("<tr><th>") + name + "</th><td" +
            (*cls != '\0' ? std::string(" class=\"") + cls + "\"" : std::string()) + ">" +
            html_escape(value) + "</td></tr>";
  };
  row("mission", config.mission.name + " (boat " + config.boat.name + ")");
  row("date", summary.date);
  row("result", summary.result, last_status.finished ? "passed" : (summary.judged ? "" : "failed"));
  row("score", summary.score, !summary.judged ? "" : (summary.good ? "passed" : "failed"));
  row("run",
      title + ": " + fixed(duration_s, 1) + " s, " + std::to_string(r.ticks) + " ticks; replay " +
          (r.identical() ? std::string("identical to the recording")
                         : std::to_string(r.ticks_different) +
                               " ticks differ from the recording (the plots show the replay)") +
          (recording.file.truncated ? "; the recording is truncated" : ""));
  html += "</table>\n<p id=\"error\" style=\"color:#c00\"></p>\n";
  html +=
      "<div id=\"toolbar\"><button id=\"reset-zoom\">Reset zoom</button><span id=\"view-range\">"
      "</span><br><span id=\"cursor-readout\"></span></div>\n<p class=\"note\">Drag across a time "
      "plot "
      "to zoom every plot to that span; the wheel zooms around the pointer; a double click shows "
      "the "
      "whole run. The pointer's time is the cursor on every plot and the boat on the map. Grey "
      "background: before the start; dashed line: the start calibration.</p>\n";
  html += plot("track", "Track on the course", 700, 560);
  html +=
      "<p class=\"note\">Red: the track (dark and thick: the time span in view). Grey dashed: the "
      "estimate before the start calibration (uncorrected GPS). Blue dashed: the planner's path at "
      "the cursor. Drag to pan, the wheel zooms, a double click fits.</p>\n";
  html += plot("heading", "Heading vs desired heading", 900, 220);
  html += plot("pulses", "Servo and thrust pulses", 900, 220);
  html += plot("speed", "Speed over ground", 900, 180);
  html += plot("states", "State machine timeline", 900, 200);
  html +=
      "<table id=\"transitions\"><tr><th>t (s)</th><th>from</th><th>to</th><th>reason</th>"
      "</tr></table>\n";
  html +=
      "<h2>Live parameter changes</h2>\n<table id=\"parameters\"><tr><th>t (s)</th><th>tick</th>"
      "<th>parameter</th><th>from</th><th>to</th></tr>" +
      (parameter_rows.empty() ? std::string("<tr><td colspan=\"5\">none</td></tr>")
                              : parameter_rows) +
      "</table>\n";
  html += plot("health", "Device rates (each on its own scale)", 900, 260);
  html += "<p class=\"note\" id=\"mean-rates\">mean rates over the run: " + mean_rates + "</p>\n";
  html +=
      "<table id=\"health-table\"><tr><th>device</th><th>states seen</th><th>final</th>"
      "<th>frames ok</th><th>checksum errors</th><th>framing errors</th><th>reopens</th>"
      "</tr></table>\n";
  html += plot("power", "Battery, e-stop, RC and mode (Arduino)", 900, 240);
  html += plot("timing", "Tick timing (interval between ticks)", 900, 180);
  html += plot("gnss", "GNSS quality", 900, 200);
  html += "<script type=\"application/json\" id=\"report-data\">" + safe + "</script>\n<script>" +
          kPageScript + "</script>\n</body></html>\n";
  result.html = std::move(html);
  result.ok = true;
  return result;
}

int run_report_command(const std::filesystem::path& recording_path, std::filesystem::path output,
                       const config::Configuration* config_override, std::ostream& out,
                       std::ostream& err) {
  const replay::Recording recording = replay::load_recording(recording_path);
  if (!recording.ok) {
    err << "report: " << recording.error << "\n";
    return 2;
  }
  std::optional<config::Configuration> recorded;
  if (config_override == nullptr) {
    config::ConfigErrors errors;
    recorded = replay::configuration_from_yaml(recording.config_yaml, errors);
    if (!recorded) {
      err << "report: the recorded configuration does not load:\n" << errors.format();
      return 2;
    }
  }
  const ReportResult r =
      build_report(recording, config_override != nullptr ? *config_override : *recorded,
                   recording_path.filename().string());
  if (!r.ok) {
    err << "report: " << r.error << "\n";
    return 2;
  }
  if (output.empty()) output = std::filesystem::path(recording_path).replace_extension(".html");
  std::ofstream f(output, std::ios::binary);
  f << r.html;
  f.close();
  if (!f) {
    err << "report: cannot write " << output.string() << "\n";
    return 1;
  }
  out << "wrote " << output.string() << " (" << r.replay.ticks << " ticks)\n";
  return 0;
}

}  // namespace coxswain::report
