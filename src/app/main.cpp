// SPDX-License-Identifier: Apache-2.0
// coxswain: the autonomy daemon. `coxswain run` sails; `coxswain check-config FILE...` validates;
// `coxswain decode --device D FILE` prints a raw device capture as JSON lines; `coxswain replay
// RUN.mcap` re-runs the core on a recording; `coxswain report RUN.mcap` writes its HTML report.
// Exit status: 0 success, 1 runtime failure, 2 configuration error.
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "coxswain/app/daemon.hpp"
#include "coxswain/app/decode_capture.hpp"
#include "coxswain/app/logging.hpp"
#include "coxswain/app/run_dir.hpp"
#include "coxswain/config/config.hpp"
#include "coxswain/replay/command.hpp"
#include "coxswain/report/report.hpp"
#include "coxswain/version.hpp"

namespace {

namespace fs = std::filesystem;
using coxswain::config::ConfigErrors;

constexpr int kExitRuntime = 1;
constexpr int kExitConfig = 2;

// The first existing of: --config-dir, $COXSWAIN_CONFIG_DIR, the installed folder, the source tree.
fs::path resolve_config_dir(const std::string& flag) {
  std::vector<fs::path> candidates;
  if (!flag.empty()) return flag;
  if (const char* env = std::getenv("COXSWAIN_CONFIG_DIR"); env != nullptr && env[0] != '\0') {
    return env;
  }
  candidates.emplace_back(COXSWAIN_INSTALL_CONFIG_DIR);
  candidates.emplace_back(COXSWAIN_SOURCE_CONFIG_DIR);
  for (const auto& c : candidates) {
    if (fs::is_directory(c)) return c;
  }
  return COXSWAIN_SOURCE_CONFIG_DIR;
}

// A mission is a path to a YAML file or a name under <config>/missions/.
fs::path resolve_mission(const fs::path& config_dir, const std::string& mission) {
  if (mission.find('/') != std::string::npos || mission.ends_with(".yaml")) return mission;
  return config_dir / "missions" / (mission + ".yaml");
}

int check_config(const std::vector<std::string>& files) {
  int failed = 0;
  for (const std::string& file : files) {
    ConfigErrors errors;
    const auto kind = coxswain::config::detect_config_kind(file, errors);
    const char* kind_name = "unknown";
    switch (kind) {
      case coxswain::config::ConfigKind::kBoat:
        kind_name = "boat";
        (void)coxswain::config::load_boat_config(file, errors);
        break;
      case coxswain::config::ConfigKind::kDevices:
        kind_name = "devices";
        (void)coxswain::config::load_devices_config(file, errors);
        break;
      case coxswain::config::ConfigKind::kMission:
        kind_name = "mission";
        (void)coxswain::config::load_mission_config(file, errors);
        break;
      case coxswain::config::ConfigKind::kCourse:
      case coxswain::config::ConfigKind::kSimSensors:
        kind_name = "simulator";
        errors.add({file, 0, "kind",
                    "is a simulator file: coxswain-sim validates it (`coxswain-sim course check` "
                    "for courses)"});
        break;
      case coxswain::config::ConfigKind::kUnknown:
        break;
    }
    if (errors.empty()) {
      std::cout << file << ": ok (" << kind_name << ")\n";
    } else {
      std::cerr << errors.format();
      ++failed;
    }
  }
  return failed == 0 ? 0 : kExitConfig;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"coxswain: autonomy daemon for small autonomous competition boats"};
  app.set_version_flag("--version", std::string("coxswain ") + coxswain::kVersion + " (git " +
                                        coxswain::kGitHash + ")");
  std::string config_dir_flag;
  std::string boat_file;
  std::string devices_file;
  std::string mission = "kaboat2026";
  std::string log_dir = "runs";
  if (const char* env = std::getenv("COXSWAIN_LOG_DIR"); env != nullptr && env[0] != '\0') {
    log_dir = env;
  }
  std::string log_level = "info";
  bool print_config = false;
  app.add_option("--config-dir", config_dir_flag,
                 "Folder holding boat.yaml, devices.yaml and missions/ (default: installed or "
                 "source config)");
  app.add_option("--boat", boat_file, "Boat file (default: <config-dir>/boat.yaml)");
  app.add_option("--devices", devices_file, "Devices file (default: <config-dir>/devices.yaml)");
  app.add_option("--mission", mission, "Mission name under <config-dir>/missions/, or a path")
      ->capture_default_str();
  app.add_option("--log-dir", log_dir, "Folder for run directories (YYMMDD-HHMMSS-<mission>-NN)")
      ->capture_default_str();
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error, critical or off")
      ->capture_default_str();
  app.add_flag("--print-config", print_config, "Print the effective configuration and exit");

  auto* run = app.add_subcommand("run", "Run the mission (the default when started by systemd)");
  double run_for_s = 0.0;
  run->add_option("--run-for-s", run_for_s, "Stop by itself after this many seconds (0 = never)")
      ->check(CLI::NonNegativeNumber);
  std::string capture_dir;
  run->add_option("--capture-dir", capture_dir,
                  "Also write each serial device's raw received bytes to DIR/<device>.raw "
                  "(lidar, imu, gnss, arduino), for `coxswain decode`");
  bool no_record = false;
  run->add_flag("--no-record", no_record, "Do not write the flight recording (run.mcap)");
  bool stop_when_finished = false;
  run->add_flag("--stop-when-finished", stop_when_finished,
                "End the run once the mission reports finished");

  auto* decode = app.add_subcommand(
      "decode",
      "Print every message of a raw device capture as one JSON object per line, then a "
      "{\"summary\": true, ...} line with the codec's error counters. An RPLIDAR capture must "
      "include the answer descriptors (A5 5A ...), as captures from --capture-dir do");
  std::string decode_device;
  std::string decode_file;
  decode->add_option("--device", decode_device, "Which codec: rplidar, myahrs, ublox or arduino")
      ->required()
      ->check(CLI::IsMember({"rplidar", "myahrs", "ublox", "arduino"}));
  decode->add_option("file", decode_file, "The capture (e.g. DIR/gnss.raw)")->required();

  auto* check = app.add_subcommand("check-config", "Validate config files without running");
  std::vector<std::string> check_files;
  check->add_option("files", check_files, "YAML files to validate")->required();
  auto* replay = app.add_subcommand(
      "replay",
      "Re-run the mission core on a recording and compare every decision (exit 0 "
      "identical, 1 different, 2 unreadable); --config-dir/--mission/--boat/--devices "
      "replay with changed parameters");
  coxswain::replay::ReplayCommand replay_command;
  std::string replay_file;
  replay->add_option("file", replay_file, "The recording (RUN/run.mcap)")->required();
  replay->add_option("--max-diffs", replay_command.max_diffs, "Differences to list")
      ->capture_default_str();
  replay->add_flag("--decode", replay_command.decode, "Re-run the device codecs on the raw bytes");
  auto* report = app.add_subcommand("report", "Write the postmortem report (one HTML file)");
  std::string report_file;
  std::string report_out;
  report->add_option("file", report_file, "The recording (RUN/run.mcap)")->required();
  report->add_option("-o,--output", report_out, "The HTML file (default: the recording's, .html)");
  app.require_subcommand(0, 1);

  CLI11_PARSE(app, argc, argv);

  if (check->parsed()) return check_config(check_files);
  if (decode->parsed()) {
    const auto format = coxswain::app::parse_capture_format(decode_device);
    if (!format) return kExitConfig;  // CLI11 already checked the name
    return coxswain::app::decode_capture_file(*format, decode_file, std::cout, std::cerr) == 0
               ? 0
               : kExitRuntime;
  }

  const auto level = coxswain::app::parse_log_level(log_level);
  if (!level) {
    std::cerr << "--log-level: unknown level '" << log_level << "'\n";
    return kExitConfig;
  }

  const fs::path config_dir = resolve_config_dir(config_dir_flag);
  const std::string boat_path = boat_file.empty() ? (config_dir / "boat.yaml").string() : boat_file;
  const std::string devices_path =
      devices_file.empty() ? (config_dir / "devices.yaml").string() : devices_file;
  const std::string mission_path = resolve_mission(config_dir, mission).string();

  ConfigErrors errors;
  coxswain::config::Configuration config{
      coxswain::config::load_boat_config(boat_path, errors),
      coxswain::config::load_devices_config(devices_path, errors),
      coxswain::config::load_mission_config(mission_path, errors)};
  if (!errors.empty()) {
    std::cerr << errors.format() << errors.size() << " configuration error"
              << (errors.size() == 1 ? "" : "s") << "; nothing was started\n";
    return kExitConfig;
  }
  if (print_config) {
    std::cout << coxswain::config::to_yaml(config);
    return 0;
  }
  const bool config_given = app.count("--config-dir") + app.count("--boat") +
                                app.count("--devices") + app.count("--mission") >
                            0;
  if (replay->parsed()) {
    replay_command.recording = replay_file;
    replay_command.config_override = config_given ? &config : nullptr;
    return coxswain::replay::run_replay_command(replay_command, std::cout, std::cerr);
  }
  if (report->parsed()) {
    return coxswain::report::run_report_command(
        report_file, report_out, config_given ? &config : nullptr, std::cout, std::cerr);
  }
  if (!run->parsed()) {
    std::cout << app.help();
    return 0;
  }

  fs::path run_dir;
  try {
    run_dir = coxswain::app::create_run_dir(log_dir, config.mission.name, std::time(nullptr));
  } catch (const fs::filesystem_error& e) {
    std::cerr << "cannot create a run directory under '" << log_dir << "': " << e.what() << "\n";
    return kExitRuntime;
  }
  coxswain::app::block_stop_signals();  // before the logging thread exists
  coxswain::app::setup_logging(run_dir / "coxswain.log", *level);
  spdlog::info("coxswain {} (git {}) starting", coxswain::kVersion, coxswain::kGitHash);
  int status = kExitRuntime;
  try {
    coxswain::app::RunOptions run_options;
    run_options.run_dir = run_dir;
    run_options.run_for_s = run_for_s;
    run_options.capture_dir = capture_dir;
    run_options.record = !no_record;
    run_options.build_version =
        std::string("coxswain ") + coxswain::kVersion + " (git " + coxswain::kGitHash + ")";
    run_options.stop_when_finished = stop_when_finished;
    status = coxswain::app::run_daemon(config, run_options);
  } catch (const std::exception& e) {
    spdlog::critical("fatal: {}", e.what());
  }
  coxswain::app::shutdown_logging();
  return status;
}
