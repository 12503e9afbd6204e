// SPDX-License-Identifier: Apache-2.0
#include "sim/devices_mode/devices_mode.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <unistd.h>

#include "coxswain/config/config.hpp"
#include "coxswain/core/clock.hpp"
#include "coxswain/live/control_client.hpp"
#include "sim/devices/arduino/emulator.hpp"
#include "sim/devices/camera/frame_writer.hpp"
#include "sim/devices/myahrs/emulator.hpp"
#include "sim/devices/rplidar/emulator.hpp"
#include "sim/devices/ublox/emulator.hpp"
#include "sim/runner/boat_truth.hpp"
#include "sim/runner/mission_run.hpp"
#include "sim/sensors/camera_sim.hpp"
#include "sim/sensors/gnss_sim.hpp"
#include "sim/sensors/imu_sim.hpp"
#include "sim/sensors/lidar_sim.hpp"
#include "sim/sensors/sensor_config.hpp"
#include "sim/world/collision.hpp"
#include "sim/world/course.hpp"

namespace coxswain::sim::devices_mode {
namespace {

namespace fs = std::filesystem;
namespace ard = drivers::arduino;

// The firmware's limits from boat.yaml, as the lockstep runner sets them (the board is flashed
// with the boat's pulse ranges).
ard::LogicConfig logic_config(const config::BoatConfig& boat, std::uint16_t failsafe_ms) {
  ard::LogicConfig c;
  const auto& a = boat.actuators;
  if (a.layout == msg::ActuatorLayout::kServoThruster) {
    c.neutral_us[0] = a.servo.center_us;
    c.min_us[0] = a.servo.min_us;
    c.max_us[0] = a.servo.max_us;
  } else {
    c.neutral_us[0] = a.thruster.neutral_us;
    c.min_us[0] = a.thruster.min_us;
    c.max_us[0] = a.thruster.max_us;
  }
  c.neutral_us[1] = a.thruster.neutral_us;
  c.min_us[1] = a.thruster.min_us;
  c.max_us[1] = a.thruster.max_us;
  c.failsafe_ms = failsafe_ms;
  return c;
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw std::runtime_error(path.string() + ": cannot be written");
}

constexpr std::uint16_t kFailsafeMs = 300;

}  // namespace

fs::path default_config_dir() { return COXSWAIN_SIM_CONFIG_DIR; }
fs::path default_daemon_path() { return COXSWAIN_SIM_DAEMON_PATH; }

std::string_view end_reason_name(EndReason reason) {
  switch (reason) {
    case EndReason::kMissionFinished:
      return "mission finished";
    case EndReason::kScored:
      return "course complete or out of time (scoring)";
    case EndReason::kTimeLimit:
      return "time limit";
    case EndReason::kInterrupted:
      return "interrupted";
    case EndReason::kDaemonExited:
      return "daemon exited";
  }
  return "?";
}

std::string progress_line(const DevicesProgress& p) {
  const auto& sc = p.score;
  std::string line = "t " + std::to_string(static_cast<long long>(std::floor(p.elapsed_s))) +
                     " s, state " + (p.state.empty() ? std::string("(starting)") : p.state) +
                     ", waypoints " + std::to_string(sc.waypoints.size()) + ", gates " +
                     std::to_string(sc.gates.size()) + ", docks " +
                     std::to_string(sc.docks.size()) + ", collisions " +
                     std::to_string(sc.collisions);
  char penalty[32];
  (void)std::snprintf(penalty, sizeof penalty, ", penalty %.1f s", sc.penalty_s);
  line += penalty;
  if (sc.completed) line += ", completed";
  return line;
}

std::string outcome_json(const DevicesOutcome& o) {
  nlohmann::json j;
  j["score"] = scoring::to_json(o.score);
  j["end"] = std::string(end_reason_name(o.end));
  j["failure"] = scoring::failure_reason(o.score, o.end == EndReason::kMissionFinished);
  j["elapsed_s"] = o.elapsed_s;
  j["world"] = {{"steps", o.world_steps},
                {"late_steps", o.world_late_steps},
                {"max_lateness_ms", o.world_max_lateness_ms},
                {"camera_frames", o.frames_written},
                {"lidar_revolutions", o.lidar_revolutions_fed}};
  nlohmann::json d;
  d["exit_status"] = o.daemon_exit_status;
  d["finished"] = o.daemon.finished;
  d["device_state"] = o.daemon.device_state;
  d["device_rate_hz"] = o.daemon.device_rate_hz;
  d["tick_window_overruns"] = o.daemon.window_overruns;
  d["tick_worst_p99_ms"] = o.daemon.worst_tick_p99_ms;
  d["tick_worst_max_ms"] = o.daemon.worst_tick_max_ms;
  if (o.daemon.total_ticks) d["ticks"] = *o.daemon.total_ticks;
  if (o.daemon.total_overruns) d["tick_overruns"] = *o.daemon.total_overruns;
  nlohmann::json tr = nlohmann::json::array();
  for (const auto& t : o.daemon.transitions) {
    tr.push_back({{"from", t.from}, {"to", t.to}, {"reason", t.reason}});
  }
  d["transitions"] = tr;
  j["daemon"] = d;
  nlohmann::json faults = nlohmann::json::array();
  for (const FaultRecord& f : o.faults) {
    nlohmann::json jf;
    jf["spec"] = fault_spec_text(f.spec);
    jf["summary"] = fault_summary_line(f);
    jf["recovered"] = fault_recovered(f);
    jf["sailing_at_start"] = f.sailing_at_start;
    if (f.began_s) jf["began_s"] = *f.began_s;
    if (f.ended_s) jf["ended_s"] = *f.ended_s;
    if (f.held_after_ms) jf["held_after_ms"] = *f.held_after_ms;
    if (f.device_back_s) jf["device_back_after_end_s"] = *f.device_back_s;
    if (f.resumed_after_s) jf["resumed_after_end_s"] = *f.resumed_after_s;
    faults.push_back(jf);
  }
  j["faults"] = faults;
  return j.dump(2) + "\n";
}

struct DevicesMode::Impl {
  DevicesModeOptions options;
  world::Course course;
  config::BoatConfig boat;
  config::MissionConfig mission;
  sensors::SensorConfig sensors;
  double time_limit_s = 900.0;

  // Emulators first: the hosts that drive them are destroyed before them.
  devices::rplidar::Emulator lidar_emu;
  devices::ublox::Emulator gnss_emu;
  devices::myahrs::Emulator imu_emu;
  devices::arduino::Emulator arduino_emu;
  std::unique_ptr<pty::EmulatorHost> hosts[4];
  std::unique_ptr<DaemonProcess> daemon;

  mutable std::mutex mutex;  // truth, started
  std::condition_variable started_cv;
  bool started = false;
  dynamics::TruthState truth{};

  Impl(DevicesModeOptions opts, world::Course c, config::BoatConfig b, config::MissionConfig m,
       sensors::SensorConfig s)
      : options(std::move(opts)),
        course(std::move(c)),
        boat(std::move(b)),
        mission(std::move(m)),
        sensors(std::move(s)),
        lidar_emu(lidar_config()),
        gnss_emu(devices::ublox::EmulatorConfig{}),
        imu_emu(devices::myahrs::EmulatorConfig{}),
        arduino_emu(arduino_config(boat, mission)) {}

  [[nodiscard]] devices::rplidar::EmulatorConfig lidar_config() const {
    return devices::rplidar::EmulatorConfig{.model = devices::rplidar::Model::kA2,
                                            .revolution_hz = sensors.lidar.rate_hz};
  }

  // A USB reset: the device's power-on state (its start-up is sent again, its configuration is
  // lost). Called under the device's host lock. The Arduino's inputs are the world's (RC,
  // switches), not the board's, so they stay.
  void power_cycle(msg::DeviceId id) {
    switch (id) {
      case msg::DeviceId::kLidar:
        lidar_emu = devices::rplidar::Emulator(lidar_config());
        break;
      case msg::DeviceId::kGnss:
        gnss_emu = devices::ublox::Emulator(devices::ublox::EmulatorConfig{});
        break;
      case msg::DeviceId::kImu:
        imu_emu = devices::myahrs::Emulator(devices::myahrs::EmulatorConfig{});
        break;
      case msg::DeviceId::kArduino: {
        const auto inputs = arduino_emu.inputs();
        arduino_emu = devices::arduino::Emulator(arduino_config(boat, mission));
        arduino_emu.set_inputs(inputs);
        break;
      }
      case msg::DeviceId::kCamera:
        break;
    }
  }

  // Applies (`on`) or undoes a fault on its device's host.
  void apply_fault(const FaultSpec& f, bool on) {
    pty::EmulatorHost& host = serial(f.device);
    switch (f.kind) {
      case FaultKind::kUnplug:
        if (on) {
          host.unplug();
        } else {
          host.replug();
        }
        break;
      case FaultKind::kReset:
        if (on) {
          host.unplug();
          host.locked([&] { power_cycle(f.device); });
        } else {
          host.replug();
        }
        break;
      case FaultKind::kGarbage:
        // A flood: random bursts before every chunk and every byte of the device's own output
        // corrupted, so no frame survives.
        host.set_garbage(on ? 1.0 : 0.0, 64);
        host.set_corruption(on ? 1.0 : 0.0);
        break;
      case FaultKind::kSilence:
        host.set_silent(on);
        break;
      case FaultKind::kBaud:
        // Read at the wrong rate, every byte is wrong (the device's bytes keep coming).
        host.set_corruption(on ? 1.0 : 0.0);
        break;
    }
  }

  static devices::arduino::EmulatorConfig arduino_config(const config::BoatConfig& boat,
                                                         const config::MissionConfig& mission) {
    devices::arduino::EmulatorConfig c;
    c.logic = logic_config(boat, kFailsafeMs);
    c.inputs.rc_present = true;
    c.inputs.mode_auto = true;  // the operator hands over to autonomy
    c.inputs.start_switch = false;
    (void)mission;
    return c;
  }

  pty::EmulatorHost& serial(msg::DeviceId id) { return *hosts[static_cast<std::size_t>(id)]; }

  // Absolute: the daemon reads these paths from its devices file, which refuses relative ones.
  fs::path dev_dir() const { return fs::absolute(options.run_dir) / "dev"; }
  // The daemon's control socket, where the simulated operator gives the target and the start
  // of a mission started from the control interface.
  // A Unix socket path holds at most 107 bytes: a deep run directory gets one in the temp folder.
  fs::path control_socket() const {
    fs::path in_run_dir = fs::absolute(options.run_dir) / "control.sock";
    if (in_run_dir.string().size() < 100) return in_run_dir;
    return fs::temp_directory_path() / ("coxswain-sim-" + std::to_string(::getpid()) + ".sock");
  }
  fs::path camera_dir() const { return options.run_dir / "camera"; }
  fs::path devices_yaml() const { return options.run_dir / "devices.yaml"; }
  fs::path mission_yaml() const { return options.run_dir / "mission.yaml"; }

  void write_mission_yaml() const {
    write_text(mission_yaml(),
               "# SPDX-License-Identifier: Apache-2.0\n"
               "# Written by coxswain-sim devices: " +
                   options.mission_file.string() + " fitted to the course.\n" +
                   config::mission_to_yaml(mission));
  }

  void write_devices_yaml() const {
    const auto& cam = sensors.camera;
    std::ostringstream y;
    y << "# SPDX-License-Identifier: Apache-2.0\n"
         "# Written by coxswain-sim devices: every device is an emulator on a pseudo-terminal.\n"
         "kind: devices\n"
      << "lidar: {path: \"" << (dev_dir() / "ttyLiDAR").string()
      << "\", timeout_ms: 200, scan_mode: auto, motor_pwm: 660}\n"
      << "imu: {path: \"" << (dev_dir() / "ttyIMU").string()
      << "\", timeout_ms: 200, output: ascii, rate_hz: 100, declination_deg: "
      << sensors.imu.declination_deg << "}\n"
      << "gnss: {path: \"" << (dev_dir() / "ttyGPS").string()
      << "\", timeout_ms: 1500, receiver: f9, port: usb, rate_hz: " << sensors.gnss.rate_hz << "}\n"
      << "arduino: {path: \"" << (dev_dir() / "ttyARDUINO").string()
      << "\", timeout_ms: 500, failsafe_ms: " << kFailsafeMs << "}\n"
      << "camera: {source: \"follow:" << camera_dir().string() << "\", width_px: " << cam.width_px
      << ", height_px: " << cam.height_px << ", fps: " << cam.rate_hz
      << ", hfov_deg: " << cam.hfov_deg << ", timeout_ms: 1000}\n"
      << "live: {control_socket: \"" << control_socket().string() << "\"";
    if (options.live_http_port) y << ", http_port: " << *options.live_http_port;
    y << "}\n";
    write_text(devices_yaml(), y.str());
  }
};

DevicesMode::DevicesMode(DevicesModeOptions options) {
  if (options.run_dir.empty()) throw std::runtime_error("devices mode: no run directory");
  const fs::path config_dir = default_config_dir();
  if (options.boat_file.empty()) options.boat_file = config_dir / "boat.yaml";
  if (options.daemon_path.empty()) options.daemon_path = default_daemon_path();
  if (options.sensors_file.empty() && fs::exists(config_dir / "sim" / "sensors.yaml")) {
    options.sensors_file = config_dir / "sim" / "sensors.yaml";
  }
  config::ConfigErrors errors;
  world::Course course = world::load_course_file(options.course_file.string(), errors);
  if (!errors.empty()) throw std::runtime_error(errors.format());
  if (options.mission_file.empty()) {
    options.mission_file = config_dir / "missions" / (course.world.name + ".yaml");
  }
  config::BoatConfig boat = config::load_boat_config(options.boat_file.string(), errors);
  // The mission fitted to the course as the lockstep runs fit it (its origin at the course's,
  // waypoints on the course's gates or points, the field's corners as the boundary), so both
  // modes sail the same mission; the daemon reads it from the run folder.
  config::MissionConfig mission = runner::fit_mission_to_course(
      config::load_mission_config(options.mission_file.string(), errors), course.world);
  sensors::SensorConfig sensor_config;
  if (!options.sensors_file.empty()) {
    if (auto s = sensors::load_sensor_config_file(options.sensors_file.string(), errors)) {
      sensor_config = *s;
    }
  }
  if (!errors.empty()) throw std::runtime_error(errors.format());
  if (!fs::is_regular_file(options.daemon_path)) {
    throw std::runtime_error("daemon not found: " + options.daemon_path.string());
  }
  // The sensors sit where boat.yaml says (the daemon converts with the same mounts), and their
  // noise streams follow --seed.
  sensor_config.lidar.mount = boat.mounts.lidar;
  sensor_config.gnss.mount = boat.mounts.gnss;
  sensor_config.imu.mount_yaw_deg = boat.mounts.imu.yaw_deg;
  sensor_config.camera.mount = boat.mounts.camera;
  sensor_config.lidar.seed += options.seed * 1000;
  sensor_config.gnss.seed += options.seed * 1000;
  sensor_config.imu.seed += options.seed * 1000;
  sensor_config.camera.seed += options.seed * 1000;
  // The course's own sensor conditions win over the sensors file.
  sensors::apply_conditions(course.world.conditions, sensor_config);
  if (const auto why = sensor_config.validate()) {
    throw std::runtime_error("sensors: " + *why);
  }
  const double limit = options.time_limit_s;
  impl_ = std::make_unique<Impl>(std::move(options), std::move(course), std::move(boat),
                                 std::move(mission), std::move(sensor_config));
  if (limit > 0.0) {
    impl_->time_limit_s = limit;
  } else {
    double sum = 0.0;
    for (const auto& r : impl_->course.world.regions) sum += r.time_limit_s;
    impl_->time_limit_s = sum > 0.0 ? sum + 60.0 : 900.0;
  }
}

DevicesMode::~DevicesMode() {
  if (impl_ && impl_->daemon) (void)impl_->daemon->stop();
}

pty::EmulatorHost* DevicesMode::host(msg::DeviceId id) {
  const auto i = static_cast<std::size_t>(id);
  if (i >= 4) return nullptr;
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->started ? impl_->hosts[i].get() : nullptr;
}

DaemonProcess* DevicesMode::daemon() {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->started ? impl_->daemon.get() : nullptr;
}

DaemonProcess* DevicesMode::wait_started(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(impl_->mutex);
  impl_->started_cv.wait_for(lock, timeout, [this] { return impl_->started; });
  return impl_->started ? impl_->daemon.get() : nullptr;
}

dynamics::TruthState DevicesMode::truth() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->truth;
}

const config::MissionConfig& DevicesMode::mission() const { return impl_->mission; }
const fs::path& DevicesMode::run_dir() const { return impl_->options.run_dir; }
fs::path DevicesMode::devices_yaml() const { return impl_->devices_yaml(); }

DevicesOutcome DevicesMode::run(const std::atomic<bool>* interrupt) {
  Impl& s = *impl_;
  const core::SteadyClock clock;
  fs::create_directories(s.options.run_dir);
  fs::create_directories(s.dev_dir());

  // The world.
  const world::World& w = s.course.world;
  dynamics::BoatModel model(s.boat, dynamics::make_params(s.boat, s.course.dynamics),
                            s.course.environment, s.options.seed,
                            core::ns_to_sec(s.options.dynamics_step_ns));
  model.reset(w.start);
  scoring::Scorer scorer(w, s.boat.hull);
  const world::CollisionResponse collisions(w, s.boat.hull);
  sensors::LidarSim lidar(s.sensors.lidar, w);
  sensors::GnssSim gnss(s.sensors.gnss, w.origin);
  sensors::ImuSim imu(s.sensors.imu);
  sensors::CameraSim camera(s.sensors.camera, w);
  devices::camera::FrameDirWriter frames(s.camera_dir());
  cv::Mat frame;
  std::vector<float> ranges(static_cast<std::size_t>(s.sensors.lidar.beams_per_revolution()), 0.0F);

  // Prime every data source with the start state, then plug the devices in.
  dynamics::TruthState truth = model.truth();
  sensors::BoatTruth bt = runner::to_boat_truth(truth);
  lidar.reset(0, bt);
  if (gnss.update(0, bt)) s.gnss_emu.set_truth(gnss.fix());
  if (imu.update(0, bt)) s.imu_emu.set_truth(imu.sample());
  const char* links[4] = {"ttyLiDAR", "ttyIMU", "ttyGPS", "ttyARDUINO"};
  devices::DeviceEmulator* emus[4] = {&s.lidar_emu, &s.imu_emu, &s.gnss_emu, &s.arduino_emu};
  for (std::size_t i = 0; i < 4; ++i) {
    pty::EmulatorHost::Options o;
    o.link_path = s.dev_dir() / links[i];
    o.seed = s.options.seed + i;
    s.hosts[i] = std::make_unique<pty::EmulatorHost>(*emus[i], o);
  }
  if (camera.update(0, truth.pose, frame)) (void)frames.write(frame);
  s.write_devices_yaml();
  s.write_mission_yaml();

  std::vector<std::string> argv{s.options.daemon_path.string(),
                                "--boat",
                                s.options.boat_file.string(),
                                "--devices",
                                s.devices_yaml().string(),
                                "--mission",
                                fs::absolute(s.mission_yaml()).string(),
                                "--log-dir",
                                (s.options.run_dir / "daemon").string(),
                                "run"};
  if (!s.options.record) argv.emplace_back("--no-record");
  for (const auto& a : s.options.daemon_run_args) argv.push_back(a);
  {
    auto d = std::make_unique<DaemonProcess>(argv, s.options.run_dir / "daemon.log",
                                             s.options.echo_daemon_log);
    std::lock_guard<std::mutex> lock(s.mutex);
    s.daemon = std::move(d);
    s.truth = truth;
    s.started = true;
  }
  s.started_cv.notify_all();
  DaemonProcess& daemon = *s.daemon;
  const bool switch_start = s.mission.start_mode == config::StartMode::kArduinoSwitch;
  bool switch_on = false;
  std::vector<std::string> operator_commands;  // sent in order through the control socket
  if (s.mission.start_mode == config::StartMode::kControl) {
    if (w.target_colour != msg::Colour::kUnknown && w.target_shape != msg::Shape::kUnknown) {
      operator_commands.push_back("target " + std::string(msg::colour_name(w.target_colour)) + " " +
                                  std::string(msg::shape_name(w.target_shape)));
    }
    operator_commands.emplace_back("start");
  }
  std::size_t operator_sent = 0;

  DevicesOutcome out;
  std::vector<core::NavPose> path{truth.pose};
  const core::TimeNs step_ns = s.options.dynamics_step_ns;
  const core::TimeNs t0 = clock.now_ns();
  core::TimeNs next_trace_ns = 0;
  core::TimeNs next_check_ns = 0;
  core::TimeNs next_progress_ns = core::kNsPerSec;
  const ard::LogicConfig logic = logic_config(s.boat, kFailsafeMs);
  for (const FaultSpec& f : s.options.faults) {
    FaultRecord r;
    r.spec = f;
    out.faults.push_back(r);
  }
  for (;;) {
    // 1. The Arduino's applied outputs drive the boat (no signal in the bootloader = neutral).
    const ard::LogicOutputs outputs =
        s.serial(msg::DeviceId::kArduino).locked([&] { return s.arduino_emu.outputs(); });
    std::array<std::uint16_t, 2> pulses{};
    for (std::size_t c = 0; c < 2; ++c) {
      pulses[c] = outputs.pulse_us[c] == 0 ? logic.neutral_us[c] : outputs.pulse_us[c];
    }
    model.set_pulses(pulses);
    model.step();
    (void)collisions.resolve(model);
    ++out.world_steps;
    const core::TimeNs t = model.time_ns();
    truth = model.truth();
    bt = runner::to_boat_truth(truth);
    // 2. The sensors measure the new state; each emulator serves what its sensor measured.
    const sensors::LidarUpdate lu = lidar.update(t, bt);
    if (lu.raw_ready) {
      std::fill(ranges.begin(), ranges.end(), 0.0F);
      const auto n = static_cast<double>(ranges.size());
      for (const sensors::RawBeam& b : lidar.raw_revolution()) {
        auto i =
            static_cast<std::size_t>(std::lround(static_cast<double>(b.angle_deg) / 360.0 * n));
        if (i >= ranges.size()) i = 0;
        ranges[i] = b.range_m;
      }
      s.serial(msg::DeviceId::kLidar).locked([&] { s.lidar_emu.set_ranges(ranges); });
      ++out.lidar_revolutions_fed;
    }
    if (gnss.update(t, bt)) {
      s.serial(msg::DeviceId::kGnss).locked([&] { s.gnss_emu.set_truth(gnss.fix()); });
    }
    if (imu.update(t, bt)) {
      s.serial(msg::DeviceId::kImu).locked([&] { s.imu_emu.set_truth(imu.sample()); });
    }
    if (camera.update(t, truth.pose, frame) && frames.write(frame)) ++out.frames_written;
    // Faults fall due on the world's time.
    for (FaultRecord& f : out.faults) {
      const double t_s = core::ns_to_sec(t);
      if (!f.began_s && t_s >= f.spec.at_s) {
        const DaemonReport r = daemon.report();
        const std::string state = r.transitions.empty() ? "" : r.transitions.back().to;
        f.sailing_at_start = !r.finished && !state.empty() && !state.starts_with("hold/") &&
                             state != "wait_for_start" && state != "finished";
        f.began_s = t_s;
        f.began_ns = clock.now_ns();
        s.apply_fault(f.spec, true);
      } else if (f.began_s && !f.ended_s && t_s >= f.spec.at_s + f.spec.duration_s) {
        s.apply_fault(f.spec, false);
        f.ended_s = t_s;
        f.ended_ns = clock.now_ns();
      }
    }
    scorer.update(truth, static_cast<msg::LedColour>(outputs.led));
    if (t >= next_trace_ns) {
      next_trace_ns += 100 * core::kNsPerMs;
      path.push_back(truth.pose);
    }
    {
      std::lock_guard<std::mutex> lock(s.mutex);
      s.truth = truth;
    }
    // 3. The end of the run, and the start switch, checked ten times a second.
    if (t >= next_check_ns) {
      next_check_ns += 100 * core::kNsPerMs;
      const DaemonReport r = daemon.report();
      if (s.options.on_progress && t >= next_progress_ns) {
        next_progress_ns += core::kNsPerSec;
        DevicesProgress p;
        p.elapsed_s = core::ns_to_sec(t);
        if (!r.transitions.empty()) p.state = r.transitions.back().to;
        p.score = scorer.result();
        s.options.on_progress(p);
      }
      bool all_running = true;
      for (msg::DeviceId id : kSerialDevices) {
        auto it = r.device_state.find(std::string(msg::device_name(id)));
        all_running = all_running && it != r.device_state.end() && it->second == "running";
      }
      // The operator gives the target drawn for the course and the start through the control
      // socket once every serial device is up (the socket may not be there yet: next check).
      if (all_running && operator_sent < operator_commands.size()) {
        std::string error;
        const auto answer = live::send_control_command(
            s.control_socket(), operator_commands[operator_sent], error, 1.0);
        if (answer && live::answer_ok(*answer)) {
          ++operator_sent;
        } else if (answer) {
          // A refusal is the daemon's answer to an operator: logged, the run goes on unstarted.
          std::cerr << "devices mode: the daemon refused '" << operator_commands[operator_sent]
                    << "': " << *answer << "\n";
          operator_sent = operator_commands.size();
        }
      }
      if (switch_start && !switch_on) {
        // The operator flips the switch once every serial device is up.
        if (all_running) {
          s.serial(msg::DeviceId::kArduino).locked([&] {
            auto in = s.arduino_emu.inputs();
            in.start_switch = true;
            s.arduino_emu.set_inputs(in);
          });
          switch_on = true;
        }
      }
      if (interrupt != nullptr && interrupt->load()) {
        out.end = EndReason::kInterrupted;
        break;
      }
      if (r.finished && !s.options.run_past_finish) {
        out.end = EndReason::kMissionFinished;
        break;
      }
      if (daemon.output_closed()) {
        out.end = EndReason::kDaemonExited;
        break;
      }
      if (scorer.done() && !s.options.run_past_finish) {
        out.end = EndReason::kScored;
        break;
      }
      if (core::ns_to_sec(t) >= s.time_limit_s) {
        out.end = EndReason::kTimeLimit;
        break;
      }
    }
    // 4. Real time: the next step starts at its absolute deadline.
    const core::TimeNs deadline = t0 + t;
    const core::TimeNs now = clock.now_ns();
    if (now - deadline > step_ns) {
      ++out.world_late_steps;
      out.world_max_lateness_ms =
          std::max(out.world_max_lateness_ms, static_cast<double>(now - deadline) * 1e-6);
    }
    if (now < deadline) std::this_thread::sleep_for(std::chrono::nanoseconds(deadline - now));
  }
  out.elapsed_s = core::ns_to_sec(model.time_ns());
  path.push_back(truth.pose);
  // The daemon is stopped while the devices still run, so it commands neutral and closes its
  // ports in order; then the hosts unplug (links removed) and the frames are cleared.
  out.daemon_exit_status = daemon.stop();
  out.daemon = daemon.report();
  {
    // Each fault owns the log lines from its start to the start of the next fault (any device).
    const std::vector<LogLine> lines = daemon.lines();
    for (FaultRecord& f : out.faults) {
      core::TimeNs until_ns = kNoLaterFault;
      for (const FaultRecord& g : out.faults) {
        if (g.began_s && g.began_ns > f.began_ns) until_ns = std::min(until_ns, g.began_ns);
      }
      observe_fault(lines, f, until_ns);
    }
  }
  {
    std::lock_guard<std::mutex> lock(s.mutex);
    for (auto& h : s.hosts) h.reset();
    s.started = false;
  }
  frames.remove_all();
  scorer.finish(out.elapsed_s);  // the daemon stopped sailing: settle the score now
  out.score = scorer.result();
  write_text(s.options.run_dir / "result.json", outcome_json(out));
  write_text(s.options.run_dir / "track.svg",
             scoring::trajectory_svg(w, s.boat.hull, path, &out.score));
  return out;
}

}  // namespace coxswain::sim::devices_mode
