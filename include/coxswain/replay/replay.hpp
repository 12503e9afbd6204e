// SPDX-License-Identifier: Apache-2.0
#pragma once
// `coxswain replay RUN.mcap`: re-runs the mission core on a flight recording's inputs in virtual
// time and compares each decision with the recorded one. Every /tick message holds the Snapshot
// the core saw (the lidar points travel in /lidar under the scan's store sequence) and what the
// core decided (command, state path); replay rebuilds each Snapshot, steps a fresh MissionCore
// built from the recorded effective configuration (or a changed one), and reports every field
// that differs bit for bit, with the tick index and time. The visualization the tick recorded
// (/viz/scene, /tf: pose, target, danger sector, obstacles) is rebuilt the way the daemon builds
// it (app::fill_tick_viz, record::foxglove) and compared byte for byte. Parameter sets the
// operator applied live (/params) are applied again before the tick they were first in force
// at, so a recording with a live change replays bit for bit too. Pure apart from reading the
// file. Thread-safety: none; one owner.
#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "coxswain/config/config.hpp"
#include "coxswain/mission/mission_core.hpp"
#include "coxswain/record/layouts.hpp"
#include "coxswain/record/mcap_reader.hpp"
#include "coxswain/record/proto_codec.hpp"

namespace coxswain::replay {

/// A recording loaded for replay: the encoded ticks in file order and the lidar scans by store
/// sequence (decoded on demand, so a long run does not hold thousands of 64 KiB scans).
struct Recording {
  bool ok = false;  // the file was read (possibly truncated) and holds a /tick channel
  std::string error;
  record::McapReadReport file;
  std::filesystem::path path;  // the file (read again for the text of a differing scene)
  std::string config_yaml;     // Metadata "config"/"yaml", empty when absent
  /// How /tick, /lidar and /params are encoded (protobuf; the packed layouts before it).
  record::Encoding encoding = record::Encoding::kProtobuf;
  /// Log time minus the recorder's clock (metadata `log_time_offset_ns`; 0 in recordings whose
  /// log times were the recorder's clock): the viewer stamps of /viz/scene and /tf are tick
  /// times plus this.
  core::TimeNs log_time_offset_ns = 0;
  std::vector<std::vector<std::uint8_t>> ticks;
  std::map<std::uint64_t, std::vector<std::uint8_t>> lidar;
  /// FNV-1a hashes of the recorded visualization (/viz/scene, /tf) by log time (tick time plus
  /// `log_time_offset_ns`).
  std::map<std::uint64_t, std::uint64_t> viz_scene;
  std::map<std::uint64_t, std::uint64_t> viz_pose;
  /// Live parameter sets (/params) in file order.
  std::vector<record::ParameterSetRecord> parameter_sets;
};
[[nodiscard]] Recording load_recording(const std::filesystem::path& mcap);

/// The Configuration of a recording's effective-configuration YAML (config::to_yaml), read back
/// through the ordinary file loaders so every check applies. nullopt with `errors` on failure.
/// Writes the recorded configuration as the files it came from: DIR/boat.yaml, devices.yaml,
/// mission.yaml and (when recorded) vision.yaml, each loadable as given to `coxswain`. Creates
/// DIR; refuses (false, `error`) to overwrite a file already there. `written` lists the files.
bool dump_configuration(const std::string& yaml, const std::filesystem::path& dir,
                        std::vector<std::filesystem::path>& written, std::string& error);

[[nodiscard]] std::optional<config::Configuration> configuration_from_yaml(
    const std::string& yaml, config::ConfigErrors& errors);

/// One recorded field that the replayed core did not reproduce.
struct Difference {
  std::uint64_t tick_index = 0;
  core::TimeNs now_ns = 0;
  /// e.g. "thruster pulse_us (command.pulse_us[1])", "state_path", or the first differing
  /// value of the visualization: "viz.scene entities[0].arrows[0].pose.orientation.z".
  std::string field;
  std::string recorded;
  std::string replayed;
};

/// How one actuator channel's commanded pulse diverged over the whole replay.
struct PulseDivergence {
  std::string name;  // "servo", "thruster", "port thruster", "starboard thruster"
  std::uint64_t ticks_different = 0;
  std::uint32_t largest_difference_us = 0;
  std::uint64_t largest_at_tick = 0;
  core::TimeNs largest_at_ns = 0;
};

/// A state path and the tick it was entered at.
struct PathChange {
  std::uint64_t tick_index = 0;
  core::TimeNs now_ns = 0;
  std::string path;
};

struct ReplayOptions {
  std::size_t max_diffs = 20;  // differences kept in the report (all are counted)
  /// Apply the recorded live parameter sets (/params); false = what the run would have done
  /// without the operator's changes.
  bool apply_parameter_sets = true;
};

/// Applies a recorded parameter set (named values over the parameters in force) to `core`.
/// Empty when applied, else why not (an unknown name, a value the core refuses).
[[nodiscard]] std::string apply_parameter_set(mission::MissionCore& core,
                                              const record::ParameterSetRecord& set);

struct ReplayReport {
  bool ok = false;  // the recording could be replayed (a readable file with ticks and a config)
  std::string error;
  std::uint64_t ticks = 0;
  std::uint64_t ticks_different = 0;      // ticks with at least one differing field
  std::uint64_t fields_different = 0;     // all differing fields
  std::uint64_t lidar_scans_missing = 0;  // ticks whose scan is not in /lidar (dropped)
  std::uint64_t ticks_undecodable = 0;    // /tick messages of an unknown layout
  std::uint64_t viz_compared = 0;         // ticks whose recorded /viz/scene was compared
  std::uint64_t parameter_sets_applied = 0;
  std::uint64_t parameter_sets_refused = 0;    // recorded sets the replayed core refused
  std::vector<std::uint64_t> parameter_ticks;  // the tick each applied set was first in force at
  std::vector<Difference> differences;         // the first max_diffs
  std::array<PulseDivergence, msg::ActuatorCommand::kChannels> pulses{};
  std::optional<std::uint64_t> first_divergence_tick;
  core::TimeNs first_divergence_ns = 0;
  std::vector<PathChange> recorded_paths;  // state path timeline as recorded
  std::vector<PathChange> replayed_paths;  // ... and as replayed
  [[nodiscard]] bool identical() const { return ok && fields_different == 0; }
};

/// Called for every replayed tick with the recorded tick (its snapshot complete, lidar points
/// included) and the replayed output; used by the postmortem report.
using TickCallback =
    std::function<void(const record::TickRecordData& tick, const mission::CoreOutput& out)>;

/// Replays `recording` through a MissionCore built from `config`. Never throws for a bad
/// recording (report.ok = false with report.error); an invalid `config` throws
/// std::invalid_argument like MissionCore.
[[nodiscard]] ReplayReport replay(const Recording& recording, const config::Configuration& config,
                                  const ReplayOptions& options = {},
                                  const TickCallback& on_tick = {});

/// Human-readable report. `summary` adds the divergence summary (for a changed configuration).
[[nodiscard]] std::string format_replay_report(const ReplayReport& report, bool summary);

}  // namespace coxswain::replay
