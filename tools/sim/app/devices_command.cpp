// SPDX-License-Identifier: Apache-2.0
// `coxswain-sim devices`: the main job's simulated run (sim/devices_mode). Ctrl-C (or SIGTERM)
// ends the run in order: the daemon is stopped with SIGTERM and waited for, the ptys and their
// links are removed, and the score so far is printed.
#include <signal.h>

#include <atomic>
#include <cstdio>
#include <ctime>
#include <iomanip>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "sim/devices_mode/devices_mode.hpp"

namespace coxswain::sim::app {
namespace {

std::atomic<bool> g_interrupted{false};  // lock-free: safe to store from a signal handler

extern "C" void on_stop_signal(int /*sig*/) { g_interrupted.store(true); }

std::string default_run_dir() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  localtime_r(&now, &tm);
  char name[64];
  (void)std::strftime(name, sizeof name, "runs/sim-%Y%m%d-%H%M%S", &tm);
  return name;
}

void print_outcome(const devices_mode::DevicesOutcome& o, const std::string& run_dir) {
  const auto& sc = o.score;
  std::cout << "run ended: " << devices_mode::end_reason_name(o.end) << " after " << std::fixed
            << std::setprecision(1) << o.elapsed_s << " s (daemon exit status "
            << o.daemon_exit_status << ")\n";
  std::cout << "daemon: ";
  if (o.daemon.total_ticks) {
    std::cout << *o.daemon.total_ticks << " ticks, " << o.daemon.total_overruns.value_or(0)
              << " overruns";
  } else {
    std::cout << o.daemon.window_overruns << " tick overruns (periodic windows)";
  }
  std::cout << "; tick p99 worst " << std::setprecision(3) << o.daemon.worst_tick_p99_ms
            << " ms, max " << o.daemon.worst_tick_max_ms << " ms\n";
  std::cout << "device rates (daemon health):";
  for (const auto& [name, hz] : o.daemon.device_rate_hz) {
    std::cout << ' ' << name << '=' << std::setprecision(1) << hz << "Hz";
  }
  std::cout << "\nworld: " << o.world_steps << " steps, " << o.world_late_steps << " late (max "
            << o.world_max_lateness_ms << " ms), " << o.frames_written << " camera frames, "
            << o.lidar_revolutions_fed << " lidar revolutions\n";
  std::cout << "score: " << sc.course << " (" << scoring::rules_name(sc.rules)
            << "): " << (sc.completed ? "completed" : "not completed") << ", elapsed "
            << sc.elapsed_s << " s, collisions " << sc.collisions << ", penalty " << sc.penalty_s
            << " s, waypoints " << sc.waypoints.size() << ", circled "
            << (sc.circled ? "yes" : "no") << ", recognised " << (sc.recognised ? "yes" : "no")
            << ", docked " << (sc.docked ? "yes" : "no") << ", bonus " << sc.bonus_points
            << ", score " << sc.score_s << " s\n";
  if (!o.faults.empty()) {
    std::size_t recovered = 0;
    for (const auto& f : o.faults) recovered += devices_mode::fault_recovered(f) ? 1U : 0U;
    std::cout << "faults: " << recovered << " of " << o.faults.size() << " held and recovered\n";
    for (const auto& f : o.faults) {
      std::cout << "  fault " << devices_mode::fault_summary_line(f) << "\n";
    }
  }
  std::cout << "result: " << run_dir << "/result.json, " << run_dir << "/track.svg\n";
}

}  // namespace

void add_devices_command(CLI::App& app, int& exit_code) {
  auto* cmd = app.add_subcommand(
      "devices",
      "run the unmodified coxswain daemon against the device emulators (ptys, camera frames) "
      "with the world in real time, and score it");
  static devices_mode::DevicesModeOptions options;
  static std::string course;
  static std::string mission;
  static std::string boat;
  static std::string sensors;
  static std::string run_dir;
  static std::string daemon;
  static bool quiet = false;
  cmd->add_option("--course", course, "course file")->required()->check(CLI::ExistingFile);
  cmd->add_option("--mission", mission,
                  "mission file (default: <config>/missions/<course name>.yaml)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--boat", boat, "boat.yaml (default: <config>/boat.yaml)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--sensors", sensors, "simulated sensors (default: <config>/sim/sensors.yaml)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--seed", options.seed, "disturbance and sensor noise seed");
  cmd->add_option("--run-dir", run_dir, "folder for ptys, frames, logs and results")
      ->capture_default_str();
  cmd->add_option("--daemon", daemon, "the coxswain binary (default: this build's)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--time-limit", options.time_limit_s,
                  "seconds before the run is stopped (default: the course's limits + 60 s)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_flag("--quiet", quiet, "do not echo the daemon's log");
  static bool no_progress = false;
  cmd->add_flag("--no-progress", no_progress,
                "no progress line (time, mission state, score so far) every second");
  static std::vector<std::string> faults;
  cmd->add_option("--fault", faults,
                  "fault on a serial device at T s of the run, DURATION s long: "
                  "DEVICE:KIND@T[+DURATION], DEVICE lidar|imu|gnss|arduino, KIND "
                  "unplug|reset|garbage|silence|baud (repeatable; e.g. gnss:unplug@40+3)")
      ->take_all();
  cmd->add_flag("--run-past-finish", options.run_past_finish,
                "keep the world, devices and daemon running after the mission finished, until "
                "--time-limit (faults go on)");
  static int live_port = -1;
  cmd->add_option("--live-port", live_port,
                  "the daemon's live HTTP port (0: any free port, written to the daemon's "
                  "<run dir>/live.port)")
      ->check(CLI::Range(0, 65535));
  cmd->callback([&exit_code] {
    options.faults.clear();
    try {
      for (const std::string& f : faults)
        options.faults.push_back(devices_mode::parse_fault_spec(f));
    } catch (const std::invalid_argument& e) {
      std::cerr << "coxswain-sim devices: " << e.what() << "\n";
      exit_code = 2;
      return;
    }
    if (live_port >= 0) options.live_http_port = live_port;
    options.course_file = course;
    options.mission_file = mission;
    options.boat_file = boat;
    options.sensors_file = sensors;
    options.run_dir = run_dir.empty() ? default_run_dir() : run_dir;
    options.daemon_path = daemon;
    options.echo_daemon_log = !quiet;
    if (!no_progress) {
      // Flushed line by line so a pipe (tee, a CI log) sees each second as it happens.
      options.on_progress = [](const devices_mode::DevicesProgress& p) {
        std::cout << "progress: " << devices_mode::progress_line(p) << std::endl;
      };
    }
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
    try {
      devices_mode::DevicesMode mode(options);
      std::cout << "devices mode: run directory " << options.run_dir.string() << std::endl;
      const devices_mode::DevicesOutcome o = mode.run(&g_interrupted);
      print_outcome(o, options.run_dir.string());
      std::cout << std::flush;
      exit_code = o.end == devices_mode::EndReason::kDaemonExited ? 1 : 0;
    } catch (const std::exception& e) {
      std::cerr << "coxswain-sim devices: " << e.what() << "\n";
      exit_code = 1;
    }
  });
}

}  // namespace coxswain::sim::app
