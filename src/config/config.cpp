// SPDX-License-Identifier: Apache-2.0
#include "coxswain/config/config.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <limits>

namespace coxswain::config {
namespace {

constexpr Bounds<double> kNonNegative{0.0, 1e9};
constexpr Bounds<double> kAngleDeg{-360.0, 360.0};
constexpr Bounds<std::uint16_t> kPulseUs{500, 2500};

// Every file starts with `kind: <expected>`; it lets check-config tell files apart.
bool read_kind(MapReader& root, std::string_view expected) {
  const auto kind = root.require<std::string>("kind");
  if (!kind.empty() && kind != expected) {
    root.error("kind", "must be '" + std::string(expected) + "' in this file, got '" + kind + "'");
    return false;
  }
  return true;
}

// Loads `path` and returns the reader of its top-level map, its `kind:` already checked.
std::optional<MapReader> open_root(const std::string& path, std::string_view kind,
                                   ConfigErrors& errors) {
  const auto doc = load_yaml_file(path, errors);
  if (!doc) return std::nullopt;
  MapReader root(*doc, path, "", errors);
  if (!root.valid()) return std::nullopt;
  read_kind(root, kind);
  return root;
}

core::MountTransform read_mount(MapReader& parent, std::string_view key) {
  core::MountTransform mount;
  auto m = parent.map(key);
  if (!m) return mount;
  mount.yaw_deg = m->get("yaw_deg", 0.0, kAngleDeg);
  mount.x_m = m->get("x_m", 0.0, {-10.0, 10.0});
  mount.y_m = m->get("y_m", 0.0, {-10.0, 10.0});
  m->finish();
  return mount;
}

void read_serial(MapReader& m, SerialDeviceConfig& d, const char* default_path,
                 std::uint32_t default_baud, std::uint32_t default_timeout_ms) {
  d.enabled = m.get("enabled", true);
  d.path = m.get<std::string>("path", default_path);
  d.baud = m.get<std::uint32_t>("baud", default_baud, {1200, 4'000'000});
  d.timeout_ms = m.get<std::uint32_t>("timeout_ms", default_timeout_ms, {20, 60'000});
  if (d.enabled && d.path.empty()) m.error("path", "must not be empty when the device is enabled");
}

msg::Colour read_colour(MapReader& m, std::string_view key) {
  return m.get_enum(key, msg::Colour::kUnknown,
                    {{"unknown", msg::Colour::kUnknown},
                     {"red", msg::Colour::kRed},
                     {"green", msg::Colour::kGreen},
                     {"blue", msg::Colour::kBlue},
                     {"yellow", msg::Colour::kYellow},
                     {"orange", msg::Colour::kOrange},
                     {"purple", msg::Colour::kPurple},
                     {"black", msg::Colour::kBlack},
                     {"white", msg::Colour::kWhite}});
}

msg::Shape read_shape(MapReader& m, std::string_view key) {
  return m.get_enum(key, msg::Shape::kUnknown,
                    {{"unknown", msg::Shape::kUnknown},
                     {"triangle", msg::Shape::kTriangle},
                     {"rectangle", msg::Shape::kRectangle},
                     {"cross", msg::Shape::kCross},
                     {"circle", msg::Shape::kCircle}});
}

core::GeoPoint read_geo(MapReader& m) {
  core::GeoPoint p;
  p.lat_deg = m.require<double>("lat_deg", {-90.0, 90.0});
  p.lon_deg = m.require<double>("lon_deg", {-180.0, 180.0});
  p.height_m = m.get("height_m", 0.0, {-1000.0, 10000.0});
  return p;
}

// Reports an engine's own validation message (the engines own their rules) at the section.
void check(MapReader& m, const std::optional<std::string>& problem) {
  if (problem) m.error("", *problem);
}
void check(MapReader& m, const std::string& problem) {
  if (!problem.empty()) m.error("", problem);
}

constexpr Bounds<double> kFrac{0.0, 1.0};
constexpr Bounds<double> kPositive{1e-9, 1e9};

void read_engines(MapReader& root, MissionConfig& mission) {
  if (auto m = root.map("course_frame")) {
    if (m->has("zero_heading_deg")) {
      mission.navigation.course_zero_deg = m->get("zero_heading_deg", 0.0, {-180.0, 180.0});
    }
    m->finish();
  }
  if (auto m = root.map("navigation")) {
    auto& n = mission.navigation;
    n.heading_filter_tau_s = m->get("heading_filter_tau_s", n.heading_filter_tau_s, {0.0, 10.0});
    n.position_gain = m->get("position_gain", n.position_gain, {0.01, 1.0});
    n.start_lever_arm = m->get("start_lever_arm", n.start_lever_arm);
    n.start_drift = m->get("start_drift", n.start_drift);
    m->finish();
  }
  if (auto m = root.map("gps_calibration")) {
    auto& g = mission.gps_calibration;
    g.min_fixes = m->get<std::size_t>("min_fixes", g.min_fixes, {1, 256});
    g.window = m->get<std::size_t>("window", g.window, {1, 256});
    g.max_spread_m = m->get("max_spread_m", g.max_spread_m, kPositive);
    g.max_offset_m = m->get("max_offset_m", g.max_offset_m, kPositive);
    check(*m, g.validate());
    m->finish();
  }
  if (auto m = root.map("waypoints")) {
    auto& w = mission.waypoints;
    w.arrival_radius_m = m->get("arrival_radius_m", w.arrival_radius_m, kPositive);
    w.slip_radius_m = m->get("slip_radius_m", w.slip_radius_m, kPositive);
    w.line_following = m->get("line_following", w.line_following);
    w.line.lookahead_m = m->get("lookahead_m", w.line.lookahead_m, kPositive);
    w.line.integral_gain = m->get("integral_gain", w.line.integral_gain, kNonNegative);
    w.line.max_integral_m = m->get("max_integral_m", w.line.max_integral_m, kNonNegative);
    w.line.max_dt_s = m->get("max_dt_s", w.line.max_dt_s, kPositive);
    check(*m, w.validate());
    m->finish();
  }
  if (auto m = root.map("heading_pid")) {
    auto& h = mission.heading_pid;
    h.kp_per_deg = m->get("kp_per_deg", h.kp_per_deg, kNonNegative);
    h.ki_per_deg_s = m->get("ki_per_deg_s", h.ki_per_deg_s, kNonNegative);
    h.kd_per_dps = m->get("kd_per_dps", h.kd_per_dps, kNonNegative);
    h.output_limit = m->get("output_limit", h.output_limit, kFrac);
    h.integral_zone_deg = m->get("integral_zone_deg", h.integral_zone_deg, kPositive);
    h.integral_limit = m->get("integral_limit", h.integral_limit, kNonNegative);
    h.tracking_gain_per_s = m->get("tracking_gain_per_s", h.tracking_gain_per_s, kNonNegative);
    h.derivative_tau_s = m->get("derivative_tau_s", h.derivative_tau_s, kNonNegative);
    h.max_dt_s = m->get("max_dt_s", h.max_dt_s, kPositive);
    h.reversal_hold_deg = m->get("reversal_hold_deg", h.reversal_hold_deg, {0.0, 89.0});
    check(*m, h.validate());
    m->finish();
  }
  if (auto m = root.map("speed")) {
    auto& sp = mission.speed;
    sp.min_thrust_frac = m->get("min_thrust_frac", sp.min_thrust_frac, kFrac);
    sp.max_thrust_frac = m->get("max_thrust_frac", sp.max_thrust_frac, kFrac);
    sp.slow_distance_m = m->get("slow_distance_m", sp.slow_distance_m, kNonNegative);
    sp.fast_distance_m = m->get("fast_distance_m", sp.fast_distance_m, kNonNegative);
    sp.rise_per_s = m->get("rise_per_s", sp.rise_per_s, kPositive);
    sp.fall_per_s = m->get("fall_per_s", sp.fall_per_s, kPositive);
    mission.cruise_thrust_frac = m->get("cruise_thrust_frac", mission.cruise_thrust_frac, kFrac);
    check(*m, sp.validate());
    m->finish();
  }
  if (auto m = root.map("avoidance")) {
    auto& a = mission.avoidance;
    const std::string name = m->get<std::string>("strategy", guidance::to_string(a.strategy));
    if (auto st = guidance::parse_strategy(name)) {
      a.strategy = *st;
    } else {
      m->error(
          "strategy",
          "must be one of: selection, score, risk_bin, selection_naive_2022; got '" + name + "'");
    }
    a.fan.min_deg = m->get("fan_min_deg", a.fan.min_deg, {-180.0, 180.0});
    a.fan.max_deg = m->get("fan_max_deg", a.fan.max_deg, {-180.0, 180.0});
    a.fan.bin_width_deg = m->get("bin_width_deg", a.fan.bin_width_deg, {0.1, 90.0});
    a.detection_range_m = m->get("detection_range_m", a.detection_range_m, kPositive);
    a.half_beam_m = m->get("half_beam_m", a.half_beam_m, kNonNegative);
    a.clearance_m = m->get("clearance_m", a.clearance_m, kNonNegative);
    a.slow_down_range_m = m->get("slow_down_range_m", a.slow_down_range_m, kNonNegative);
    a.min_speed_factor = m->get("min_speed_factor", a.min_speed_factor, kFrac);
    a.shrink_factor = m->get("shrink_factor", a.shrink_factor, kFrac);
    a.min_detection_range_m = m->get("min_detection_range_m", a.min_detection_range_m, kPositive);
    a.blocked_speed_factor = m->get("blocked_speed_factor", a.blocked_speed_factor, kFrac);
    a.all_blocked_policy = m->get_enum("all_blocked", a.all_blocked_policy,
                                       {{"stop", guidance::AllBlockedPolicy::kStop},
                                        {"back_off", guidance::AllBlockedPolicy::kBackOff}});
    a.back_off_speed_factor = m->get("back_off_speed_factor", a.back_off_speed_factor, kFrac);
    a.hysteresis_deg = m->get("hysteresis_deg", a.hysteresis_deg, {0.0, 180.0});
    a.hold_time_s = m->get("hold_time_s", a.hold_time_s, kNonNegative);
    if (auto sc = m->map("score")) {
      a.score_goal_weight = sc->get("goal_weight", a.score_goal_weight, kNonNegative);
      a.score_distance_weight = sc->get("distance_weight", a.score_distance_weight, kNonNegative);
      a.score_angle_weight = sc->get("angle_weight", a.score_angle_weight, kNonNegative);
      a.score_block_range_m = sc->get("block_range_m", a.score_block_range_m, kNonNegative);
      sc->finish();
    }
    if (auto r = m->map("risk")) {
      a.risk_gain_per_m = r->get("gain_per_m", a.risk_gain_per_m, kPositive);
      a.risk_offset = r->get("offset", a.risk_offset, {-100.0, 100.0});
      a.risk_max = r->get("max", a.risk_max, kPositive);
      a.risk_threshold = r->get("threshold", a.risk_threshold, kPositive);
      r->finish();
    }
    a.naive_margin_deg = m->get("naive_margin_deg", a.naive_margin_deg, {0.0, 90.0});
    if (auto sw = m->map("sweep")) {
      a.sweep_enabled = sw->get("enabled", a.sweep_enabled);
      a.hull_length_m = sw->get("hull_length_m", a.hull_length_m, kPositive);
      a.bow_ahead_m = sw->get("bow_ahead_m", a.bow_ahead_m, kNonNegative);
      a.pivot_ahead_m = sw->get("pivot_ahead_m", a.pivot_ahead_m, {-10.0, 10.0});
      a.sweep_turn_radius_m = sw->get("turn_radius_m", a.sweep_turn_radius_m, kNonNegative);
      a.sweep_clearance_m = sw->get("clearance_m", a.sweep_clearance_m, kNonNegative);
      a.sweep_step_deg = sw->get("step_deg", a.sweep_step_deg, {0.5, 45.0});
      sw->finish();
    }
    check(*m, a.validate());
    m->finish();
  }
  if (auto m = root.map("clustering")) {
    auto& c = mission.clustering;
    c.group_gap_m = m->get("group_gap_m", c.group_gap_m, kNonNegative);
    c.group_gap_per_m = m->get("group_gap_per_m", c.group_gap_per_m, kNonNegative);
    c.min_group_points = m->get("min_group_points", c.min_group_points, {1U, 4096U});
    c.split_distance_m = m->get("split_distance_m", c.split_distance_m, kNonNegative);
    c.split_distance_per_m = m->get("split_distance_per_m", c.split_distance_per_m, kNonNegative);
    c.min_split_points = m->get("min_split_points", c.min_split_points, {1U, 4096U});
    c.wall_min_length_m = m->get("wall_min_length_m", c.wall_min_length_m, kNonNegative);
    c.wall_piece_max_length_m =
        m->get("wall_piece_max_length_m", c.wall_piece_max_length_m, kPositive);
    c.min_range_m = m->get("min_range_m", c.min_range_m, kNonNegative);
    c.max_range_m = m->get("max_range_m", c.max_range_m, kPositive);
    if (auto h = m->map("hull_box")) {
      c.hull.forward_min_m = h->get("forward_min_m", c.hull.forward_min_m, {-50.0, 50.0});
      c.hull.forward_max_m = h->get("forward_max_m", c.hull.forward_max_m, {-50.0, 50.0});
      c.hull.starboard_min_m = h->get("starboard_min_m", c.hull.starboard_min_m, {-50.0, 50.0});
      c.hull.starboard_max_m = h->get("starboard_max_m", c.hull.starboard_max_m, {-50.0, 50.0});
      h->finish();
    }
    c.profile_bin_width_deg = m->get("profile_bin_width_deg", c.profile_bin_width_deg, kPositive);
    c.line_fit = m->get("line_fit", c.line_fit);
    c.merge_across_seam = m->get("merge_across_seam", c.merge_across_seam);
    check(*m, c.validate());
    m->finish();
  }
  if (auto m = root.map("vision_vote")) {
    auto& v = mission.vision_vote;
    v.window_ns = core::sec_to_ns(m->get("window_s", core::ns_to_sec(v.window_ns), {0.05, 600.0}));
    v.min_ratio = m->get("min_ratio", v.min_ratio, {0.01, 1.0});
    v.min_frames = m->get<std::size_t>("min_frames", v.min_frames, {1, 256});
    v.min_span_ns =
        core::sec_to_ns(m->get("min_span_s", core::ns_to_sec(v.min_span_ns), {0.0, 600.0}));
    if (v.min_span_ns > v.window_ns) m->error("min_span_s", "must not exceed window_s");
    m->finish();
  }
  if (auto m = root.map("course1")) {
    auto& c = mission.course1;
    c.turn_deg = m->get("turn_deg", c.turn_deg, {-180.0, 180.0});
    c.search_timeout_s = m->get("search_timeout_s", c.search_timeout_s, {0.0, 600.0});
    c.search_thrust_frac = m->get("search_thrust_frac", c.search_thrust_frac, kFrac);
    c.buoy_colour = read_colour(*m, "buoy_colour");
    if (!m->has("buoy_colour")) c.buoy_colour = msg::Colour::kPurple;
    m->finish();
  }
  if (auto m = root.map("course2")) {
    auto& c = mission.course2;
    auto& b = c.circling;
    b.target_bearing_deg = m->get("target_bearing_deg", b.target_bearing_deg, kAngleDeg);
    b.target_distance_m = m->get("target_distance_m", b.target_distance_m, kPositive);
    b.bearing_gain = m->get("bearing_gain", b.bearing_gain, kPositive);
    b.distance_gain_deg_per_m =
        m->get("distance_gain_deg_per_m", b.distance_gain_deg_per_m, kNonNegative);
    b.max_distance_correction_deg =
        m->get("max_distance_correction_deg", b.max_distance_correction_deg, {0.0, 180.0});
    b.max_turn_deg = m->get("max_turn_deg", b.max_turn_deg, {0.0, 180.0});
    b.search_turn_deg = m->get("search_turn_deg", b.search_turn_deg, {0.0, 180.0});
    b.complete_turn_deg = m->get("complete_turn_deg", b.complete_turn_deg, {1.0, 3600.0});
    b.max_heading_step_deg = m->get("max_heading_step_deg", b.max_heading_step_deg, kAngleDeg);
    check(*m, b.validate());
    c.circling_thrust_frac = m->get("circling_thrust_frac", c.circling_thrust_frac, kFrac);
    c.exit_course_deg = m->get("exit_course_deg", c.exit_course_deg, {-180.0, 180.0});
    c.exit_align_deg = m->get("exit_align_deg", c.exit_align_deg, {1.0, 180.0});
    c.colour_timeout_s = m->get("colour_timeout_s", c.colour_timeout_s, {0.0, 3600.0});
    c.seek_thrust_frac = m->get("seek_thrust_frac", c.seek_thrust_frac, kFrac);
    c.buoy_range_window_deg = m->get("buoy_range_window_deg", c.buoy_range_window_deg, {0.0, 45.0});
    c.buoy_memory_s = m->get("buoy_memory_s", c.buoy_memory_s, {0.0, 10.0});
    c.lidar_tracking = m->get("lidar_tracking", c.lidar_tracking);
    c.buoy_radius_m = m->get("buoy_radius_m", c.buoy_radius_m, {0.0, 5.0});
    c.track_gate_m = m->get("track_gate_m", c.track_gate_m, kPositive);
    c.track_timeout_s = m->get("track_timeout_s", c.track_timeout_s, {0.1, 60.0});
    c.buoy_colour = read_colour(*m, "buoy_colour");
    if (!m->has("buoy_colour")) c.buoy_colour = msg::Colour::kPurple;
    if (m->has("colours")) {
      c.colours.clear();
      const auto list = m->sequence("colours");
      for (std::size_t i = 0; i < list.size(); ++i) {
        const std::string name = list[i].IsScalar() ? list[i].Scalar() : std::string{};
        bool found = false;
        for (auto col : {msg::Colour::kRed, msg::Colour::kGreen, msg::Colour::kBlue,
                         msg::Colour::kYellow, msg::Colour::kOrange, msg::Colour::kPurple,
                         msg::Colour::kBlack, msg::Colour::kWhite}) {
          if (name == msg::colour_name(col)) {
            c.colours.push_back(col);
            found = true;
          }
        }
        if (!found)
          m->error("colours", "unknown colour '" + name + "' at index " + std::to_string(i));
      }
      if (c.colours.empty() || c.colours.size() > 8)
        m->error("colours", "must list 1 to 8 colours");
    }
    m->finish();
  }
  if (auto m = root.map("docking")) {
    auto& d = mission.docking;
    auto& a = d.approach;
    a.lookahead_m = m->get("lookahead_m", a.lookahead_m, kPositive);
    a.stop_range_m = m->get("stop_range_m", a.stop_range_m, kPositive);
    a.marker_gain = m->get("marker_gain", a.marker_gain, kNonNegative);
    a.max_marker_turn_deg = m->get("max_marker_turn_deg", a.max_marker_turn_deg, {0.0, 180.0});
    a.ahead_half_angle_deg = m->get("ahead_half_angle_deg", a.ahead_half_angle_deg, {0.5, 90.0});
    check(*m, a.validate());
    d.decision_distance_m = m->get("decision_distance_m", d.decision_distance_m, kPositive);
    d.face_time_s = m->get("face_time_s", d.face_time_s, {0.1, 600.0});
    d.face_tolerance_deg = m->get("face_tolerance_deg", d.face_tolerance_deg, {0.5, 90.0});
    d.marker_window_deg = m->get("marker_window_deg", d.marker_window_deg, {0.5, 90.0});
    d.approach_thrust_frac = m->get("approach_thrust_frac", d.approach_thrust_frac, kFrac);
    d.open_window_deg = m->get("open_window_deg", d.open_window_deg, {0.0, 45.0});
    d.open_max_range_m = m->get("open_max_range_m", d.open_max_range_m, kPositive);
    d.survey_distance_m = m->get("survey_distance_m", d.survey_distance_m, kPositive);
    d.slip_depth_m = m->get("slip_depth_m", d.slip_depth_m, {0.0, 20.0});
    d.turn_thrust_frac = m->get("turn_thrust_frac", d.turn_thrust_frac, kFrac);
    d.line_up_distance_m = m->get("line_up_distance_m", d.line_up_distance_m, {0.0, 50.0});
    d.axis_lookahead_m = m->get("axis_lookahead_m", d.axis_lookahead_m, kPositive);
    d.marker_fix_gain = m->get("marker_fix_gain", d.marker_fix_gain, {0.0, 1.0});
    d.marker_fix_max_range_m =
        m->get("marker_fix_max_range_m", d.marker_fix_max_range_m, kPositive);
    d.max_marker_fix_m = m->get("max_marker_fix_m", d.max_marker_fix_m, {0.0, 10.0});
    d.slip_match_m = m->get("slip_match_m", d.slip_match_m, kPositive);
    d.commit_range_m = m->get("commit_range_m", d.commit_range_m, kPositive);
    d.sweep_wall_range_m = m->get("sweep_wall_range_m", d.sweep_wall_range_m, kPositive);
    d.sweep_standoff_m = m->get("sweep_standoff_m", d.sweep_standoff_m, kPositive);
    d.sweep_turn_back_m = m->get("sweep_turn_back_m", d.sweep_turn_back_m, kPositive);
    auto& sl = d.slip;
    sl.min_width_m = m->get("slip_min_width_m", sl.min_width_m, kPositive);
    sl.max_width_m = m->get("slip_max_width_m", sl.max_width_m, kPositive);
    sl.min_depth_m = m->get("slip_min_depth_m", sl.min_depth_m, kPositive);
    sl.max_depth_m = m->get("slip_max_depth_m", sl.max_depth_m, kPositive);
    sl.max_bearing_deg = m->get("slip_max_bearing_deg", sl.max_bearing_deg, {1.0, 180.0});
    sl.max_axis_deg = m->get("slip_max_axis_deg", sl.max_axis_deg, {1.0, 180.0});
    sl.max_range_m = m->get("slip_max_range_m", sl.max_range_m, kPositive);
    check(*m, sl.validate());
    m->finish();
  }
}

}  // namespace

BoatConfig load_boat_config(const std::string& path, ConfigErrors& errors) {
  BoatConfig boat;
  boat.file = path;
  auto opened = open_root(path, "boat", errors);
  if (!opened) return boat;
  MapReader& root = *opened;
  boat.name = root.get<std::string>("name", "boat");
  if (auto hull = root.map("hull", true)) {
    boat.hull.length_m = hull->require<double>("length_m", {0.2, 20.0});
    boat.hull.beam_m = hull->require<double>("beam_m", {0.1, 10.0});
    boat.hull.bow_overhang_m = hull->get("bow_overhang_m", 0.1, {0.0, 20.0});
    if (boat.hull.bow_overhang_m > boat.hull.length_m) {
      hull->error("bow_overhang_m", "must not exceed hull.length_m");
    }
    hull->finish();
  }
  if (auto mounts = root.map("mounts", true)) {
    boat.mounts.lidar = read_mount(*mounts, "lidar");
    boat.mounts.imu = read_mount(*mounts, "imu");
    boat.mounts.gnss = read_mount(*mounts, "gnss");
    boat.mounts.camera = read_mount(*mounts, "camera");
    mounts->finish();
  }
  if (auto act = root.map("actuators", true)) {
    ActuatorsConfig& a = boat.actuators;
    a.layout = act->get_enum("layout", msg::ActuatorLayout::kServoThruster,
                             {{"servo_thruster", msg::ActuatorLayout::kServoThruster},
                              {"twin_thrusters", msg::ActuatorLayout::kTwinThrusters}});
    a.command_rate_hz = act->get("command_rate_hz", 20.0, {1.0, 200.0});
    a.twin_track_width_m = act->get("twin_track_width_m", 0.6, {0.05, 10.0});
    if (auto s = act->map("servo", a.layout == msg::ActuatorLayout::kServoThruster)) {
      a.servo.center_us = s->get("center_us", a.servo.center_us, kPulseUs);
      a.servo.min_us = s->get("min_us", a.servo.min_us, kPulseUs);
      a.servo.max_us = s->get("max_us", a.servo.max_us, kPulseUs);
      a.servo.max_deflection_deg = s->get("max_deflection_deg", 25.0, {1.0, 90.0});
      a.servo.rate_deg_per_s = s->get("rate_deg_per_s", 180.0, {1.0, 5000.0});
      a.servo.deadband_us = s->get<std::uint16_t>("deadband_us", 4, {0, 100});
      a.servo.reversed = s->get("reversed", false);
      if (!(a.servo.min_us < a.servo.center_us && a.servo.center_us < a.servo.max_us)) {
        s->error("center_us", "must lie strictly between min_us and max_us");
      }
      s->finish();
    }
    if (auto t = act->map("thruster", true)) {
      ThrusterConfig& th = a.thruster;
      th.neutral_us = t->get("neutral_us", th.neutral_us, kPulseUs);
      th.min_us = t->get("min_us", th.min_us, kPulseUs);
      th.max_us = t->get("max_us", th.max_us, kPulseUs);
      th.forward_start_us = t->get("forward_start_us", th.forward_start_us, kPulseUs);
      th.reverse_start_us = t->get("reverse_start_us", th.reverse_start_us, kPulseUs);
      th.reverse_allowed = t->get("reverse_allowed", true);
      if (!(th.min_us <= th.reverse_start_us && th.reverse_start_us <= th.neutral_us &&
            th.neutral_us <= th.forward_start_us && th.forward_start_us < th.max_us)) {
        t->error("",
                 "pulses must be ordered min_us <= reverse_start_us <= neutral_us <= "
                 "forward_start_us < max_us");
      }
      t->finish();
    }
    act->finish();
  }
  root.finish();
  return boat;
}

DevicesConfig load_devices_config(const std::string& path, ConfigErrors& errors) {
  DevicesConfig d;
  d.file = path;
  auto opened = open_root(path, "devices", errors);
  if (!opened) return d;
  MapReader& root = *opened;
  if (auto m = root.map("lidar", true)) {
    read_serial(*m, d.lidar, "/dev/ttyLiDAR", 115200, 200);
    d.lidar.scan_mode = m->get_enum("scan_mode", LidarScanMode::kAuto,
                                    {{"auto", LidarScanMode::kAuto},
                                     {"standard", LidarScanMode::kStandard},
                                     {"express", LidarScanMode::kExpress}});
    d.lidar.motor_pwm = m->get<std::uint16_t>("motor_pwm", 660, {0, 1023});
    d.lidar.motor_rpm = m->get<std::uint16_t>("motor_rpm", 600, {0, 3000});
    m->finish();
  }
  if (auto m = root.map("imu", true)) {
    read_serial(*m, d.imu, "/dev/ttyIMU", 115200, 200);
    d.imu.output = m->get_enum("output", ImuOutput::kAscii,
                               {{"ascii", ImuOutput::kAscii}, {"binary", ImuOutput::kBinary}});
    d.imu.rate_hz = m->get("rate_hz", 100.0, {1.0, 100.0});
    d.imu.declination_deg = m->get("declination_deg", 0.0, {-180.0, 180.0});
    // ---- BEGIN magnetometer calibration (`coxswain calibrate mag`; port to the tables) ----
    d.imu.mag_hard_iron_x_ut = m->get("mag_hard_iron_x_ut", 0.0, {-1000.0, 1000.0});
    d.imu.mag_hard_iron_y_ut = m->get("mag_hard_iron_y_ut", 0.0, {-1000.0, 1000.0});
    d.imu.mag_soft_iron_xx = m->get("mag_soft_iron_xx", 1.0, {-10.0, 10.0});
    d.imu.mag_soft_iron_xy = m->get("mag_soft_iron_xy", 0.0, {-10.0, 10.0});
    d.imu.mag_soft_iron_yx = m->get("mag_soft_iron_yx", 0.0, {-10.0, 10.0});
    d.imu.mag_soft_iron_yy = m->get("mag_soft_iron_yy", 1.0, {-10.0, 10.0});
    // ---- END magnetometer calibration ----
    m->finish();
  }
  if (auto m = root.map("gnss", true)) {
    read_serial(*m, d.gnss, "/dev/ttyGPS", 38400, 1500);
    d.gnss.receiver = m->get_enum("receiver", GnssReceiver::kF9,
                                  {{"f9", GnssReceiver::kF9}, {"m8", GnssReceiver::kM8}});
    d.gnss.port =
        m->get_enum("port", GnssPort::kUsb, {{"usb", GnssPort::kUsb}, {"uart1", GnssPort::kUart1}});
    d.gnss.rate_hz = m->get("rate_hz", 5.0, {0.1, 25.0});
    d.gnss.nmea_output = m->get("nmea_output", false);
    d.gnss.rtcm_input = m->get<std::string>("rtcm_input", "");
    m->finish();
  }
  if (auto m = root.map("arduino", true)) {
    read_serial(*m, d.arduino, "/dev/ttyARDUINO", 115200, 500);
    d.arduino.failsafe_ms = m->get<std::uint32_t>("failsafe_ms", 300, {50, 5000});
    m->finish();
  }
  if (auto m = root.map("camera", true)) {
    CameraDeviceConfig& c = d.camera;
    c.enabled = m->get("enabled", true);
    c.source = m->get<std::string>("source", "/dev/videoCAM");
    c.loop = m->get("loop", true);
    c.width_px = m->get<std::uint32_t>("width_px", 640, {16, 8192});
    c.height_px = m->get<std::uint32_t>("height_px", 480, {16, 8192});
    c.fps = m->get("fps", 30.0, {0.5, 240.0});
    c.hfov_deg = m->get("hfov_deg", 80.0, {5.0, 179.0});
    c.auto_exposure = m->get("auto_exposure", false);
    c.exposure = m->get("exposure", 100.0, kNonNegative);
    c.saturation = m->get("saturation", 128.0, kNonNegative);
    c.contrast = m->get("contrast", 128.0, kNonNegative);
    c.brightness = m->get("brightness", 128.0, kNonNegative);
    c.timeout_ms = m->get<std::uint32_t>("timeout_ms", 1000, {20, 60'000});
    if (c.enabled && c.source.empty()) m->error("source", "must not be empty when enabled");
    m->finish();
  }
  if (auto m = root.map("live")) {
    LiveConfig& l = d.live;
    l.control_socket = m->get<std::string>("control_socket", "");
    l.http_enabled = m->get("http_enabled", true);
    l.http_address = m->get<std::string>("http_address", "127.0.0.1");
    l.http_port = m->get<std::uint16_t>("http_port", 8765, {0, 65535});
    l.viz_rate_hz = m->get("viz_rate_hz", 10.0, {0.1, 100.0});
    l.token = m->get<std::string>("token", "");
    m->finish();
  }
  root.finish();
  return d;
}

MissionConfig load_mission_config(const std::string& path, ConfigErrors& errors) {
  MissionConfig mission;
  mission.file = path;
  auto opened = open_root(path, "mission", errors);
  if (!opened) return mission;
  MapReader& root = *opened;
  mission.name = root.require<std::string>("name");
  for (char ch : mission.name) {
    const bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                    (ch >= '0' && ch <= '9') || ch == '_' || ch == '-';
    if (!ok) {
      root.error("name", "may hold only letters, digits, '_' and '-' (it names the run folder)");
      break;
    }
  }
  mission.tick_rate_hz = root.get("tick_rate_hz", 50.0, {1.0, 1000.0});
  if (auto origin = root.map("origin", true)) {
    mission.origin = read_geo(*origin);
    origin->finish();
  }
  if (auto start = root.map("start")) {
    mission.start_mode = start->get_enum("mode", StartMode::kImmediate,
                                         {{"immediate", StartMode::kImmediate},
                                          {"arduino_switch", StartMode::kArduinoSwitch},
                                          {"control", StartMode::kControl}});
    mission.calibrate_gps_at_start = start->get("calibrate_gps", true);
    mission.require_arduino = start->get("require_arduino", true);
    start->finish();
  }
  if (auto stale = root.map("stale_after_ms")) {
    constexpr Bounds<std::uint32_t> kStaleMs{20, 60'000};
    mission.lidar_stale_ms = stale->get("lidar", mission.lidar_stale_ms, kStaleMs);
    mission.imu_stale_ms = stale->get("imu", mission.imu_stale_ms, kStaleMs);
    mission.gnss_stale_ms = stale->get("gnss", mission.gnss_stale_ms, kStaleMs);
    mission.arduino_stale_ms = stale->get("arduino", mission.arduino_stale_ms, kStaleMs);
    stale->finish();
  }
  read_engines(root, mission);
  const auto tasks = root.sequence("tasks", true);
  if (tasks.empty() && root.has("tasks")) root.error("tasks", "must list at least one task");
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    auto t = root.element(tasks[i], i, "tasks");
    if (!t) continue;
    TaskConfig task;
    task.type = t->get_enum("type", TaskType::kHopping,
                            {{"hopping", TaskType::kHopping},
                             {"obstacle_course", TaskType::kObstacleCourse},
                             {"course1", TaskType::kCourse1},
                             {"course2", TaskType::kCourse2},
                             {"docking", TaskType::kDocking}});
    if (!t->has("type")) t->error("type", "is required");
    task.name = t->get<std::string>("name", std::string(task_type_name(task.type)));
    task.time_limit_s = t->get("time_limit_s", 300.0, {1.0, 7200.0});
    task.on_timeout = t->get_enum(
        "on_timeout", TimeoutOutcome::kNextTask,
        {{"next_task", TimeoutOutcome::kNextTask}, {"finish", TimeoutOutcome::kFinish}});
    task.docking_style = t->get_enum(
        "style", DockingStyle::kKaboat2022,
        {{"kaboat2022", DockingStyle::kKaboat2022}, {"course3", DockingStyle::kCourse3}});
    if (t->has("style") && task.type != TaskType::kDocking) {
      t->error("style", "applies to docking tasks only");
    }
    const auto slips = t->sequence("slips");
    for (std::size_t w = 0; w < slips.size(); ++w) {
      auto sp = t->element(slips[w], w, "slips");
      if (!sp) continue;
      task.slips.push_back(read_geo(*sp));
      sp->finish();
    }
    task.dock_heading_deg = t->get("dock_heading_deg", 0.0, {-180.0, 180.0});
    if (task.type == TaskType::kDocking && task.docking_style == DockingStyle::kKaboat2022 &&
        task.slips.empty()) {
      t->error("slips", "a kaboat2022 docking task needs at least one slip");
    }
    const auto waypoints = t->sequence("waypoints");
    for (std::size_t w = 0; w < waypoints.size(); ++w) {
      auto wp = t->element(waypoints[w], w, "waypoints");
      if (!wp) continue;
      task.waypoints.push_back(read_geo(*wp));
      wp->finish();
    }
    task.target_colour = read_colour(*t, "target_colour");
    task.target_shape = read_shape(*t, "target_shape");
    if ((task.type == TaskType::kObstacleCourse || task.type == TaskType::kCourse1 ||
         task.type == TaskType::kCourse2) &&
        task.waypoints.empty() && t->has("type")) {
      t->error("waypoints", "this task needs at least one waypoint");
    }
    if (task.waypoints.size() > guidance::WaypointFollower::kMaxWaypoints ||
        task.slips.size() > 8) {
      t->error("waypoints", "at most 64 waypoints and 8 slips per task");
    }
    if (task.type == TaskType::kHopping && task.waypoints.size() < 2) {
      t->error("waypoints", "a hopping task needs at least two waypoints");
    }
    t->finish();
    mission.tasks.push_back(std::move(task));
  }
  root.finish();
  return mission;
}

ConfigKind detect_config_kind(const std::string& path, ConfigErrors& errors) {
  const auto doc = load_yaml_file(path, errors);
  if (!doc) return ConfigKind::kUnknown;
  if (!doc->IsMap() || !(*doc)["kind"] || !(*doc)["kind"].IsScalar()) {
    errors.add({path, 1, "kind",
                "is required: every coxswain config file starts with "
                "kind: boat | devices | mission | course | sensors"});
    return ConfigKind::kUnknown;
  }
  const std::string kind = (*doc)["kind"].Scalar();
  if (kind == "boat") return ConfigKind::kBoat;
  if (kind == "devices") return ConfigKind::kDevices;
  if (kind == "mission") return ConfigKind::kMission;
  if (kind == "course") return ConfigKind::kCourse;
  if (kind == "sensors") return ConfigKind::kSimSensors;
  errors.add({path, (*doc)["kind"].Mark().line + 1, "kind",
              "must be one of: boat, devices, mission, course, sensors; got '" + kind + "'"});
  return ConfigKind::kUnknown;
}

std::string_view task_type_name(TaskType type) {
  switch (type) {
    case TaskType::kHopping:
      return "hopping";
    case TaskType::kObstacleCourse:
      return "obstacle_course";
    case TaskType::kCourse1:
      return "course1";
    case TaskType::kCourse2:
      return "course2";
    case TaskType::kDocking:
      return "docking";
  }
  return "unknown";
}

namespace {

void emit_mount(YAML::Emitter& out, const char* name, const core::MountTransform& m) {
  out << YAML::Key << name << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key << "yaw_deg"
      << YAML::Value << m.yaw_deg << YAML::Key << "x_m" << YAML::Value << m.x_m << YAML::Key
      << "y_m" << YAML::Value << m.y_m << YAML::EndMap;
}

template <class T>
void kv(YAML::Emitter& out, const char* key, const T& value) {
  out << YAML::Key << key << YAML::Value << value;
}

void emit_serial(YAML::Emitter& out, const SerialDeviceConfig& d) {
  kv(out, "enabled", d.enabled);
  kv(out, "path", d.path);
  kv(out, "baud", d.baud);
  kv(out, "timeout_ms", d.timeout_ms);
}

void begin(YAML::Emitter& out, const char* key, bool flow = false) {
  out << YAML::Key << key << YAML::Value;
  if (flow) out << YAML::Flow;
  out << YAML::BeginMap;
}

// The engine sections, in the mission file's own layout (so the printout loads back).
void emit_engines(YAML::Emitter& out, const MissionConfig& m) {
  if (m.navigation.course_zero_deg) {
    begin(out, "course_frame", true);
    kv(out, "zero_heading_deg", *m.navigation.course_zero_deg);
    out << YAML::EndMap;
  }
  begin(out, "navigation", true);
  kv(out, "heading_filter_tau_s", m.navigation.heading_filter_tau_s);
  kv(out, "position_gain", m.navigation.position_gain);
  kv(out, "start_lever_arm", m.navigation.start_lever_arm);
  kv(out, "start_drift", m.navigation.start_drift);
  out << YAML::EndMap;
  const auto& g = m.gps_calibration;
  begin(out, "gps_calibration", true);
  kv(out, "min_fixes", g.min_fixes);
  kv(out, "window", g.window);
  kv(out, "max_spread_m", g.max_spread_m);
  kv(out, "max_offset_m", g.max_offset_m);
  out << YAML::EndMap;
  const auto& w = m.waypoints;
  begin(out, "waypoints");
  kv(out, "arrival_radius_m", w.arrival_radius_m);
  kv(out, "slip_radius_m", w.slip_radius_m);
  kv(out, "line_following", w.line_following);
  kv(out, "lookahead_m", w.line.lookahead_m);
  kv(out, "integral_gain", w.line.integral_gain);
  kv(out, "max_integral_m", w.line.max_integral_m);
  kv(out, "max_dt_s", w.line.max_dt_s);
  out << YAML::EndMap;
  const auto& h = m.heading_pid;
  begin(out, "heading_pid");
  kv(out, "kp_per_deg", h.kp_per_deg);
  kv(out, "ki_per_deg_s", h.ki_per_deg_s);
  kv(out, "kd_per_dps", h.kd_per_dps);
  kv(out, "output_limit", h.output_limit);
  kv(out, "integral_zone_deg", h.integral_zone_deg);
  kv(out, "integral_limit", h.integral_limit);
  kv(out, "tracking_gain_per_s", h.tracking_gain_per_s);
  kv(out, "derivative_tau_s", h.derivative_tau_s);
  kv(out, "max_dt_s", h.max_dt_s);
  kv(out, "reversal_hold_deg", h.reversal_hold_deg);
  out << YAML::EndMap;
  const auto& sp = m.speed;
  begin(out, "speed");
  kv(out, "min_thrust_frac", sp.min_thrust_frac);
  kv(out, "max_thrust_frac", sp.max_thrust_frac);
  kv(out, "slow_distance_m", sp.slow_distance_m);
  kv(out, "fast_distance_m", sp.fast_distance_m);
  kv(out, "rise_per_s", sp.rise_per_s);
  kv(out, "fall_per_s", sp.fall_per_s);
  kv(out, "cruise_thrust_frac", m.cruise_thrust_frac);
  out << YAML::EndMap;
  const auto& a = m.avoidance;
  begin(out, "avoidance");
  kv(out, "strategy", std::string(guidance::to_string(a.strategy)));
  kv(out, "fan_min_deg", a.fan.min_deg);
  kv(out, "fan_max_deg", a.fan.max_deg);
  kv(out, "bin_width_deg", a.fan.bin_width_deg);
  kv(out, "detection_range_m", a.detection_range_m);
  kv(out, "half_beam_m", a.half_beam_m);
  kv(out, "clearance_m", a.clearance_m);
  kv(out, "slow_down_range_m", a.slow_down_range_m);
  kv(out, "min_speed_factor", a.min_speed_factor);
  kv(out, "shrink_factor", a.shrink_factor);
  kv(out, "min_detection_range_m", a.min_detection_range_m);
  kv(out, "blocked_speed_factor", a.blocked_speed_factor);
  kv(out, "all_blocked",
     a.all_blocked_policy == guidance::AllBlockedPolicy::kStop ? "stop" : "back_off");
  kv(out, "back_off_speed_factor", a.back_off_speed_factor);
  kv(out, "hysteresis_deg", a.hysteresis_deg);
  kv(out, "hold_time_s", a.hold_time_s);
  begin(out, "score", true);
  kv(out, "goal_weight", a.score_goal_weight);
  kv(out, "distance_weight", a.score_distance_weight);
  kv(out, "angle_weight", a.score_angle_weight);
  kv(out, "block_range_m", a.score_block_range_m);
  out << YAML::EndMap;
  begin(out, "risk", true);
  kv(out, "gain_per_m", a.risk_gain_per_m);
  kv(out, "offset", a.risk_offset);
  kv(out, "max", a.risk_max);
  kv(out, "threshold", a.risk_threshold);
  out << YAML::EndMap;
  kv(out, "naive_margin_deg", a.naive_margin_deg);
  begin(out, "sweep", true);
  kv(out, "enabled", a.sweep_enabled);
  kv(out, "hull_length_m", a.hull_length_m);
  kv(out, "bow_ahead_m", a.bow_ahead_m);
  kv(out, "pivot_ahead_m", a.pivot_ahead_m);
  kv(out, "turn_radius_m", a.sweep_turn_radius_m);
  kv(out, "clearance_m", a.sweep_clearance_m);
  kv(out, "step_deg", a.sweep_step_deg);
  out << YAML::EndMap;
  out << YAML::EndMap;
  const auto& c = m.clustering;
  begin(out, "clustering");
  kv(out, "group_gap_m", c.group_gap_m);
  kv(out, "group_gap_per_m", c.group_gap_per_m);
  kv(out, "min_group_points", c.min_group_points);
  kv(out, "split_distance_m", c.split_distance_m);
  kv(out, "split_distance_per_m", c.split_distance_per_m);
  kv(out, "min_split_points", c.min_split_points);
  kv(out, "wall_min_length_m", c.wall_min_length_m);
  kv(out, "wall_piece_max_length_m", c.wall_piece_max_length_m);
  kv(out, "min_range_m", c.min_range_m);
  kv(out, "max_range_m", c.max_range_m);
  begin(out, "hull_box", true);
  kv(out, "forward_min_m", c.hull.forward_min_m);
  kv(out, "forward_max_m", c.hull.forward_max_m);
  kv(out, "starboard_min_m", c.hull.starboard_min_m);
  kv(out, "starboard_max_m", c.hull.starboard_max_m);
  out << YAML::EndMap;
  kv(out, "profile_bin_width_deg", c.profile_bin_width_deg);
  kv(out, "line_fit", c.line_fit);
  kv(out, "merge_across_seam", c.merge_across_seam);
  out << YAML::EndMap;
  const auto& v = m.vision_vote;
  begin(out, "vision_vote", true);
  kv(out, "window_s", core::ns_to_sec(v.window_ns));
  kv(out, "min_ratio", v.min_ratio);
  kv(out, "min_frames", v.min_frames);
  kv(out, "min_span_s", core::ns_to_sec(v.min_span_ns));
  out << YAML::EndMap;
  const auto& c1 = m.course1;
  begin(out, "course1");
  kv(out, "turn_deg", c1.turn_deg);
  kv(out, "search_timeout_s", c1.search_timeout_s);
  kv(out, "search_thrust_frac", c1.search_thrust_frac);
  kv(out, "buoy_colour", std::string(msg::colour_name(c1.buoy_colour)));
  out << YAML::EndMap;
  const auto& c2 = m.course2;
  const auto& b = c2.circling;
  begin(out, "course2");
  kv(out, "buoy_colour", std::string(msg::colour_name(c2.buoy_colour)));
  kv(out, "target_bearing_deg", b.target_bearing_deg);
  kv(out, "target_distance_m", b.target_distance_m);
  kv(out, "bearing_gain", b.bearing_gain);
  kv(out, "distance_gain_deg_per_m", b.distance_gain_deg_per_m);
  kv(out, "max_distance_correction_deg", b.max_distance_correction_deg);
  kv(out, "max_turn_deg", b.max_turn_deg);
  kv(out, "search_turn_deg", b.search_turn_deg);
  kv(out, "complete_turn_deg", b.complete_turn_deg);
  kv(out, "max_heading_step_deg", b.max_heading_step_deg);
  kv(out, "circling_thrust_frac", c2.circling_thrust_frac);
  kv(out, "buoy_range_window_deg", c2.buoy_range_window_deg);
  kv(out, "buoy_memory_s", c2.buoy_memory_s);
  kv(out, "lidar_tracking", c2.lidar_tracking);
  kv(out, "buoy_radius_m", c2.buoy_radius_m);
  kv(out, "track_gate_m", c2.track_gate_m);
  kv(out, "track_timeout_s", c2.track_timeout_s);
  kv(out, "exit_course_deg", c2.exit_course_deg);
  kv(out, "exit_align_deg", c2.exit_align_deg);
  kv(out, "seek_thrust_frac", c2.seek_thrust_frac);
  kv(out, "colour_timeout_s", c2.colour_timeout_s);
  out << YAML::Key << "colours" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (const msg::Colour col : c2.colours) out << std::string(msg::colour_name(col));
  out << YAML::EndSeq << YAML::EndMap;
  const auto& d = m.docking;
  begin(out, "docking");
  kv(out, "lookahead_m", d.approach.lookahead_m);
  kv(out, "stop_range_m", d.approach.stop_range_m);
  kv(out, "marker_gain", d.approach.marker_gain);
  kv(out, "max_marker_turn_deg", d.approach.max_marker_turn_deg);
  kv(out, "ahead_half_angle_deg", d.approach.ahead_half_angle_deg);
  kv(out, "decision_distance_m", d.decision_distance_m);
  kv(out, "face_time_s", d.face_time_s);
  kv(out, "face_tolerance_deg", d.face_tolerance_deg);
  kv(out, "marker_window_deg", d.marker_window_deg);
  kv(out, "approach_thrust_frac", d.approach_thrust_frac);
  kv(out, "open_window_deg", d.open_window_deg);
  kv(out, "open_max_range_m", d.open_max_range_m);
  kv(out, "survey_distance_m", d.survey_distance_m);
  kv(out, "slip_depth_m", d.slip_depth_m);
  kv(out, "turn_thrust_frac", d.turn_thrust_frac);
  kv(out, "line_up_distance_m", d.line_up_distance_m);
  kv(out, "axis_lookahead_m", d.axis_lookahead_m);
  kv(out, "marker_fix_gain", d.marker_fix_gain);
  kv(out, "marker_fix_max_range_m", d.marker_fix_max_range_m);
  kv(out, "max_marker_fix_m", d.max_marker_fix_m);
  kv(out, "slip_match_m", d.slip_match_m);
  kv(out, "commit_range_m", d.commit_range_m);
  kv(out, "sweep_wall_range_m", d.sweep_wall_range_m);
  kv(out, "sweep_standoff_m", d.sweep_standoff_m);
  kv(out, "sweep_turn_back_m", d.sweep_turn_back_m);
  kv(out, "slip_min_width_m", d.slip.min_width_m);
  kv(out, "slip_max_width_m", d.slip.max_width_m);
  kv(out, "slip_min_depth_m", d.slip.min_depth_m);
  kv(out, "slip_max_depth_m", d.slip.max_depth_m);
  kv(out, "slip_max_bearing_deg", d.slip.max_bearing_deg);
  kv(out, "slip_max_axis_deg", d.slip.max_axis_deg);
  kv(out, "slip_max_range_m", d.slip.max_range_m);
  out << YAML::EndMap;
}

}  // namespace

std::string to_yaml(const Configuration& c) {
  YAML::Emitter out;
  // Replay rebuilds the core from this text: every double must load back bit for bit.
  out.SetDoublePrecision(std::numeric_limits<double>::max_digits10);
  out.SetFloatPrecision(std::numeric_limits<float>::max_digits10);
  out << YAML::BeginMap;
  out << YAML::Key << "boat" << YAML::Value << YAML::BeginMap;
  kv(out, "file", c.boat.file);
  kv(out, "name", c.boat.name);
  out << YAML::Key << "hull" << YAML::Value << YAML::BeginMap;
  kv(out, "length_m", c.boat.hull.length_m);
  kv(out, "beam_m", c.boat.hull.beam_m);
  kv(out, "bow_overhang_m", c.boat.hull.bow_overhang_m);
  out << YAML::EndMap;
  out << YAML::Key << "mounts" << YAML::Value << YAML::BeginMap;
  emit_mount(out, "lidar", c.boat.mounts.lidar);
  emit_mount(out, "imu", c.boat.mounts.imu);
  emit_mount(out, "gnss", c.boat.mounts.gnss);
  emit_mount(out, "camera", c.boat.mounts.camera);
  out << YAML::EndMap;
  const ActuatorsConfig& a = c.boat.actuators;
  out << YAML::Key << "actuators" << YAML::Value << YAML::BeginMap;
  kv(out, "layout",
     a.layout == msg::ActuatorLayout::kServoThruster ? "servo_thruster" : "twin_thrusters");
  kv(out, "command_rate_hz", a.command_rate_hz);
  kv(out, "twin_track_width_m", a.twin_track_width_m);
  out << YAML::Key << "servo" << YAML::Value << YAML::BeginMap;
  kv(out, "center_us", a.servo.center_us);
  kv(out, "min_us", a.servo.min_us);
  kv(out, "max_us", a.servo.max_us);
  kv(out, "max_deflection_deg", a.servo.max_deflection_deg);
  kv(out, "rate_deg_per_s", a.servo.rate_deg_per_s);
  kv(out, "deadband_us", a.servo.deadband_us);
  kv(out, "reversed", a.servo.reversed);
  out << YAML::EndMap;
  out << YAML::Key << "thruster" << YAML::Value << YAML::BeginMap;
  kv(out, "neutral_us", a.thruster.neutral_us);
  kv(out, "min_us", a.thruster.min_us);
  kv(out, "max_us", a.thruster.max_us);
  kv(out, "forward_start_us", a.thruster.forward_start_us);
  kv(out, "reverse_start_us", a.thruster.reverse_start_us);
  kv(out, "reverse_allowed", a.thruster.reverse_allowed);
  out << YAML::EndMap << YAML::EndMap << YAML::EndMap;

  const DevicesConfig& d = c.devices;
  out << YAML::Key << "devices" << YAML::Value << YAML::BeginMap;
  kv(out, "file", d.file);
  out << YAML::Key << "lidar" << YAML::Value << YAML::BeginMap;
  emit_serial(out, d.lidar);
  kv(out, "scan_mode",
     d.lidar.scan_mode == LidarScanMode::kAuto       ? "auto"
     : d.lidar.scan_mode == LidarScanMode::kStandard ? "standard"
                                                     : "express");
  kv(out, "motor_pwm", d.lidar.motor_pwm);
  kv(out, "motor_rpm", d.lidar.motor_rpm);
  out << YAML::EndMap;
  out << YAML::Key << "imu" << YAML::Value << YAML::BeginMap;
  emit_serial(out, d.imu);
  kv(out, "output", d.imu.output == ImuOutput::kAscii ? "ascii" : "binary");
  kv(out, "rate_hz", d.imu.rate_hz);
  kv(out, "declination_deg", d.imu.declination_deg);
  out << YAML::EndMap;
  out << YAML::Key << "gnss" << YAML::Value << YAML::BeginMap;
  emit_serial(out, d.gnss);
  kv(out, "receiver", d.gnss.receiver == GnssReceiver::kF9 ? "f9" : "m8");
  kv(out, "port", d.gnss.port == GnssPort::kUsb ? "usb" : "uart1");
  kv(out, "rate_hz", d.gnss.rate_hz);
  kv(out, "nmea_output", d.gnss.nmea_output);
  kv(out, "rtcm_input", d.gnss.rtcm_input);
  out << YAML::EndMap;
  out << YAML::Key << "arduino" << YAML::Value << YAML::BeginMap;
  emit_serial(out, d.arduino);
  kv(out, "failsafe_ms", d.arduino.failsafe_ms);
  out << YAML::EndMap;
  out << YAML::Key << "camera" << YAML::Value << YAML::BeginMap;
  kv(out, "enabled", d.camera.enabled);
  kv(out, "source", d.camera.source);
  kv(out, "loop", d.camera.loop);
  kv(out, "width_px", d.camera.width_px);
  kv(out, "height_px", d.camera.height_px);
  kv(out, "fps", d.camera.fps);
  kv(out, "hfov_deg", d.camera.hfov_deg);
  kv(out, "auto_exposure", d.camera.auto_exposure);
  kv(out, "exposure", d.camera.exposure);
  kv(out, "saturation", d.camera.saturation);
  kv(out, "contrast", d.camera.contrast);
  kv(out, "brightness", d.camera.brightness);
  kv(out, "timeout_ms", d.camera.timeout_ms);
  out << YAML::EndMap;
  out << YAML::Key << "live" << YAML::Value << YAML::BeginMap;
  kv(out, "control_socket", d.live.control_socket);
  kv(out, "http_enabled", d.live.http_enabled);
  kv(out, "http_address", d.live.http_address);
  kv(out, "http_port", d.live.http_port);
  kv(out, "viz_rate_hz", d.live.viz_rate_hz);
  // Never the token itself: this text goes into every recording.
  kv(out, "token", d.live.token.empty() ? "" : "(set)");
  out << YAML::EndMap << YAML::EndMap;

  const MissionConfig& m = c.mission;
  out << YAML::Key << "mission" << YAML::Value << YAML::BeginMap;
  kv(out, "file", m.file);
  kv(out, "name", m.name);
  kv(out, "tick_rate_hz", m.tick_rate_hz);
  out << YAML::Key << "origin" << YAML::Value << YAML::Flow << YAML::BeginMap;
  kv(out, "lat_deg", m.origin.lat_deg);
  kv(out, "lon_deg", m.origin.lon_deg);
  kv(out, "height_m", m.origin.height_m);
  out << YAML::EndMap;
  out << YAML::Key << "start" << YAML::Value << YAML::BeginMap;
  kv(out, "mode",
     m.start_mode == StartMode::kImmediate       ? "immediate"
     : m.start_mode == StartMode::kArduinoSwitch ? "arduino_switch"
                                                 : "control");
  kv(out, "calibrate_gps", m.calibrate_gps_at_start);
  kv(out, "require_arduino", m.require_arduino);
  out << YAML::EndMap;
  out << YAML::Key << "stale_after_ms" << YAML::Value << YAML::Flow << YAML::BeginMap;
  kv(out, "lidar", m.lidar_stale_ms);
  kv(out, "imu", m.imu_stale_ms);
  kv(out, "gnss", m.gnss_stale_ms);
  kv(out, "arduino", m.arduino_stale_ms);
  out << YAML::EndMap;
  emit_engines(out, m);
  out << YAML::Key << "tasks" << YAML::Value << YAML::BeginSeq;
  for (const TaskConfig& t : m.tasks) {
    out << YAML::BeginMap;
    kv(out, "type", std::string(task_type_name(t.type)));
    kv(out, "name", t.name);
    kv(out, "time_limit_s", t.time_limit_s);
    kv(out, "on_timeout", t.on_timeout == TimeoutOutcome::kNextTask ? "next_task" : "finish");
    if (t.type == TaskType::kDocking) {
      kv(out, "style", t.docking_style == DockingStyle::kKaboat2022 ? "kaboat2022" : "course3");
      kv(out, "dock_heading_deg", t.dock_heading_deg);
    }
    if (!t.slips.empty()) {
      out << YAML::Key << "slips" << YAML::Value << YAML::BeginSeq;
      for (const auto& w : t.slips) {
        out << YAML::Flow << YAML::BeginMap;
        kv(out, "lat_deg", w.lat_deg);
        kv(out, "lon_deg", w.lon_deg);
        kv(out, "height_m", w.height_m);
        out << YAML::EndMap;
      }
      out << YAML::EndSeq;
    }
    if (!t.waypoints.empty()) {
      out << YAML::Key << "waypoints" << YAML::Value << YAML::BeginSeq;
      for (const auto& w : t.waypoints) {
        out << YAML::Flow << YAML::BeginMap;
        kv(out, "lat_deg", w.lat_deg);
        kv(out, "lon_deg", w.lon_deg);
        kv(out, "height_m", w.height_m);
        out << YAML::EndMap;
      }
      out << YAML::EndSeq;
    }
    if (t.target_colour != msg::Colour::kUnknown) {
      kv(out, "target_colour", std::string(colour_name(t.target_colour)));
    }
    if (t.target_shape != msg::Shape::kUnknown) {
      kv(out, "target_shape", std::string(shape_name(t.target_shape)));
    }
    out << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace coxswain::config
