// SPDX-License-Identifier: Apache-2.0
#include "coxswain/config/config.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>

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
    const auto waypoints = t->sequence("waypoints");
    for (std::size_t w = 0; w < waypoints.size(); ++w) {
      auto wp = t->element(waypoints[w], w, "waypoints");
      if (!wp) continue;
      task.waypoints.push_back(read_geo(*wp));
      wp->finish();
    }
    task.target_colour = read_colour(*t, "target_colour");
    task.target_shape = read_shape(*t, "target_shape");
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
                "kind: boat | devices | mission | course"});
    return ConfigKind::kUnknown;
  }
  const std::string kind = (*doc)["kind"].Scalar();
  if (kind == "boat") return ConfigKind::kBoat;
  if (kind == "devices") return ConfigKind::kDevices;
  if (kind == "mission") return ConfigKind::kMission;
  if (kind == "course") return ConfigKind::kCourse;
  errors.add({path, (*doc)["kind"].Mark().line + 1, "kind",
              "must be one of: boat, devices, mission, course; got '" + kind + "'"});
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

}  // namespace

std::string to_yaml(const Configuration& c) {
  YAML::Emitter out;
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
  out << YAML::EndMap << YAML::EndMap;

  const MissionConfig& m = c.mission;
  out << YAML::Key << "mission" << YAML::Value << YAML::BeginMap;
  kv(out, "file", m.file);
  kv(out, "name", m.name);
  kv(out, "tick_rate_hz", m.tick_rate_hz);
  out << YAML::Key << "origin" << YAML::Value << YAML::Flow << YAML::BeginMap;
  kv(out, "lat_deg", m.origin.lat_deg);
  kv(out, "lon_deg", m.origin.lon_deg);
  out << YAML::EndMap;
  out << YAML::Key << "start" << YAML::Value << YAML::BeginMap;
  kv(out, "mode",
     m.start_mode == StartMode::kImmediate       ? "immediate"
     : m.start_mode == StartMode::kArduinoSwitch ? "arduino_switch"
                                                 : "control");
  kv(out, "calibrate_gps", m.calibrate_gps_at_start);
  out << YAML::EndMap;
  out << YAML::Key << "stale_after_ms" << YAML::Value << YAML::Flow << YAML::BeginMap;
  kv(out, "lidar", m.lidar_stale_ms);
  kv(out, "imu", m.imu_stale_ms);
  kv(out, "gnss", m.gnss_stale_ms);
  kv(out, "arduino", m.arduino_stale_ms);
  out << YAML::EndMap;
  out << YAML::Key << "tasks" << YAML::Value << YAML::BeginSeq;
  for (const TaskConfig& t : m.tasks) {
    out << YAML::BeginMap;
    kv(out, "type", std::string(task_type_name(t.type)));
    kv(out, "name", t.name);
    kv(out, "time_limit_s", t.time_limit_s);
    if (!t.waypoints.empty()) {
      out << YAML::Key << "waypoints" << YAML::Value << YAML::BeginSeq;
      for (const auto& w : t.waypoints) {
        out << YAML::Flow << YAML::BeginMap;
        kv(out, "lat_deg", w.lat_deg);
        kv(out, "lon_deg", w.lon_deg);
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
