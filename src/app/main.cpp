// SPDX-License-Identifier: Apache-2.0
// coxswain: the autonomy daemon. `coxswain run` sails; `coxswain check-config FILE...` validates;
// `coxswain decode --device D FILE` prints a raw device capture as JSON lines; `coxswain replay
// RUN.mcap` re-runs the core on a recording; `coxswain info RUN.mcap` summarises one;
// `coxswain report RUN.mcap` writes its HTML report;
// `coxswain ctl CMD...` sends a command to the running daemon's control socket.
// Exit status: 0 success, 1 runtime failure, 2 configuration error.
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "coxswain/app/calibrate_mag.hpp"
#include "coxswain/app/cli.hpp"
#include "coxswain/app/daemon.hpp"
#include "coxswain/app/decode_capture.hpp"
#include "coxswain/app/logging.hpp"
#include "coxswain/app/run_dir.hpp"
#include "coxswain/app/save_params.hpp"
#include "coxswain/config/config.hpp"
#include "coxswain/config/reference.hpp"
#include "coxswain/config/vision_config.hpp"
#include "coxswain/live/control_client.hpp"
#include "coxswain/live/control_protocol.hpp"
#include "coxswain/replay/command.hpp"
#include "coxswain/replay/info.hpp"
#include "coxswain/report/report.hpp"
#include "coxswain/version.hpp"
#include "vision_commands.hpp"

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
      case coxswain::config::ConfigKind::kVision:
        kind_name = "vision";
        (void)coxswain::config::load_vision_file(file, errors);
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

namespace {

int run_main(int argc, char** argv) {
  CLI::App app{"coxswain: autonomy daemon for small autonomous competition boats"};
  app.set_version_flag("--version", std::string("coxswain ") + coxswain::kVersion + " (git " +
                                        coxswain::kGitHash + ")");
  // Defaults shown in every --help; the options of `coxswain` itself are accepted after the
  // subcommand as well (`coxswain replay --mission new.yaml RUN.mcap`).
  app.option_defaults()->always_capture_default();
  app.fallthrough();
  std::string config_dir_flag;
  std::string boat_file;
  std::string devices_file;
  std::string vision_file;
  std::string mission = "kaboat2026";
  std::string log_dir = "runs";
  if (const char* env = std::getenv("COXSWAIN_LOG_DIR"); env != nullptr && env[0] != '\0') {
    log_dir = env;
  }
  std::string log_level = "info";
  bool print_config = false;
  app.add_option("--config-dir", config_dir_flag,
                 "Folder holding boat.yaml, devices.yaml, vision.yaml and missions/ (default: "
                 "installed or source config)");
  app.add_option("--boat", boat_file, "Boat file (default: <config-dir>/boat.yaml)");
  app.add_option("--devices", devices_file, "Devices file (default: <config-dir>/devices.yaml)");
  app.add_option("--vision", vision_file,
                 "Vision file: the camera detectors' colour model (default: "
                 "<config-dir>/vision.yaml; the built-in defaults when that is absent)");
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

  std::vector<std::string> target_words;
  run->add_option("--target", target_words,
                  "Docking target COLOUR SHAPE (e.g. --target red triangle), as `ctl target`")
      ->expected(2);

  auto* ctl = app.add_subcommand(
      "ctl",
      "Send a command to the running daemon: start, hold, resume, target COLOUR SHAPE, status, "
      "params. Prints the daemon's one-line JSON answer. `save-params VISION_FILE "
      "[MISSION_FILE]` writes the parameters in force as a vision file (and the daemon's mission "
      "file with the live values), each checked by loading it back");
  std::vector<std::string> ctl_words;
  std::string ctl_socket;
  ctl->add_option("--socket", ctl_socket,
                  "Control socket (default: $COXSWAIN_CONTROL_SOCKET, the devices file's "
                  "live.control_socket, else the newest <log-dir>/*/control.sock)");
  ctl->add_option("command", ctl_words, "The command and its arguments")->required();

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
  auto* config_cmd = app.add_subcommand(
      "config",
      "Describe the configuration: every parameter (doc), a kind's JSON Schema, the list");
  config_cmd->require_subcommand(1);
  auto* config_doc = config_cmd->add_subcommand("doc", "Print the parameter reference (Markdown)");
  auto* config_schema = config_cmd->add_subcommand("schema", "Print a config kind's JSON Schema");
  std::string schema_kind;
  config_schema->add_option("kind", schema_kind, "boat, devices, mission or vision")
      ->required()
      ->check(CLI::IsMember({"boat", "devices", "mission", "vision"}));
  auto* config_params =
      config_cmd->add_subcommand("params", "Print every parameter with its bounds as JSON");
  bool params_json = false;
  config_params->add_flag("--json", params_json, "JSON (the only format; kept for tools)");
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
  replay->add_flag("--ignore-parameter-changes", replay_command.ignore_parameter_sets,
                   "Leave out the parameter sets applied live (/params): what the run would have "
                   "done without them");
  bool dump_config = false;
  std::string dump_dir;
  replay->add_flag("--dump-config", dump_config,
                   "Write the recorded boat, devices, mission (and vision) files into DIR instead "
                   "of replaying (`coxswain replay --dump-config RUN.mcap DIR`): edit them, then "
                   "replay with --config-dir DIR --mission DIR/mission.yaml");
  replay->add_option("dir", dump_dir, "With --dump-config: the folder to write the files into");
  replay->callback([&dump_config, &dump_dir] {
    // A usage error like CLI11's own (exit 2 with the hint).
    if (dump_config && dump_dir.empty()) {
      throw CLI::ValidationError("--dump-config", "needs a folder: --dump-config RUN.mcap DIR");
    }
    if (!dump_config && !dump_dir.empty()) {
      throw CLI::ValidationError("dir", "one recording (a folder only with --dump-config)");
    }
  });
  auto* info = app.add_subcommand(
      "info",
      "Summarise a recording: duration, channels with message counts, rates and drops, the "
      "mission's result, the configuration's hash (exit 0, or 2 when unreadable)");
  std::string info_file;
  bool info_as_json = false;
  info->add_option("file", info_file, "The recording (RUN/run.mcap)")->required();
  info->add_flag("--json", info_as_json, "One JSON object instead of text");
  auto* report = app.add_subcommand("report", "Write the postmortem report (one HTML file)");
  std::string report_file;
  std::string report_out;
  report->add_option("file", report_file, "The recording (RUN/run.mcap)")->required();
  report->add_option("-o,--output", report_out, "The HTML file (default: the recording's, .html)");
  int vision_exit = 0;
  const CLI::App* vision = coxswain::app::add_vision_commands(app, vision_exit);
  auto* calibrate = app.add_subcommand("calibrate", "Fit a sensor calibration from a recording");
  auto* calibrate_mag = calibrate->add_subcommand(
      "mag",
      "Magnetometer hard- and soft-iron terms from a recorded slow turn in place, written to "
      "the devices file (--devices, default <config-dir>/devices.yaml)");
  std::string calibrate_file;
  calibrate_mag->add_option("file", calibrate_file, "The recording (RUN/run.mcap)")->required();
  calibrate->require_subcommand(1);
  app.require_subcommand(0, 1);

  if (const auto status =
          coxswain::app::parse_command_line(app, argc, argv, "coxswain", std::cout, std::cerr)) {
    return *status;
  }
  // The daemon blocks its stop signals before it loads anything (and before any thread): a stop
  // asked while it starts is then handled in order once it runs, not by the default action.
  if (run->parsed()) coxswain::app::block_stop_signals();
  if (vision->parsed()) return vision_exit;

  if (check->parsed()) return check_config(check_files);
  if (info->parsed()) {
    const coxswain::replay::RecordingInfo recording = coxswain::replay::recording_info(info_file);
    if (info_as_json) {
      std::cout << coxswain::replay::info_json(recording) << "\n";
    } else if (recording.ok) {
      std::cout << info_file << "\n" << coxswain::replay::format_info(recording);
    } else {
      std::cerr << "info: " << recording.error << "\n";
    }
    return recording.ok ? 0 : kExitConfig;
  }
  if (config_doc->parsed()) {
    std::cout << coxswain::config::parameter_reference_markdown();
    return 0;
  }
  if (config_schema->parsed()) {
    std::cout << coxswain::config::json_schema(schema_kind).value_or("");
    return 0;
  }
  if (config_params->parsed()) {
    std::cout << coxswain::config::parameters_json();
    return 0;
  }
  if (decode->parsed()) {
    const auto format = coxswain::app::parse_capture_format(decode_device);
    if (!format) return kExitConfig;  // CLI11 already checked the name
    return coxswain::app::decode_capture_file(*format, decode_file, std::cout, std::cerr) == 0
               ? 0
               : kExitRuntime;
  }

  if (ctl->parsed()) {
    // `save-params VISION_FILE [MISSION_FILE]` asks for the parameters in force (`params`) and
    // writes them here, where the operator is: the daemon never writes files for the socket.
    const bool save = ctl_words.front() == "save-params";
    if (save && (ctl_words.size() < 2 || ctl_words.size() > 3)) {
      std::cerr << "ctl: usage: save-params VISION_FILE [MISSION_FILE]\n";
      return kExitConfig;
    }
    std::string line;
    if (save) {
      line = "params";
    } else {
      for (const std::string& w : ctl_words) line += (line.empty() ? "" : " ") + w;
    }
    if (std::string error; !coxswain::live::parse_command(line, error)) {
      std::cerr << "ctl: " << error << "\n";
      return kExitConfig;
    }
    fs::path socket = ctl_socket;
    if (const char* env = std::getenv("COXSWAIN_CONTROL_SOCKET");
        socket.empty() && env != nullptr && env[0] != '\0') {
      socket = env;
    }
    if (socket.empty()) {
      ConfigErrors ignored;  // a broken devices file must not stop an operator's hold
      const fs::path dir = resolve_config_dir(config_dir_flag);
      const auto devices = coxswain::config::load_devices_config(
          devices_file.empty() ? (dir / "devices.yaml").string() : devices_file, ignored);
      socket = devices.live.control_socket;
    }
    if (socket.empty()) socket = coxswain::live::newest_run_socket(log_dir);
    if (socket.empty()) {
      std::cerr << "ctl: no control socket found under '" << log_dir
                << "' (is the daemon running? use --socket)\n";
      return kExitRuntime;
    }
    std::string error;
    const auto answer = coxswain::live::send_control_command(socket, line, error);
    if (!answer) {
      std::cerr << "ctl: " << error << "\n";
      return kExitRuntime;
    }
    if (save) {
      const fs::path mission_out = ctl_words.size() == 3 ? fs::path(ctl_words[2]) : fs::path();
      if (const std::string problem =
              coxswain::app::save_params(*answer, ctl_words[1], mission_out);
          !problem.empty()) {
        std::cerr << "ctl: save-params: " << problem << "\n";
        return kExitRuntime;
      }
      std::cout << "saved the vision parameters in force to " << ctl_words[1];
      if (!mission_out.empty()) std::cout << " and the mission's to " << mission_out.string();
      std::cout << "\n";
      return 0;
    }
    std::cout << *answer << "\n";
    return coxswain::live::answer_ok(*answer) ? 0 : kExitRuntime;
  }

  if (calibrate_mag->parsed()) {
    const fs::path dir = resolve_config_dir(config_dir_flag);
    return coxswain::app::calibrate_mag(
        calibrate_file, devices_file.empty() ? (dir / "devices.yaml").string() : devices_file,
        std::cout, std::cerr);
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
  // A config folder without a vision file (one made before it existed) sails on the built-in
  // colour model; a vision file named with --vision must exist.
  const fs::path default_vision = config_dir / "vision.yaml";
  if (!vision_file.empty() || fs::exists(default_vision)) {
    config.vision.file = vision_file.empty() ? default_vision.string() : vision_file;
    if (auto v = coxswain::config::load_vision_file(config.vision.file, errors)) {
      config.vision.params = *v;
    }
  }
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
                                app.count("--devices") + app.count("--mission") +
                                app.count("--vision") >
                            0;
  if (replay->parsed()) {
    replay_command.recording = replay_file;
    replay_command.dump_config_dir = dump_dir;
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

  if (!target_words.empty() &&
      (target_words.size() != 2 || !coxswain::live::parse_colour(target_words[0]) ||
       !coxswain::live::parse_shape(target_words[1]))) {
    std::cerr << "--target: expected COLOUR SHAPE (e.g. red triangle)\n";
    return kExitConfig;
  }
  fs::path run_dir;
  try {
    run_dir = coxswain::app::create_run_dir(log_dir, config.mission.name, std::time(nullptr));
  } catch (const fs::filesystem_error& e) {
    std::cerr << "cannot create a run directory under '" << log_dir << "': " << e.what() << "\n";
    return kExitRuntime;
  }
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
    if (!target_words.empty()) {
      run_options.target_colour = *coxswain::live::parse_colour(target_words[0]);
      run_options.target_shape = *coxswain::live::parse_shape(target_words[1]);
    }
    status = coxswain::app::run_daemon(config, run_options);
  } catch (const std::exception& e) {
    spdlog::critical("fatal: {}", e.what());
  }
  coxswain::app::shutdown_logging();
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  // Whatever escapes (a failed allocation, a library error before the daemon's own handlers):
  // said in one line, a runtime failure, never an abort.
  try {
    return run_main(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "coxswain: fatal: " << e.what() << "\n";
  } catch (...) {
    std::cerr << "coxswain: fatal: unknown exception\n";
  }
  return kExitRuntime;
}
