// SPDX-License-Identifier: Apache-2.0
#include "coxswain/report/report.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "coxswain/core/angles.hpp"
#include "coxswain/mission/tunable_parameters.hpp"
#include "coxswain/msg/device_health.hpp"

namespace coxswain::report {
namespace {

using nlohmann::json;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Plots keep at most about this many points per series (long runs are decimated evenly).
constexpr std::size_t kMaxPoints = 6000;
// Obstacle segments drawn for runs without a course: at most this many, sampled once a second.
constexpr std::size_t kMaxSegments = 20000;

double num(bool valid, double v) { return valid ? v : kNaN; }

// The page: static text with the data spliced in. The script draws every plot into its SVG and
// marks it rendered with its point count (the headless-browser test checks those marks).
constexpr const char* kHead = R"HTML(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>coxswain report</title>
<style>
body{font-family:sans-serif;margin:16px;color:#222;background:#fff}
h1{font-size:20px}h2{font-size:16px;margin:18px 0 4px}
svg.plot{border:1px solid #ccc;background:#fcfcfc;display:block}
table{border-collapse:collapse;font-size:12px}td,th{border:1px solid #ddd;padding:2px 6px;text-align:left}
.legend span{margin-right:12px;font-size:12px}.note{font-size:12px;color:#555}
</style></head><body>
)HTML";

constexpr const char* kScript = R"JS(
const D = JSON.parse(document.getElementById('report-data').textContent);
const NS = 'http://www.w3.org/2000/svg';
function el(parent, name, attrs, text) {
  const e = document.createElementNS(NS, name);
  for (const k in attrs) e.setAttribute(k, attrs[k]);
  if (text !== undefined) e.textContent = text;
  parent.appendChild(e);
  return e;
}
function fin(v) { return v !== null && v !== undefined && isFinite(v); }
function extent(arrays) {
  let lo = Infinity, hi = -Infinity;
  for (const a of arrays) for (const v of a) if (fin(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
  if (!isFinite(lo)) { lo = 0; hi = 1; }
  if (hi - lo < 1e-9) { lo -= 0.5; hi += 0.5; }
  return [lo, hi];
}
function mark(svg, points) {
  svg.setAttribute('data-rendered', 'true');
  svg.setAttribute('data-points', String(points));
}
function legend(id, series) {
  const div = document.getElementById(id + '-legend');
  if (!div) return;
  for (const s of series) {
    const sp = document.createElement('span');
    sp.style.color = s.color; sp.textContent = '\u25A0 ' + s.name; div.appendChild(sp);
  }
}
// A time plot: series [{name, ys, color, step}] over the shared xs.
function linePlot(id, xs, series, ylabel, yrange) {
  const svg = document.getElementById(id);
  const W = +svg.getAttribute('width'), H = +svg.getAttribute('height');
  const L = 60, R = 10, T = 20, B = 30;
  const [x0, x1] = extent([xs]);
  const [y0, y1] = yrange || extent(series.map(s => s.ys));
  const X = x => L + (x - x0) / (x1 - x0) * (W - L - R);
  const Y = y => H - B - (y - y0) / (y1 - y0) * (H - T - B);
  for (let i = 0; i <= 5; i++) {
    const xv = x0 + (x1 - x0) * i / 5, yv = y0 + (y1 - y0) * i / 5;
    el(svg, 'line', {x1: X(xv), x2: X(xv), y1: T, y2: H - B, stroke: '#eee'});
    el(svg, 'line', {x1: L, x2: W - R, y1: Y(yv), y2: Y(yv), stroke: '#eee'});
    el(svg, 'text', {x: X(xv), y: H - 12, 'font-size': 10, 'text-anchor': 'middle'}, xv.toFixed(1));
    el(svg, 'text', {x: L - 4, y: Y(yv) + 3, 'font-size': 10, 'text-anchor': 'end'},
       Math.abs(y1 - y0) < 10 ? yv.toFixed(2) : yv.toFixed(0));
  }
  el(svg, 'text', {x: 4, y: 12, 'font-size': 10}, ylabel);
  el(svg, 'text', {x: W - R, y: H - 2, 'font-size': 10, 'text-anchor': 'end'}, 'time (s)');
  let points = 0;
  for (const s of series) {
    let d = '', pen = false, prev = null;
    for (let i = 0; i < xs.length; i++) {
      const y = s.ys[i];
      if (!fin(y)) { pen = false; continue; }
      if (s.wrap && pen && Math.abs(y - prev) > 180) pen = false;  // heading crossing +-180
      if (s.step && pen && prev !== null) d += 'L' + X(xs[i]).toFixed(1) + ' ' + Y(prev).toFixed(1);
      d += (pen ? 'L' : 'M') + X(xs[i]).toFixed(1) + ' ' + Y(y).toFixed(1);
      pen = true; prev = y; points++;
    }
    el(svg, 'path', {d: d, fill: 'none', stroke: s.color, 'stroke-width': 1.2});
  }
  legend(id, series);
  mark(svg, points);
}
function drawTrack() {
  const svg = document.getElementById('track');
  const W = +svg.getAttribute('width'), H = +svg.getAttribute('height');
  const C = D.course || {};
  const es = [], ns = [];
  const add = (n, e) => { if (fin(n) && fin(e)) { ns.push(n); es.push(e); } };
  D.track.north.forEach((n, i) => add(n, D.track.east[i]));
  for (const w of (C.walls || [])) for (const p of w) add(p[0], p[1]);
  for (const b of (C.buoys || [])) add(b.n, b.e);
  for (const w of (C.waypoints || [])) add(w.n, w.e);
  for (const s of D.segments) { add(s[0], s[1]); add(s[2], s[3]); }
  const [e0, e1] = extent([es]), [n0, n1] = extent([ns]);
  const pad = 2, span = Math.max(e1 - e0, n1 - n0) + 2 * pad;
  const k = Math.min(W, H) / span;
  const cx = (e0 + e1) / 2, cy = (n0 + n1) / 2;
  const X = e => W / 2 + (e - cx) * k, Y = n => H / 2 - (n - cy) * k;
  let points = 0;
  for (const s of D.segments) {
    el(svg, 'line', {x1: X(s[1]), y1: Y(s[0]), x2: X(s[3]), y2: Y(s[2]), stroke: '#bbb', 'stroke-width': 1});
    points++;
  }
  for (const w of (C.walls || [])) {
    el(svg, 'polyline', {points: w.map(p => X(p[1]) + ',' + Y(p[0])).join(' '), fill: 'none', stroke: '#444', 'stroke-width': 2});
    points += w.length;
  }
  for (const b of (C.buoys || [])) {
    el(svg, 'circle', {cx: X(b.e), cy: Y(b.n), r: Math.max(2, b.r * k), fill: b.colour || 'orange', stroke: '#333'});
    points++;
  }
  (C.waypoints || []).forEach((w, i) => {
    el(svg, 'circle', {cx: X(w.e), cy: Y(w.n), r: Math.max(2, w.r * k), fill: 'none', stroke: '#07c', 'stroke-dasharray': '4 3'});
    el(svg, 'text', {x: X(w.e) + 4, y: Y(w.n) - 4, 'font-size': 10, fill: '#07c'}, w.name || ('wp' + i));
    points++;
  });
  let d = '', pen = false;
  for (let i = 0; i < D.track.north.length; i++) {
    const n = D.track.north[i], e = D.track.east[i];
    if (!fin(n) || !fin(e)) { pen = false; continue; }
    d += (pen ? 'L' : 'M') + X(e).toFixed(1) + ' ' + Y(n).toFixed(1); pen = true; points++;
  }
  el(svg, 'path', {d: d, fill: 'none', stroke: '#d22', 'stroke-width': 1.5});
  if (C.start) el(svg, 'circle', {cx: X(C.start[1]), cy: Y(C.start[0]), r: 4, fill: '#2a2'});
  el(svg, 'text', {x: 6, y: 14, 'font-size': 11}, 'north up, ' + (span / W * 100).toFixed(1) + ' m per 100 px');
  mark(svg, points);
}
function drawStates() {
  const svg = document.getElementById('states');
  const W = +svg.getAttribute('width'), H = +svg.getAttribute('height');
  const xs = D.t, t0 = xs.length ? xs[0] : 0, t1 = xs.length ? xs[xs.length - 1] : 1;
  const X = t => 10 + (t - t0) / Math.max(1e-9, t1 - t0) * (W - 20);
  const names = [...new Set(D.paths.map(p => p.path))];
  const rowH = Math.max(10, (H - 30) / Math.max(1, names.length));
  const hue = i => 'hsl(' + (i * 67 % 360) + ',60%,55%)';
  D.paths.forEach((p, i) => {
    const end = i + 1 < D.paths.length ? D.paths[i + 1].t : t1;
    const row = names.indexOf(p.path);
    el(svg, 'rect', {x: X(p.t), y: 5 + row * rowH, width: Math.max(1, X(end) - X(p.t)), height: rowH - 2, fill: hue(row)},
       undefined).appendChild(document.createElementNS(NS, 'title')).textContent = p.path;
  });
  names.forEach((n, i) => el(svg, 'text', {x: 12, y: 5 + i * rowH + rowH / 2 + 3, 'font-size': 10}, n));
  el(svg, 'text', {x: W - 10, y: H - 4, 'font-size': 10, 'text-anchor': 'end'},
     t0.toFixed(1) + ' .. ' + t1.toFixed(1) + ' s');
  const tb = document.getElementById('transitions');
  for (const tr of D.transitions) {
    const row = tb.insertRow();
    [tr.t.toFixed(2), tr.from, tr.to, tr.reason].forEach(v => { row.insertCell().textContent = v; });
  }
  mark(svg, D.paths.length);
}
function drawHealth() {
  const series = D.rates.map((h, i) => ({name: h.device + ' (Hz)', ys: h.rate_hz, color: ['#c33', '#39c', '#3a3', '#a6c', '#c90'][i % 5]}));
  linePlot('health', D.t, series, 'new samples per second seen by the core (Hz)');
  const tb = document.getElementById('health-table');
  if (D.health.length === 0) tb.insertRow().insertCell().textContent = 'no device health in the recording';
  for (const h of D.health) {
    const row = tb.insertRow();
    [h.device, h.states.join(', '), h.final_state, h.frames_ok, h.checksum_errors, h.framing_errors, h.reopen_count]
      .forEach(v => { row.insertCell().textContent = v; });
  }
}
try {
  drawTrack();
  linePlot('heading', D.t, [{name: 'heading', ys: D.heading, color: '#c33', wrap: true},
                            {name: 'desired heading', ys: D.desired, color: '#36c', wrap: true}], 'deg (0 north, clockwise)');
  linePlot('pulses', D.t, [{name: 'servo/port (us)', ys: D.pulse0, color: '#a6c', step: true},
                           {name: 'thrust/starboard (us)', ys: D.pulse1, color: '#c60', step: true}], 'pulse (us)');
  linePlot('speed', D.t, [{name: 'GNSS ground speed (m/s)', ys: D.speed, color: '#093'}], 'm/s');
  drawStates();
  drawHealth();
  linePlot('timing', D.t, [{name: 'tick interval (ms)', ys: D.tick_dt_ms, color: '#555'}], 'ms');
  linePlot('gnss', D.t, [{name: 'h_acc (m)', ys: D.h_acc, color: '#c33'},
                         {name: 'satellites', ys: D.sats, color: '#36c', step: true},
                         {name: 'fix type', ys: D.fix_type, color: '#093', step: true}], 'h_acc m / count / type');
} catch (e) {
  document.getElementById('error').textContent = 'drawing failed: ' + e;
}
)JS";

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
       segments = json::array();
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
  json rates_json = json::array();
  for (std::size_t i = 0; i < kInputs; ++i) {
    rates_json.push_back({{"device", kInputNames[i]}, {"rate_hz", rates[i].series}});
  }
  json data = {{"t", t},
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
               {"rates", rates_json}};
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
        if (it != in_force.end() && std::memcmp(&it->second, &value, sizeof value) == 0) continue;
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
  std::string html = kHead;
  html += "<h1>coxswain run report: " + html_escape(title) + "</h1>\n<p class=\"note\">mission " +
          html_escape(config.mission.name) + ", boat " + html_escape(config.boat.name) + "; " +
          std::to_string(r.ticks) + " ticks; replay " +
          (r.identical() ? std::string("identical to the recording")
                         : std::to_string(r.ticks_different) +
                               " ticks differ from the recording (plots show the replay)") +
          (recording.file.truncated ? "; the recording is truncated" : "") +
          "</p>\n<p id=\"error\" style=\"color:#c00\"></p>\n";
  html += plot("track", "Track on the course", 700, 560);
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
  html += plot("health", "Device rates and health", 900, 200);
  html +=
      "<table id=\"health-table\"><tr><th>device</th><th>states seen</th><th>final</th>"
      "<th>frames ok</th><th>checksum errors</th><th>framing errors</th><th>reopens</th>"
      "</tr></table>\n";
  html += plot("timing", "Tick timing (interval between ticks)", 900, 180);
  html += plot("gnss", "GNSS quality", 900, 200);
  html += "<script type=\"application/json\" id=\"report-data\">" + safe + "</script>\n<script>" +
          kScript + "</script>\n</body></html>\n";
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
