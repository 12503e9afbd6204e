// SPDX-License-Identifier: Apache-2.0
// The loaders of the three config kinds. Parameters come from their tables (param_tables.cpp)
// through one reader and one emitter; what is written here by hand is the files' structure
// (tasks, waypoints, origin) and the checks that span several keys.
#include "coxswain/config/config.hpp"
#include "coxswain/config/vision_config.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <limits>
#include <sstream>

#include "coxswain/config/input_checks.hpp"
#include "coxswain/config/param_tables.hpp"
#include "coxswain/config/yaml_reader.hpp"
#include "table_io.hpp"

namespace coxswain::config {
namespace {

using detail::emit_table;
using detail::read_table;

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

core::GeoPoint read_geo(MapReader& m) {
  core::GeoPoint p;
  p.lat_deg = m.require<double>("lat_deg", {-90.0, 90.0});
  p.lon_deg = m.require<double>("lon_deg", {-180.0, 180.0});
  p.height_m = m.get("height_m", 0.0, {-1000.0, 10000.0});
  return p;
}

msg::Colour read_colour(MapReader& m, std::string_view key) {
  if (!m.has(key)) return msg::Colour::kUnknown;
  const std::string name = m.get<std::string>(key, std::string{});
  for (const core::ParamChoice& c : colour_choices()) {
    if (name == c.name) return static_cast<msg::Colour>(c.value);
  }
  m.error(key, "must be a colour name (red, green, blue, ...); got '" + name + "'");
  return msg::Colour::kUnknown;
}

msg::Shape read_shape(MapReader& m, std::string_view key) {
  return m.get_enum(key, msg::Shape::kUnknown,
                    {{"unknown", msg::Shape::kUnknown},
                     {"triangle", msg::Shape::kTriangle},
                     {"rectangle", msg::Shape::kRectangle},
                     {"cross", msg::Shape::kCross},
                     {"circle", msg::Shape::kCircle}});
}

// Reports an engine's own validation message (the engines own their cross-key rules).
void check(MapReader& m, const std::optional<std::string>& problem) {
  if (problem) m.error("", *problem);
}

// The checks that span several keys of one section, after its table is read.
void check_section(MapReader&, const MissionConfig&) {}
void check_section(MapReader& m, const NavigationConfig& n) { check(m, n.filter.validate()); }
void check_section(MapReader& m, const guidance::GpsCalibrationParams& p) {
  check(m, p.validate());
}
void check_section(MapReader& m, const guidance::WaypointFollowerParams& p) {
  check(m, p.validate());
}
void check_section(MapReader& m, const control::HeadingPidParams& p) { check(m, p.validate()); }
void check_section(MapReader& m, const control::SpeedScheduleParams& p) { check(m, p.validate()); }
void check_section(MapReader& m, const guidance::AvoidanceParams& p) { check(m, p.validate()); }
void check_section(MapReader& m, const perception::LidarClusterParams& p) {
  check(m, p.validate());
}
void check_section(MapReader& m, const perception::MarkerVoteParams& p) {
  if (p.min_span_ns > p.window_ns) m.error("min_span_s", "must not exceed window_s");
}
void check_section(MapReader&, const Course1Config&) {}
void check_section(MapReader& m, const Course2Config& c) { check(m, c.circling.validate()); }
void check_section(MapReader& m, const guidance::PlanningConfig& p) { check(m, p.validate()); }
void check_section(MapReader& m, const DockingConfig& d) {
  check(m, d.approach.validate());
  check(m, d.slip.validate());
}

// Course 2's colour list: the one list-valued setting of the engine sections.
void read_course2_colours(MapReader& m, Course2Config& c) {
  if (!m.has("colours")) return;
  c.colours.clear();
  const auto list = m.sequence("colours");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string name = list[i].IsScalar() ? list[i].Scalar() : std::string{};
    bool found = false;
    for (const core::ParamChoice& choice : colour_choices()) {
      if (choice.value != 0 && name == choice.name) {
        c.colours.push_back(static_cast<msg::Colour>(choice.value));
        found = true;
      }
    }
    if (!found) m.error("colours", "unknown colour '" + name + "' at index " + std::to_string(i));
  }
  if (c.colours.empty() || c.colours.size() > 8) m.error("colours", "must list 1 to 8 colours");
}

std::vector<core::GeoPoint> read_corners(MapReader& parent, std::string_view key) {
  std::vector<core::GeoPoint> out;
  const auto seq = parent.sequence(key);
  for (std::size_t i = 0; i < seq.size(); ++i) {
    auto e = parent.element(seq[i], i, key);
    if (!e) continue;
    out.push_back(read_geo(*e));
    e->finish();
  }
  return out;
}

// The planning section's geometry: the field boundary and the no-go polygons.
void read_planning_areas(MapReader& m, guidance::PlanningConfig& p) {
  p.boundary = read_corners(m, "boundary");
  const auto no_go = m.sequence("no_go");
  for (std::size_t i = 0; i < no_go.size(); ++i) {
    auto e = m.element(no_go[i], i, "no_go");
    if (!e) continue;
    p.no_go.push_back(read_corners(*e, "corners"));
    e->finish();
  }
}

void read_sections(MapReader& root, MissionConfig& mission) {
  if (auto m = root.map("course_frame")) {
    if (m->has("zero_heading_deg")) {
      mission.navigation.course_zero_deg = m->get("zero_heading_deg", 0.0, {-180.0, 180.0});
    }
    m->finish();
  }
  for_each_mission_section(mission, [&](std::string_view key, auto& section) {
    using S = std::remove_cvref_t<decltype(section)>;
    if (key.empty()) {
      read_table(root, section, param_table<S>());
      return;
    }
    auto m = root.map(key);
    if (!m) return;
    read_table(*m, section, param_table<S>());
    if constexpr (std::is_same_v<S, Course2Config>) read_course2_colours(*m, section);
    if constexpr (std::is_same_v<S, guidance::PlanningConfig>) read_planning_areas(*m, section);
    check_section(*m, section);
    m->finish();
  });
}

}  // namespace

BoatConfig load_boat_config(const std::string& path, ConfigErrors& errors) {
  BoatConfig boat;
  boat.file = path;
  auto opened = open_root(path, "boat", errors);
  if (!opened) return boat;
  MapReader& root = *opened;
  for (const char* required : {"hull", "mounts", "actuators"}) {
    if (!root.has(required)) root.error(required, "is required");
  }
  read_table(root, boat, param_table<BoatConfig>());
  if (boat.hull.bow_overhang_m > boat.hull.length_m) {
    root.error("hull.bow_overhang_m", "must not exceed hull.length_m");
  }
  const ServoConfig& s = boat.actuators.servo;
  if (!(s.min_us < s.center_us && s.center_us < s.max_us)) {
    root.error("actuators.servo.center_us", "must lie strictly between min_us and max_us");
  }
  const ThrusterConfig& th = boat.actuators.thruster;
  if (!(th.min_us <= th.reverse_start_us && th.reverse_start_us <= th.neutral_us &&
        th.neutral_us <= th.forward_start_us && th.forward_start_us < th.max_us)) {
    root.error("actuators.thruster",
               "pulses must be ordered min_us <= reverse_start_us <= neutral_us <= "
               "forward_start_us < max_us");
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
  for_each_devices_section(d, [&](std::string_view key, auto& section) {
    using S = std::remove_cvref_t<decltype(section)>;
    auto m = root.map(key, /*required=*/key != "live");
    if (!m) return;
    read_table(*m, section, param_table<S>());
    // Addresses, paths and URLs are checked here, as far as they can be without opening
    // anything, so that `check-config` finds what would otherwise fail at run time.
    const auto check_value = [&](std::string_view field,
                                 const std::optional<std::string>& problem) {
      if (problem) m->error(field, *problem);
    };
    if constexpr (std::is_base_of_v<SerialDeviceConfig, S>) {
      if (section.enabled && section.path.empty()) {
        m->error("path", "must not be empty when the device is enabled");
      } else if (section.enabled) {
        check_value("path", validate_device_path(section.path));
      }
    }
    if constexpr (std::is_same_v<S, GnssDeviceConfig>) {
      check_value("rtcm_input", validate_rtcm_input(section.rtcm_input));
    }
    if constexpr (std::is_same_v<S, LiveConfig>) {
      check_value("http_address", validate_http_address(section.http_address));
      check_value("control_socket", validate_control_socket(section.control_socket));
      for (const std::string& host : section.allowed_hosts) {
        check_value("allowed_hosts", validate_allowed_host(host));
      }
      for (const std::string& origin : section.allowed_origins) {
        check_value("allowed_origins", validate_allowed_origin(origin));
      }
    }
    if constexpr (std::is_same_v<S, CameraDeviceConfig>) {
      if (section.enabled && section.source.empty()) {
        m->error("source", "must not be empty when enabled");
      }
    }
    m->finish();
  });
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
  if (auto origin = root.map("origin", true)) {
    mission.origin = read_geo(*origin);
    origin->finish();
  }
  read_sections(root, mission);
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
                "kind: boat | devices | mission | vision | course | sensors"});
    return ConfigKind::kUnknown;
  }
  const std::string kind = (*doc)["kind"].Scalar();
  if (kind == "boat") return ConfigKind::kBoat;
  if (kind == "devices") return ConfigKind::kDevices;
  if (kind == "mission") return ConfigKind::kMission;
  if (kind == "vision") return ConfigKind::kVision;
  if (kind == "course") return ConfigKind::kCourse;
  if (kind == "sensors") return ConfigKind::kSimSensors;
  errors.add(
      {path, (*doc)["kind"].Mark().line + 1, "kind",
       "must be one of: boat, devices, mission, vision, course, sensors; got '" + kind + "'"});
  return ConfigKind::kUnknown;
}

namespace {

void emit_geo(YAML::Emitter& out, const core::GeoPoint& p) {
  out << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "lat_deg" << YAML::Value << p.lat_deg;
  out << YAML::Key << "lon_deg" << YAML::Value << p.lon_deg;
  out << YAML::Key << "height_m" << YAML::Value << p.height_m;
  out << YAML::EndMap;
}

template <class T>
void kv(YAML::Emitter& out, const char* key, const T& value) {
  out << YAML::Key << key << YAML::Value << value;
}

// The mission's keys and values, as the mission file holds them (its name, origin, sections
// and tasks), into the open map `out`.
void emit_mission(YAML::Emitter& out, const MissionConfig& m) {
  kv(out, "name", m.name);
  out << YAML::Key << "origin" << YAML::Value;
  emit_geo(out, m.origin);
  if (m.navigation.course_zero_deg) {
    out << YAML::Key << "course_frame" << YAML::Value << YAML::Flow << YAML::BeginMap;
    kv(out, "zero_heading_deg", *m.navigation.course_zero_deg);
    out << YAML::EndMap;
  }
  for_each_mission_section(m, [&](std::string_view key, const auto& section) {
    using S = std::remove_cvref_t<decltype(section)>;
    if (key.empty()) {
      emit_table(out, section, param_table<S>());
      return;
    }
    out << YAML::Key << std::string(key) << YAML::Value << YAML::BeginMap;
    emit_table(out, section, param_table<S>());
    if constexpr (std::is_same_v<S, Course2Config>) {
      out << YAML::Key << "colours" << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (const msg::Colour col : section.colours) out << std::string(msg::colour_name(col));
      out << YAML::EndSeq;
    }
    if constexpr (std::is_same_v<S, guidance::PlanningConfig>) {
      const auto corners = [&out](const std::vector<core::GeoPoint>& points) {
        out << YAML::BeginSeq;
        for (const core::GeoPoint& g : points) emit_geo(out, g);
        out << YAML::EndSeq;
      };
      if (!section.boundary.empty()) {
        out << YAML::Key << "boundary" << YAML::Value;
        corners(section.boundary);
      }
      if (!section.no_go.empty()) {
        out << YAML::Key << "no_go" << YAML::Value << YAML::BeginSeq;
        for (const auto& polygon : section.no_go) {
          out << YAML::BeginMap << YAML::Key << "corners" << YAML::Value;
          corners(polygon);
          out << YAML::EndMap;
        }
        out << YAML::EndSeq;
      }
    }
    out << YAML::EndMap;
  });
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
  out << YAML::EndSeq;
}

// Replay and devices mode rebuild the core from this text: every number must load back bit for
// bit.
void emit_numbers_exactly(YAML::Emitter& out) {
  out.SetDoublePrecision(std::numeric_limits<double>::max_digits10);
  out.SetFloatPrecision(std::numeric_limits<float>::max_digits10);
}

}  // namespace

std::string to_yaml(const Configuration& c) {
  YAML::Emitter out;
  emit_numbers_exactly(out);
  out << YAML::BeginMap;
  out << YAML::Key << "boat" << YAML::Value << YAML::BeginMap;
  kv(out, "file", c.boat.file);
  emit_table(out, c.boat, param_table<BoatConfig>());
  out << YAML::EndMap;

  out << YAML::Key << "devices" << YAML::Value << YAML::BeginMap;
  kv(out, "file", c.devices.file);
  for_each_devices_section(c.devices, [&](std::string_view key, const auto& section) {
    using S = std::remove_cvref_t<decltype(section)>;
    out << YAML::Key << std::string(key) << YAML::Value << YAML::BeginMap;
    emit_table(out, section, param_table<S>());
    out << YAML::EndMap;
  });
  out << YAML::EndMap;

  out << YAML::Key << "mission" << YAML::Value << YAML::BeginMap;
  kv(out, "file", c.mission.file);
  emit_mission(out, c.mission);
  out << YAML::EndMap;

  // The vision file's keys as write_vision gives them (its numbers read back bit for bit).
  std::ostringstream vision_text;
  write_vision(c.vision.params, vision_text);
  out << YAML::Key << "vision" << YAML::Value << YAML::BeginMap;
  kv(out, "file", c.vision.file);
  for (const auto& entry : YAML::Load(vision_text.str())) {
    if (entry.first.Scalar() == "kind") continue;
    out << YAML::Key << entry.first << YAML::Value << entry.second;
  }
  out << YAML::EndMap << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

std::string mission_to_yaml(const MissionConfig& mission) {
  YAML::Emitter out;
  emit_numbers_exactly(out);
  out << YAML::BeginMap;
  kv(out, "kind", "mission");
  emit_mission(out, mission);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

guidance::MagCalibration magnetometer_of(const ImuDeviceConfig& imu) {
  guidance::MagCalibration m;
  m.hard_iron_x_ut = imu.mag_hard_iron_x_ut;
  m.hard_iron_y_ut = imu.mag_hard_iron_y_ut;
  m.soft_iron = {imu.mag_soft_iron_xx, imu.mag_soft_iron_xy, imu.mag_soft_iron_yx,
                 imu.mag_soft_iron_yy};
  return m;
}

}  // namespace coxswain::config
