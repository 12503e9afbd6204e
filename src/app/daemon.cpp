// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/daemon.hpp"

#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <opencv2/core/utility.hpp>
#include <optional>
#include <stdexcept>
#include <thread>

#include "coxswain/app/core_host.hpp"
#include "coxswain/app/device_probe.hpp"
#include "coxswain/app/device_sessions.hpp"
#include "coxswain/app/health_reporter.hpp"
#include "coxswain/app/logging.hpp"
#include "coxswain/app/raw_capture_sink.hpp"
#include "coxswain/app/serial_drivers.hpp"
#include "coxswain/app/systemd_notify.hpp"
#include "coxswain/app/tick_loop.hpp"
#include "coxswain/config/input_checks.hpp"
#include "coxswain/core/clock.hpp"
#include "coxswain/core/latest_store.hpp"
#include "coxswain/drivers/camera/camera_driver.hpp"
#include "coxswain/drivers/camera/viewer_images.hpp"
#include "coxswain/drivers/ublox/rtcm_queue.hpp"
#include "coxswain/drivers/ublox/rtcm_source.hpp"
#include "coxswain/drivers/ublox/session.hpp"
#include "coxswain/host/step_record.hpp"
#include "coxswain/live/live_server.hpp"
#include "coxswain/mission/mission_core.hpp"
#include "coxswain/record/recorder.hpp"

namespace coxswain::app {
namespace {

// Real-time priority for the tick thread where permitted: the systemd unit sets
// COXSWAIN_TICK_RT_PRIORITY (with LimitRTPRIO) and this thread asks for SCHED_FIFO at it, after
// every other thread has started so none inherits it. Refused or unset: normal priority.
void request_tick_priority() {
  const char* env = std::getenv("COXSWAIN_TICK_RT_PRIORITY");
  if (env == nullptr || *env == '\0') return;
  char* end = nullptr;
  const long priority = std::strtol(env, &end, 10);
  if (*end != '\0' || priority < 1 || priority > 99) {
    spdlog::warn("COXSWAIN_TICK_RT_PRIORITY='{}' is not 1..99: the tick runs at normal priority",
                 env);
    return;
  }
  sched_param param{};
  param.sched_priority = static_cast<int>(priority);
  const int rc = ::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &param);
  if (rc == 0) {
    spdlog::info("tick: real-time priority SCHED_FIFO {}", priority);
  } else {
    spdlog::warn("tick: real-time priority {} refused ({}): normal priority", priority,
                 std::strerror(rc));
  }
}

constexpr core::TimeNs kProbePeriodNs = core::kNsPerSec;
constexpr core::TimeNs kCountersPeriodNs = 10 * core::kNsPerSec;

msg::ActuatorCommand neutral_command(const config::BoatConfig& boat, core::TimeNs now_ns) {
  msg::ActuatorCommand cmd;
  cmd.stamp_ns = now_ns;
  cmd.active = false;
  if (boat.actuators.layout == msg::ActuatorLayout::kServoThruster) {
    cmd.pulse_us = {boat.actuators.servo.center_us, boat.actuators.thruster.neutral_us};
  } else {
    cmd.pulse_us = {boat.actuators.thruster.neutral_us, boat.actuators.thruster.neutral_us};
  }
  return cmd;
}

// Waits for SIGINT/SIGTERM on its own thread (the signals are blocked everywhere else), so the
// stop request is handled in ordinary code rather than in a signal handler.
class SignalWaiter {
 public:
  explicit SignalWaiter(TickLoop& loop) : loop_(loop) {
    thread_ = std::thread([this] { wait(); });
  }
  ~SignalWaiter() {
    done_.store(true);
    thread_.join();
  }
  SignalWaiter(const SignalWaiter&) = delete;
  SignalWaiter& operator=(const SignalWaiter&) = delete;
  [[nodiscard]] int signal_number() const { return signal_.load(); }

 private:
  void wait() {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    const timespec poll{0, 100'000'000};
    while (!done_.load()) {
      const int sig = sigtimedwait(&set, nullptr, &poll);
      if (sig > 0) {
        signal_.store(sig);
        loop_.request_stop();
        return;
      }
    }
  }
  TickLoop& loop_;
  std::atomic<bool> done_{false};
  std::atomic<int> signal_{0};
  std::thread thread_;
};

// Probes device presence once a second until stopped (see DeviceProbe).
class ProbeThread {
 public:
  ProbeThread(DeviceProbe& probe, const core::Clock& clock) : probe_(probe), clock_(clock) {
    probe_.probe_once(clock_.now_ns());  // the first tick already sees every device's state
    thread_ = std::thread([this] { run(); });
  }
  ~ProbeThread() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    thread_.join();
  }
  ProbeThread(const ProbeThread&) = delete;
  ProbeThread& operator=(const ProbeThread&) = delete;

 private:
  void run() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (
        !wake_.wait_for(lock, std::chrono::nanoseconds(kProbePeriodNs), [this] { return stop_; })) {
      probe_.probe_once(clock_.now_ns());
    }
  }
  DeviceProbe& probe_;
  const core::Clock& clock_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace

void block_stop_signals() {
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
}

int run_daemon(const config::Configuration& config, const RunOptions& options) {
  block_stop_signals();  // idempotent; the caller should already have done it before its threads
  // A file-size limit (systemd LimitFSIZE=, ulimit -f) must cost the recording, not the boat:
  // ignored, SIGXFSZ turns into EFBIG from write(2), which the recorder and the log survive.
  ::signal(SIGXFSZ, SIG_IGN);

  const core::SteadyClock clock;
  const SystemdNotifier notifier;
  auto store = std::make_unique<core::LatestStore>();
  auto snapshot = std::make_unique<core::Snapshot>();
  HealthReporter reporter;
  // A device that cannot be opened is logged with where its path or source is set.
  if (!config.devices.file.empty()) {
    for (const msg::DeviceId id : {msg::DeviceId::kLidar, msg::DeviceId::kImu, msg::DeviceId::kGnss,
                                   msg::DeviceId::kArduino}) {
      reporter.set_origin(id,
                          std::string(msg::device_name(id)) + ".path in " + config.devices.file);
    }
    reporter.set_origin(msg::DeviceId::kCamera, "camera.source in " + config.devices.file);
  }

  // The mission core is built first: a configuration it rejects stops the run before any
  // device is touched.
  auto core = std::make_unique<mission::MissionCore>(config.boat, config.mission,
                                                     config::magnetometer_of(config.devices.imu));
  if (std::string e = core->set_vision(config.vision.params); !e.empty()) {
    throw std::invalid_argument(config.vision.file + ": " + e);
  }
  spdlog::info("vision: {}",
               config.vision.file.empty() ? std::string("built-in defaults") : config.vision.file);
  auto out = std::make_unique<mission::CoreOutput>();
  auto tick_viz = std::make_unique<record::TickViz>();

  std::unique_ptr<RawCaptureSink> capture;
  if (!options.capture_dir.empty()) {
    capture = std::make_unique<RawCaptureSink>(options.capture_dir);
    spdlog::info("capture mode: raw device bytes go to {}/<device>.raw",
                 options.capture_dir.string());
  }
  std::unique_ptr<record::Recorder> recorder;
  std::shared_ptr<spdlog::sinks::sink> recorder_log;
  if (options.record) {
    record::RecorderOptions recorder_options;
    recorder_options.path = options.run_dir / "run.mcap";
    recorder_options.config_yaml = config::to_yaml(config);
    recorder_options.build_version = options.build_version;
    recorder_options.map = host::map_geometry(config.mission);
    recorder = std::make_unique<record::Recorder>(recorder_options, store.get(), clock);
    if (recorder->start()) {
      // The daemon's own log lines (info and above) go to /log through the recorder's queue.
      recorder_log = recorder->log_sink();
      if (!attach_log_sink(recorder_log, spdlog::level::info)) recorder_log.reset();
      spdlog::info("flight recording to {}", recorder_options.path.string());
    } else {
      spdlog::error("flight recorder could not start ({}): sailing without a recording",
                    recorder->stats().error);
      recorder.reset();
    }
  }
  // The control socket, status page and live view: the only writer of operator_input.
  live::LiveOptions live_options;
  live_options.map = host::map_geometry(config.mission);
  live_options.socket_path = config.devices.live.control_socket.empty()
                                 ? options.run_dir / "control.sock"
                                 : std::filesystem::path(config.devices.live.control_socket);
  live_options.http_enabled = config.devices.live.http_enabled;
  live_options.http_address = config.devices.live.http_address;
  live_options.http_port = config.devices.live.http_port;
  live_options.viz_rate_hz = config.devices.live.viz_rate_hz;
  live_options.token = config.devices.live.token;
  live_options.allowed_hosts = config.devices.live.allowed_hosts;
  live_options.allowed_origins = config.devices.live.allowed_origins;
  live_options.initial_target_colour = options.target_colour;
  live_options.initial_target_shape = options.target_shape;
  live_options.mission_file =
      config.mission.file.empty() ? "" : std::filesystem::absolute(config.mission.file).string();
  live_options.vision_file =
      config.vision.file.empty() ? "" : std::filesystem::absolute(config.vision.file).string();
  auto live_server = std::make_unique<live::LiveServer>(live_options, *store, clock);
  auto live_tick = std::make_unique<live::LiveTick>();
  auto live_params = std::make_unique<mission::TunableParameters>();
  std::string live_error;
  bool live_started = live_server->start(live_error);
  if (!live_started && live_options.http_enabled && !live_options.socket_path.empty() &&
      live_error.starts_with("control socket")) {
    // An unusable socket path (too long for a Unix socket, a read-only directory) must not cost
    // the live view and status page, which take start, hold and the target as well.
    spdlog::error("{}: no control socket; live view and status page only", live_error);
    live_options.socket_path.clear();
    live_server = std::make_unique<live::LiveServer>(live_options, *store, clock);
    live_started = live_server->start(live_error);
  }
  if (!live_started && live_options.http_enabled && !live_options.socket_path.empty()) {
    // A busy port (another daemon, a test beside us) must not cost the control socket.
    spdlog::warn("live view disabled ({}); control socket only", live_error);
    live_options.http_enabled = false;
    live_server = std::make_unique<live::LiveServer>(live_options, *store, clock);
    live_started = live_server->start(live_error);
  }
  if (live_started) {
    if (!live_options.socket_path.empty()) {
      spdlog::info("control socket {}", live_options.socket_path.string());
    }
    if (live_server->http_port() != 0) {
      spdlog::info("status page and live view on http://{}:{}/", live_options.http_address,
                   live_server->http_port());
      std::ofstream(options.run_dir / "live.port") << live_server->http_port() << "\n";
    }
    live_server->publish_parameters(core->parameters(), clock.now_ns());
  } else {
    spdlog::error("control interface could not start ({}): none", live_error);
    live_server.reset();
    if (options.target_colour != msg::Colour::kUnknown) {
      msg::OperatorInput target;  // no control thread: this thread is the slot's only writer
      target.stamp_ns = clock.now_ns();
      target.target_colour = options.target_colour;
      target.target_shape = options.target_shape;
      store->operator_input.publish(target, target.stamp_ns);
    }
  }
  RawByteTee raw_tee(recorder.get(), capture.get());
  drivers::RawByteSink* const raw_sink =
      (recorder || capture) ? static_cast<drivers::RawByteSink*>(&raw_tee) : nullptr;

  // RTCM corrections for the GNSS receiver, when configured.
  std::unique_ptr<drivers::ublox::RtcmQueue> rtcm_queue;
  std::unique_ptr<drivers::ublox::RtcmSource> rtcm_source;
  const std::string& rtcm_input = config.devices.gnss.rtcm_input;
  const std::optional<std::string> rtcm_problem = config::validate_rtcm_input(rtcm_input);
  if (config.devices.gnss.enabled && rtcm_problem) {
    // Said once, with where it came from: otherwise RTK corrections are silently missing.
    spdlog::error("devices.gnss.rtcm_input '{}' ({}): {}; no RTK corrections", rtcm_input,
                  config.devices.file, *rtcm_problem);
  } else if (config.devices.gnss.enabled && !rtcm_input.empty() &&
             !rtcm_input.starts_with("tcp://") && !std::filesystem::exists(rtcm_input)) {
    spdlog::error("devices.gnss.rtcm_input '{}' ({}): no such file or pipe; no RTK corrections",
                  rtcm_input, config.devices.file);
  }
  if (config.devices.gnss.enabled && !rtcm_input.empty() && !rtcm_problem) {
    rtcm_queue = std::make_unique<drivers::ublox::RtcmQueue>();
    drivers::ublox::RtcmSourceOptions rtcm_options;
    // Run-time problems (a refused connection, a pipe that vanished) are logged once per reason
    // with where the input is configured, so missing RTK corrections are never silent.
    rtcm_options.on_event = [origin = "gnss.rtcm_input in " + config.devices.file](
                                bool problem, std::string_view what) {
      if (problem) {
        spdlog::warn("rtcm: {} [{}]; no RTK corrections meanwhile", what, origin);
      } else {
        spdlog::info("rtcm: {}", what);
      }
    };
    rtcm_source = std::make_unique<drivers::ublox::RtcmSource>(config.devices.gnss.rtcm_input,
                                                               *rtcm_queue, rtcm_options);
  }
  SerialDrivers serial_drivers(
      config.devices,
      [&](msg::DeviceId id) {
        auto session = make_device_session(id, config, *store);
        if (auto* gnss = dynamic_cast<drivers::ublox::UbloxSession*>(session.get());
            gnss != nullptr && rtcm_queue) {
          gnss->set_rtcm_queue(rtcm_queue.get());
        }
        return session;
      },
      *store, clock, raw_sink);
  std::unique_ptr<drivers::camera::CameraDriver> camera;
  // The newest frame and its detections, for the viewers' JPEG images.
  auto latest_frame = std::make_unique<drivers::camera::LatestFrame>();
  std::unique_ptr<drivers::camera::ViewerImages> viewer_images;
  if (config.devices.camera.enabled) {
    // The camera's work (capture, detection, the viewers' JPEGs) runs on the camera's own
    // threads, frame by frame: an OpenCV worker pool beside them would only compete with the tick
    // and the device threads for the boat computer's few cores.
    cv::setNumThreads(1);
    const bool images =
        config.devices.camera.image_rate_hz > 0.0 && (recorder != nullptr || live_server);
    // The detector tunables in force are the core's (live-tunable HSV boxes).
    camera = std::make_unique<drivers::camera::CameraDriver>(
        config.devices.camera, config.boat.mounts.camera, core->parameters().vision, store->camera,
        store->health_of(msg::DeviceId::kCamera), clock, images ? latest_frame.get() : nullptr);
    if (images) {
      viewer_images = std::make_unique<drivers::camera::ViewerImages>(
          config.devices.camera, *latest_frame,
          [rec = recorder.get(), live = live_server.get()](
              core::TimeNs stamp_ns, std::span<const std::uint8_t> jpeg,
              const msg::CameraDetections& detections, double scale) {
            if (rec != nullptr) (void)rec->record_image(stamp_ns, jpeg, detections, scale);
            if (live != nullptr) live->publish_image(stamp_ns, jpeg, detections, scale);
          });
    }
  }
  // Devices with a driver publish their own health; the probe watches only the others.
  std::array<bool, msg::kDeviceCount> driven = serial_drivers.driven();
  driven[static_cast<std::size_t>(msg::DeviceId::kCamera)] = true;  // driver or disabled
  DeviceProbe probe(config.devices, *store, driven);

  TickLoop loop(clock, &TickLoop::sleep_until_steady,
                TickLoop::Params{config.mission.tick_rate_hz, kCountersPeriodNs});
  spdlog::info("mission '{}' from {}; tick {:.1f} Hz; run directory {}", config.mission.name,
               config.mission.file, config.mission.tick_rate_hz, options.run_dir.string());

  SignalWaiter signals(loop);
  ProbeThread probe_thread(probe, clock);
  serial_drivers.start();
  if (camera) camera->start();
  if (viewer_images) viewer_images->start();
  if (rtcm_source) rtcm_source->start();
  bool finished_reported = false;
  std::string last_state_path;

  const core::TimeNs start_ns = clock.now_ns();
  const core::TimeNs stop_at_ns =
      options.run_for_s > 0.0 ? start_ns + core::sec_to_ns(options.run_for_s) : INT64_MAX;
  const core::TimeNs watchdog_every_ns = notifier.watchdog_interval_ns() / 2;
  core::TimeNs last_watchdog_ns = core::kNeverNs;
  core::TimeNs next_counters_ns = start_ns + kCountersPeriodNs;

  notifier.ready();
  notifier.status("running: " + config.mission.name);

  request_tick_priority();
  loop.run(
      [&](const TickInfo& tick) {
        store->refresh(*snapshot);  // unchanged slots (the scan, most ticks) not copied again
        if (reporter.report_changes(*snapshot) > 0) {
          notifier.status(config.mission.name + ": " + HealthReporter::summary(*snapshot));
        }
        if (live_server && live_server->take_parameters(*live_params)) {
          // Between two steps: the core never sees a half-applied set. Rare (an operator action).
          const std::string error = core->apply_parameters(*live_params);
          *live_params = core->parameters();
          if (error.empty()) {
            spdlog::info("live: tunable parameters applied at tick {}", tick.index);
            // Recorded with the tick it first steps, so replay applies it at the same point.
            if (recorder && !recorder->record_parameters(tick.index, tick.now_ns,
                                                         host::named_values(*live_params))) {
              spdlog::warn("live: the applied parameter set could not be recorded");
            }
            if (camera) camera->set_vision(live_params->vision);
          } else {
            spdlog::warn("live: parameters refused: {}", error);
          }
          live_server->publish_parameters(*live_params, tick.now_ns);
        }
        core->step(*snapshot, tick.now_ns, *out);
        store->command.publish(out->command, tick.now_ns);
        log_transitions(out->transitions);
        if (recorder || live_server) host::fill_tick_viz(*out, config.boat, *tick_viz);
        if (live_server) {
          live_tick->summary.tick_index = tick.index;
          live_tick->summary.status = out->status;
          live_tick->viz = *tick_viz;
          live_server->publish_tick(*live_tick, tick.now_ns);
        }
        if (recorder) {
          (void)recorder->record_tick({tick.index, tick.now_ns, snapshot.get(), out->command,
                                       out->status.state_path.view(), tick_viz.get()});
        }
        if (out->transitions.count > 0 && out->status.state_path.view() != last_state_path) {
          last_state_path = std::string(out->status.state_path.view());  // rare: on transitions
          notifier.status(config.mission.name + ": " + last_state_path);
        }
        if (out->status.finished && !finished_reported) {
          finished_reported = true;
          spdlog::info("mission finished after {:.1f} s", out->status.mission_elapsed_s);
          if (options.stop_when_finished) return false;
        }
        if (watchdog_every_ns > 0 && (last_watchdog_ns == core::kNeverNs ||
                                      tick.now_ns - last_watchdog_ns >= watchdog_every_ns)) {
          notifier.watchdog();  // fed from the tick: a stuck tick means systemd restarts us
          last_watchdog_ns = tick.now_ns;
        }
        if (tick.now_ns >= next_counters_ns) {
          reporter.report_counters(*snapshot, tick.now_ns);
          next_counters_ns += kCountersPeriodNs;
        }
        // The map update and any replan, now the command is out and the tick is recorded.
        core->finish_tick();
        return tick.now_ns < stop_at_ns;
      },
      [](const TickWindowStats& s) {
        spdlog::info(
            "tick: {} ticks, duration min {:.3f} mean {:.3f} p99 {:.3f} max {:.3f} ms, "
            "max lateness {:.3f} ms, overruns {}, skipped {}",
            s.ticks, static_cast<double>(s.min_ns) * 1e-6, static_cast<double>(s.mean_ns) * 1e-6,
            static_cast<double>(s.p99_ns) * 1e-6, static_cast<double>(s.max_ns) * 1e-6,
            static_cast<double>(s.max_lateness_ns) * 1e-6, s.overruns, s.skipped_ticks);
      });

  notifier.stopping();
  if (live_server) live_server->stop();
  if (serial_drivers.drives(msg::DeviceId::kArduino)) {
    // Give the Arduino driver two of its command periods to send neutral outputs before its
    // port closes (the board's own failsafe would neutralise them too, but later).
    const core::TimeNs now_ns = clock.now_ns();
    store->command.publish(neutral_command(config.boat, now_ns), now_ns);
    std::this_thread::sleep_for(
        std::chrono::nanoseconds(core::sec_to_ns(2.0 / config.boat.actuators.command_rate_hz)));
  }
  if (rtcm_source) rtcm_source->stop();
  if (viewer_images) viewer_images->stop();  // before the recorder and the live view go
  if (camera) camera->stop();
  serial_drivers.stop();  // each returns within milliseconds, whatever its device does
  const core::TimeNs end_ns = clock.now_ns();
  store->command.publish(neutral_command(config.boat, end_ns), end_ns);
  if (capture) capture->stop();  // after the transports: they were its producers
  if (recorder) {
    recorder->stop();
    if (recorder_log) detach_log_sink(recorder_log);
    const record::RecorderStats stats = recorder->stats();
    spdlog::info("flight recording closed{}",
                 stats.failed ? " after a write error: " + stats.error : "");
  }
  const int sig = signals.signal_number();
  spdlog::info("stopping{}: commanded neutral actuators; {} ticks in {:.1f} s, {} overruns",
               sig != 0 ? (sig == SIGINT ? " on SIGINT" : " on SIGTERM") : "", loop.total_ticks(),
               core::ns_to_sec(end_ns - start_ns), loop.total_overruns());
  return 0;
}

}  // namespace coxswain::app
