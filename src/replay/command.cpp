// SPDX-License-Identifier: Apache-2.0
#include "coxswain/replay/command.hpp"

#include <stdexcept>
#include <string>
#include <vector>

#include "coxswain/replay/decode_replay.hpp"
#include "coxswain/replay/replay.hpp"

namespace coxswain::replay {

int run_replay_command(const ReplayCommand& command, std::ostream& out, std::ostream& err) {
  constexpr int kDifferent = 1;
  constexpr int kUnreadable = 2;
  if (command.decode) {
    const DecodeReplayReport r = decode_replay(command.recording);
    if (!r.ok) {
      err << "replay --decode: " << r.error << "\n";
      return kUnreadable;
    }
    out << format_decode_replay(r);
    return 0;
  }
  const Recording recording = load_recording(command.recording);
  if (!recording.ok) {
    err << "replay: " << recording.error << "\n";
    return kUnreadable;
  }
  if (!command.dump_config_dir.empty()) {
    if (recording.config_yaml.empty()) {
      err << "replay --dump-config: the recording holds no configuration\n";
      return kUnreadable;
    }
    std::vector<std::filesystem::path> written;
    std::string error;
    if (!dump_configuration(recording.config_yaml, command.dump_config_dir, written, error)) {
      err << "replay --dump-config: " << error << "\n";
      return kUnreadable;
    }
    for (const auto& p : written) out << "wrote " << p.string() << "\n";
    const std::string dir = command.dump_config_dir.string();
    out << "what-if: edit them, then\n  coxswain replay --config-dir " << dir << " --mission "
        << (command.dump_config_dir / "mission.yaml").string() << " " << command.recording.string()
        << "\n";
    return 0;
  }
  std::optional<config::Configuration> recorded;
  if (command.config_override == nullptr) {
    config::ConfigErrors errors;
    if (recording.config_yaml.empty()) {
      err << "replay: the recording holds no configuration; give --config-dir/--mission\n";
      return kUnreadable;
    }
    recorded = configuration_from_yaml(recording.config_yaml, errors);
    if (!recorded) {
      err << "replay: the recorded configuration does not load:\n" << errors.format();
      return kUnreadable;
    }
  }
  const config::Configuration& config =
      command.config_override != nullptr ? *command.config_override : *recorded;
  ReplayReport report;
  try {
    report = replay(recording, config, {command.max_diffs, !command.ignore_parameter_sets});
  } catch (const std::invalid_argument& e) {
    err << "replay: invalid configuration: " << e.what() << "\n";
    return kUnreadable;
  }
  if (!report.ok) {
    err << "replay: " << report.error << "\n";
    return kUnreadable;
  }
  if (recording.file.truncated) out << "note: the recording is truncated (crash or still open)\n";
  out << format_replay_report(report, command.config_override != nullptr);
  return report.identical() ? 0 : kDifferent;
}

}  // namespace coxswain::replay
