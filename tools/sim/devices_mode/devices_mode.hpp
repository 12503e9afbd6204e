// SPDX-License-Identifier: Apache-2.0
#pragma once
// Devices mode: the simulated world in real time with every sensor behind its device
// emulator, and the UNMODIFIED coxswain daemon, a child process, talking to them exactly as to
// the boat's hardware:
// - a pseudo-terminal per serial device (sim::pty::EmulatorHost, udev-like symlinks in
//   <run_dir>/dev): the RPLIDAR emulator fed each revolution from LidarSim's raw beams, the
//   u-blox emulator from GnssSim, the myAHRS+ emulator from ImuSim, and the Arduino emulator
//   whose APPLIED outputs drive the boat (so its failsafe is the real one);
// - the camera as a follow directory (<run_dir>/camera) written by FrameDirWriter from CameraSim;
// - a generated devices.yaml naming those, and `coxswain --devices ... --mission ... run`;
// - the dynamics stepped at a fixed step against absolute steady-clock deadlines, the emulators'
//   data sources updated from the truth, the run scored (tools/sim/scoring).
// The run ends when the daemon logs "mission finished", the scorer is done, the time limit
// passes, the daemon dies, or the caller asks (interrupt flag); the daemon is then stopped with
// SIGTERM and waited for, and the ptys and their links are removed with the hosts.
//
// Thread-safety: run() is called from one thread. While it runs, other threads may call
// host(), daemon(), truth() and elapsed_s() (fault injection and observation in tests).
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "coxswain/config/config.hpp"
#include "coxswain/msg/device_health.hpp"
#include "sim/devices_mode/daemon_process.hpp"
#include "sim/devices_mode/faults.hpp"
#include "sim/dynamics/boat_model.hpp"
#include "sim/pty/emulator_host.hpp"
#include "sim/scoring/scorer.hpp"

namespace coxswain::sim::devices_mode {

/// Where a run is, once a second while it runs (DevicesModeOptions::on_progress).
struct DevicesProgress {
  double elapsed_s = 0.0;      // simulated (= wall) time from the start of the world
  std::string state;           // the daemon's last logged mission state ("" before the first)
  scoring::ScoreResult score;  // the judge's view so far (not settled: the run goes on)
};

struct DevicesModeOptions {
  std::filesystem::path course_file;
  std::filesystem::path mission_file;  // empty: <config>/missions/<course name>.yaml
  std::filesystem::path boat_file;     // empty: <config>/boat.yaml
  std::filesystem::path sensors_file;  // empty: <config>/sim/sensors.yaml when present
  std::uint64_t seed = 1;
  std::filesystem::path run_dir;      // required; created
  std::filesystem::path daemon_path;  // empty: this build's coxswain
  double time_limit_s = 0.0;          // 0: the course's region limits summed plus 60 s, or 900
  core::TimeNs dynamics_step_ns = 10 * core::kNsPerMs;
  bool echo_daemon_log = false;  // copy the daemon's log lines to stderr
  bool record = true;            // false: the daemon runs with --no-record
  /// Called from run()'s thread once a second of the world's time (may be empty).
  std::function<void(const DevicesProgress&)> on_progress;
  /// Extra arguments after `run` (e.g. --run-for-s).
  std::vector<std::string> daemon_run_args;
  /// Faults applied to the serial devices at their times of the run (faults.hpp).
  std::vector<FaultSpec> faults;
  /// Keep the world, the devices and the daemon running after the mission finished (or the
  /// course was scored) until the time limit: faults and live traffic go on (the soak).
  bool run_past_finish = false;
  /// The daemon's live HTTP/WebSocket port (live.http_port; 0 = any free port, written to
  /// <daemon run dir>/live.port); empty: the devices file's default.
  std::optional<int> live_http_port;
};

/// The default config folder (the source tree's config/).
std::filesystem::path default_config_dir();
/// This build's daemon.
std::filesystem::path default_daemon_path();

enum class EndReason : std::uint8_t {
  kMissionFinished,
  kScored,
  kTimeLimit,
  kInterrupted,
  kDaemonExited
};
std::string_view end_reason_name(EndReason reason);

struct DevicesOutcome {
  scoring::ScoreResult score;
  EndReason end = EndReason::kTimeLimit;
  double elapsed_s = 0.0;  // simulated (= wall) time from the start of the world
  int daemon_exit_status = 0;
  DaemonReport daemon;  // what the daemon logged (rates, overruns, transitions)
  std::uint64_t world_steps = 0;
  std::uint64_t world_late_steps = 0;  // steps that began more than one step late
  double world_max_lateness_ms = 0.0;
  std::uint64_t frames_written = 0;
  std::uint64_t lidar_revolutions_fed = 0;
  std::vector<FaultRecord> faults;  // each fault asked for, with what the daemon did about it
};

/// One line of progress (no newline): "t 12 s, state transit, waypoints 2, gates 1, docks 0,
/// collisions 0, penalty 0 s".
std::string progress_line(const DevicesProgress& progress);

/// JSON of an outcome (result.json).
std::string outcome_json(const DevicesOutcome& outcome);

class DevicesMode {
 public:
  /// Loads the course, mission, boat and sensor files; throws std::runtime_error naming every
  /// problem. Nothing is started yet.
  explicit DevicesMode(DevicesModeOptions options);
  /// Stops the daemon (if still running) and removes the ptys.
  ~DevicesMode();
  DevicesMode(const DevicesMode&) = delete;
  DevicesMode& operator=(const DevicesMode&) = delete;

  /// Creates the ptys, the frame directory and devices.yaml, starts the daemon, runs the world
  /// in real time until the run ends, stops the daemon, and writes result.json and track.svg in
  /// the run directory. `interrupt` (may be null) ends the run when it becomes true.
  DevicesOutcome run(const std::atomic<bool>* interrupt);

  /// The host of a serial device (unplug/replug, silence...); null before run() started it,
  /// after it ended, or for the camera. The pointer is valid only while run() is running.
  [[nodiscard]] pty::EmulatorHost* host(msg::DeviceId id);
  /// The daemon; null before run() started it.
  [[nodiscard]] DaemonProcess* daemon();
  /// Waits until run() has started the daemon (or `timeout`); the daemon or null.
  DaemonProcess* wait_started(std::chrono::milliseconds timeout);
  /// The boat's truth now.
  [[nodiscard]] dynamics::TruthState truth() const;
  [[nodiscard]] const config::MissionConfig& mission() const;
  [[nodiscard]] const std::filesystem::path& run_dir() const;
  /// Path of the generated devices.yaml.
  [[nodiscard]] std::filesystem::path devices_yaml() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace coxswain::sim::devices_mode
