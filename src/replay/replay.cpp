// SPDX-License-Identifier: Apache-2.0
#include "coxswain/replay/replay.hpp"

#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <span>
#include <sstream>
#include <stdexcept>

#include "coxswain/config/vision_config.hpp"
#include "coxswain/host/step_record.hpp"
#include "coxswain/mission/tunable_parameters.hpp"
#include "coxswain/record/foxglove.hpp"

namespace coxswain::replay {
namespace {

namespace fs = std::filesystem;

// The loaders read files; each section goes through a private temporary file, removed after.
class TempFile {
 public:
  explicit TempFile(const std::string& stem) {
    static std::atomic<unsigned> counter{0};
    path_ =
        fs::temp_directory_path() / ("coxswain-replay-" + std::to_string(::getpid()) + "-" +
                                     std::to_string(counter.fetch_add(1)) + "-" + stem + ".yaml");
  }
  ~TempFile() {
    std::error_code ec;
    fs::remove(path_, ec);
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  [[nodiscard]] const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

bool write_section(const YAML::Node& root, const char* key, const fs::path& path,
                   config::ConfigErrors& errors) {
  const YAML::Node section = root[key];
  if (!section || !section.IsMap()) {
    errors.add({"<recorded config>", 0, key, "missing from the recorded configuration"});
    return false;
  }
  YAML::Node copy = YAML::Clone(section);
  copy.remove("file");  // where the daemon loaded it from: not a key of the file itself
  copy["kind"] = key;
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << copy;
  std::ofstream f(path);
  f << out.c_str() << "\n";
  return static_cast<bool>(f);
}

std::uint64_t fnv1a(std::span<const std::uint8_t> bytes) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const std::uint8_t b : bytes) {
    h ^= b;
    h *= 0x100000001b3ULL;
  }
  return h;
}
std::uint64_t fnv1a(std::string_view text) {
  return fnv1a(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

std::string hex(std::uint64_t h) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "fnv1a:%016llx", static_cast<unsigned long long>(h));
  return buf;
}

std::string command_field(std::size_t i) {
  static constexpr const char* kNames[] = {"command.stamp_ns", "command.pulse_us[0]",
                                           "command.pulse_us[1]", "command.led", "command.active"};
  return kNames[i];
}

/// What each actuator channel drives, for the reader of a difference.
std::array<std::string, msg::ActuatorCommand::kChannels> channel_names(msg::ActuatorLayout l) {
  if (l == msg::ActuatorLayout::kTwinThrusters) return {"port thruster", "starboard thruster"};
  return {"servo", "thruster"};
}

/// The first value that differs between two JSON documents, depth first: its path and both
/// values as text. nullopt when equal.
struct JsonDifference {
  std::string path;
  std::string recorded;
  std::string replayed;
};
std::optional<JsonDifference> first_difference(const nlohmann::json& a, const nlohmann::json& b,
                                               const std::string& path, int depth = 0) {
  // The recorded text comes from a file: a crafted one nests without end, our scenes never
  // deeper than a few levels.
  constexpr int kMaxDepth = 32;
  if (depth > kMaxDepth) return JsonDifference{path, "(nested too deep)", "(not compared)"};
  if (a.type() != b.type() && !(a.is_number() && b.is_number())) {
    return JsonDifference{path, a.dump(), b.dump()};
  }
  if (a.is_object()) {
    for (auto it = a.begin(); it != a.end(); ++it) {
      const std::string at = path.empty() ? it.key() : path + "." + it.key();
      if (!b.contains(it.key())) return JsonDifference{at, it.value().dump(), "(absent)"};
      if (auto d = first_difference(it.value(), b.at(it.key()), at, depth + 1)) return d;
    }
    for (auto it = b.begin(); it != b.end(); ++it) {
      if (!a.contains(it.key())) {
        return JsonDifference{path.empty() ? it.key() : path + "." + it.key(), "(absent)",
                              it.value().dump()};
      }
    }
    return std::nullopt;
  }
  if (a.is_array()) {
    const std::size_t n = std::min(a.size(), b.size());
    for (std::size_t i = 0; i < n; ++i) {
      if (auto d = first_difference(a[i], b[i], path + "[" + std::to_string(i) + "]", depth + 1)) {
        return d;
      }
    }
    if (a.size() != b.size()) {
      return JsonDifference{path + ".length", std::to_string(a.size()), std::to_string(b.size())};
    }
    return std::nullopt;
  }
  if (a != b) return JsonDifference{path, a.dump(), b.dump()};
  return std::nullopt;
}

/// The listed visualization differences carry the replayed JSON until now: read the recorded
/// messages at their log times and say which value differs.
struct PendingViz {
  std::uint64_t log_time_ns = 0;
  std::string replayed_json;
};

void explain_viz_differences(const Recording& recording, std::vector<Difference>& differences,
                             const std::map<std::size_t, PendingViz>& pending) {
  if (pending.empty()) return;
  std::map<std::pair<std::string, std::uint64_t>, std::string> recorded;  // (topic, log time)
  std::set<std::pair<std::string, std::uint64_t>> wanted;
  for (const auto& [index, p] : pending) {
    wanted.insert({differences[index].field == "viz.scene" ? "/viz/scene" : "/tf", p.log_time_ns});
  }
  record::McapReader reader;
  if (reader.open(recording.path)) {
    (void)reader.read([&](const record::McapMessageView& m) {
      const std::pair<std::string, std::uint64_t> key{reader.channels().at(m.channel_id).topic,
                                                      m.log_time_ns};
      if (wanted.contains(key)) recorded[key].assign(m.data.begin(), m.data.end());
    });
  }
  // Left as hashes when the recorded text is gone or the values agree (other bytes differ).
  for (const auto& [index, p] : pending) {
    Difference& d = differences[index];
    const auto it = recorded.find({d.field == "viz.scene" ? "/viz/scene" : "/tf", p.log_time_ns});
    if (it == recorded.end()) continue;
    const nlohmann::json was = nlohmann::json::parse(it->second, nullptr, false);
    const nlohmann::json replayed = nlohmann::json::parse(p.replayed_json, nullptr, false);
    if (was.is_discarded() || replayed.is_discarded()) continue;
    if (const auto j = first_difference(was, replayed, "")) {
      d.field += " " + j->path;
      d.recorded = j->recorded;
      d.replayed = j->replayed;
    }
  }
}

}  // namespace

Recording load_recording(const fs::path& mcap) {
  Recording rec;
  rec.path = mcap;
  record::McapReader reader;
  if (!reader.open(mcap)) {
    rec.error = "cannot read " + mcap.string();
    return rec;
  }
  // Channels are known once their Channel record was read, which precedes their messages.
  std::optional<std::uint16_t> tick_id;
  std::optional<std::uint16_t> lidar_id;
  std::optional<std::uint16_t> scene_id;
  std::optional<std::uint16_t> pose_id;
  std::optional<std::uint16_t> params_id;
  bool encoding_known = false;
  rec.file = reader.read([&](const record::McapMessageView& m) {
    if (!tick_id) tick_id = reader.channel_id("/tick");
    if (tick_id && !encoding_known) {
      // Every message channel of a recording is written in one encoding: the tick's.
      encoding_known =
          record::encoding_of(reader.channels().at(*tick_id).message_encoding, rec.encoding);
    }
    if (!params_id) params_id = reader.channel_id("/params");
    if (params_id && m.channel_id == *params_id) {
      record::ParameterSetRecord set;
      if (record::decode_parameters(rec.encoding, m.data, set)) {
        rec.parameter_sets.push_back(std::move(set));
      }
      return;
    }
    if (!lidar_id) lidar_id = reader.channel_id("/lidar");
    if (!scene_id) scene_id = reader.channel_id("/viz/scene");
    if (!pose_id) pose_id = reader.channel_id("/tf");
    if (scene_id && m.channel_id == *scene_id) {
      rec.viz_scene[m.log_time_ns] = fnv1a(m.data);
    } else if (pose_id && m.channel_id == *pose_id) {
      rec.viz_pose[m.log_time_ns] = fnv1a(m.data);
    } else if (tick_id && m.channel_id == *tick_id) {
      rec.ticks.emplace_back(m.data.begin(), m.data.end());
    } else if (lidar_id && m.channel_id == *lidar_id) {
      std::uint64_t sequence = 0;
      if (record::peek_sequence(rec.encoding, m.data, sequence)) {
        rec.lidar[sequence].assign(m.data.begin(), m.data.end());
      }
    }
  });
  if (!rec.file.header_ok) {
    rec.error = "not an MCAP file: " + mcap.string();
    return rec;
  }
  if (const auto it = rec.file.metadata.find("config"); it != rec.file.metadata.end()) {
    if (const auto y = it->second.find("yaml"); y != it->second.end()) rec.config_yaml = y->second;
  }
  if (const auto it = rec.file.metadata.find("coxswain"); it != rec.file.metadata.end()) {
    if (const auto o = it->second.find("log_time_offset_ns"); o != it->second.end()) {
      rec.log_time_offset_ns = std::strtoll(o->second.c_str(), nullptr, 10);
    }
  }
  if (tick_id && !encoding_known) {
    rec.error = "the /tick channel's message encoding '" +
                reader.channels().at(*tick_id).message_encoding + "' is not one this build reads";
    return rec;
  }
  if (!reader.channel_id("/tick")) {
    rec.error = "the recording has no /tick channel";
    return rec;
  }
  rec.ok = true;
  return rec;
}

namespace {

std::optional<YAML::Node> recorded_root(const std::string& yaml, config::ConfigErrors& errors) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& e) {
    errors.add({"<recorded config>", 0, "", std::string("not YAML: ") + e.what()});
    return std::nullopt;
  }
  if (!root.IsMap()) {
    errors.add({"<recorded config>", 0, "", "not a map"});
    return std::nullopt;
  }
  return root;
}

}  // namespace

bool dump_configuration(const std::string& yaml, const fs::path& dir,
                        std::vector<fs::path>& written, std::string& error) {
  config::ConfigErrors errors;
  const std::optional<YAML::Node> root = recorded_root(yaml, errors);
  if (!root) {
    error = errors.format();
    return false;
  }
  std::vector<const char*> sections{"boat", "devices", "mission"};
  if ((*root)["vision"]) sections.push_back("vision");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    error = "cannot create " + dir.string() + ": " + ec.message();
    return false;
  }
  for (const char* key : sections) {
    if (const fs::path p = dir / (std::string(key) + ".yaml"); fs::exists(p)) {
      error = p.string() + " exists; dump into an empty folder (nothing was written)";
      return false;
    }
  }
  for (const char* key : sections) {
    const fs::path p = dir / (std::string(key) + ".yaml");
    if (!write_section(*root, key, p, errors)) {
      error = errors.empty() ? "cannot write " + p.string() : errors.format();
      return false;
    }
    written.push_back(p);
  }
  return true;
}

std::optional<config::Configuration> configuration_from_yaml(const std::string& yaml,
                                                             config::ConfigErrors& errors) {
  const std::optional<YAML::Node> parsed = recorded_root(yaml, errors);
  if (!parsed) return std::nullopt;
  const YAML::Node& root = *parsed;
  TempFile boat("boat");
  TempFile devices("devices");
  TempFile mission("mission");
  if (!write_section(root, "boat", boat.path(), errors) ||
      !write_section(root, "devices", devices.path(), errors) ||
      !write_section(root, "mission", mission.path(), errors)) {
    return std::nullopt;
  }
  config::Configuration c{config::load_boat_config(boat.path().string(), errors),
                          config::load_devices_config(devices.path().string(), errors),
                          config::load_mission_config(mission.path().string(), errors)};
  // Recordings made before the vision file was recorded have none: the built-in defaults.
  if (root["vision"]) {
    TempFile vision("vision");
    if (!write_section(root, "vision", vision.path(), errors)) return std::nullopt;
    if (auto v = config::load_vision_file(vision.path().string(), errors)) c.vision.params = *v;
    c.vision.file = root["vision"]["file"] ? root["vision"]["file"].as<std::string>() : "";
  }
  if (!errors.empty()) return std::nullopt;
  return c;
}

std::string apply_parameter_set(mission::MissionCore& core, const record::ParameterSetRecord& set) {
  mission::TunableParameters p = core.parameters();
  for (const auto& [name, value] : set.values) {
    const mission::TunableSpec* spec = mission::find_tunable(name);
    if (spec == nullptr) return "unknown parameter '" + name + "'";
    if (std::string e = mission::check_tunable(*spec, value); !e.empty()) return e;
    spec->set(p, value);
  }
  return core.apply_parameters(p);
}

ReplayReport replay(const Recording& recording, const config::Configuration& config,
                    const ReplayOptions& options, const TickCallback& on_tick) {
  ReplayReport report;
  if (!recording.ok) {
    report.error = recording.error.empty() ? "recording not loaded" : recording.error;
    return report;
  }
  report.ok = true;
  mission::MissionCore core(config.boat, config.mission,
                            config::magnetometer_of(config.devices.imu));
  (void)core.set_vision(config.vision.params);  // loaded and validated with the rest
  // Large (scan arrays): allocated once, reused for every tick.
  auto tick = std::make_unique<record::TickRecordData>();
  auto scan = std::make_unique<msg::LidarScan>();
  auto out = std::make_unique<mission::CoreOutput>();
  auto viz = std::make_unique<record::TickViz>();
  std::uint64_t scan_sequence = 0;
  bool scan_loaded = false;
  std::string recorded_path;
  std::string replayed_path;
  std::size_t next_set = 0;  // recording.parameter_sets[next_set] is the next to apply
  const auto names = channel_names(config.boat.actuators.layout);
  for (std::size_t c = 0; c < report.pulses.size(); ++c) report.pulses[c].name = names[c];
  // Listed visualization differences still holding the replayed JSON: index -> log time.
  std::map<std::size_t, PendingViz> viz_pending;

  for (const auto& bytes : recording.ticks) {
    if (!record::decode_tick(recording.encoding, bytes, *tick)) {
      ++report.ticks_undecodable;
      continue;
    }
    // The live parameter sets first in force at this tick, applied between the same two steps.
    while (options.apply_parameter_sets && next_set < recording.parameter_sets.size() &&
           recording.parameter_sets[next_set].tick_index <= tick->tick_index) {
      if (apply_parameter_set(core, recording.parameter_sets[next_set]).empty()) {
        ++report.parameter_sets_applied;
        report.parameter_ticks.push_back(tick->tick_index);
      } else {
        ++report.parameter_sets_refused;
      }
      ++next_set;
    }
    // The scan the core saw: the /lidar message of the tick's sequence (header from the tick).
    const std::uint64_t seq = tick->snapshot.lidar.sequence;
    if (seq != 0 && seq != scan_sequence) {
      scan_sequence = seq;
      scan_loaded = false;
      if (const auto it = recording.lidar.find(seq); it != recording.lidar.end()) {
        std::uint64_t s = 0;
        scan_loaded = record::decode_sample(recording.encoding, it->second, s, *scan);
      }
    }
    if (seq != 0) {
      if (scan_loaded) {
        tick->snapshot.lidar.value = *scan;
      } else {
        ++report.lidar_scans_missing;
      }
    }
    core.step(tick->snapshot, tick->now_ns, *out);
    ++report.ticks;

    const msg::ActuatorCommand& a = tick->command;
    const msg::ActuatorCommand& b = out->command;
    const std::int64_t recorded_fields[] = {a.stamp_ns, a.pulse_us[0], a.pulse_us[1],
                                            static_cast<std::int64_t>(a.led), a.active ? 1 : 0};
    const std::int64_t replayed_fields[] = {b.stamp_ns, b.pulse_us[0], b.pulse_us[1],
                                            static_cast<std::int64_t>(b.led), b.active ? 1 : 0};
    bool tick_differs = false;
    auto note = [&](std::string field, std::string rec, std::string rep) {
      tick_differs = true;
      ++report.fields_different;
      if (report.differences.size() < options.max_diffs) {
        report.differences.push_back(
            {tick->tick_index, tick->now_ns, std::move(field), std::move(rec), std::move(rep)});
      }
    };
    for (std::size_t i = 0; i < std::size(recorded_fields); ++i) {
      if (recorded_fields[i] != replayed_fields[i]) {
        std::string field = command_field(i);
        if (i == 1 || i == 2) {
          std::string named = names[i - 1];
          named += " pulse_us (";
          named += field;
          named += ")";
          field = std::move(named);
        }
        note(std::move(field), std::to_string(recorded_fields[i]),
             std::to_string(replayed_fields[i]));
      }
    }
    for (std::size_t c = 0; c < a.pulse_us.size(); ++c) {
      if (a.pulse_us[c] == b.pulse_us[c]) continue;
      PulseDivergence& p = report.pulses[c];
      const auto by = static_cast<std::uint32_t>(std::abs(a.pulse_us[c] - b.pulse_us[c]));
      if (p.ticks_different++ == 0 || by > p.largest_difference_us) {
        p.largest_difference_us = by;
        p.largest_at_tick = tick->tick_index;
        p.largest_at_ns = tick->now_ns;
      }
    }
    const std::string_view path = out->status.state_path.view();
    const std::string_view recorded_cut = tick->state_path;
    if (path.substr(0, record::kMaxStatePathBytes) != recorded_cut) {
      note("state_path", std::string(recorded_cut), std::string(path));
    }
    // The visualization, as the recorder's writer thread turned the tick's TickViz into JSON.
    const core::TimeNs viewer_ns = tick->now_ns + recording.log_time_offset_ns;
    const auto stamp = static_cast<std::uint64_t>(viewer_ns < 0 ? 0 : viewer_ns);
    const auto scene = recording.viz_scene.find(stamp);
    if (scene != recording.viz_scene.end()) {
      ++report.viz_compared;
      host::fill_tick_viz(*out, config.boat, *viz);
      const std::string replayed_json = record::foxglove::scene_update_json(
          viewer_ns, *viz, path.substr(0, record::kMaxStatePathBytes));
      const std::uint64_t replayed_scene = fnv1a(replayed_json);
      if (replayed_scene != scene->second) {
        if (report.differences.size() < options.max_diffs) {
          viz_pending[report.differences.size()] = {stamp, replayed_json};
        }
        note("viz.scene", hex(scene->second), hex(replayed_scene));
      }
      const auto pose = recording.viz_pose.find(stamp);
      const bool recorded_pose = pose != recording.viz_pose.end();
      if (recorded_pose != viz->pose_valid) {
        note("viz.pose", recorded_pose ? "present" : "absent",
             viz->pose_valid ? "present" : "absent");
      } else if (recorded_pose) {
        const std::string replayed_pose = record::foxglove::frame_transform_json(viewer_ns, *viz);
        if (fnv1a(replayed_pose) != pose->second) {
          if (report.differences.size() < options.max_diffs) {
            viz_pending[report.differences.size()] = {stamp, replayed_pose};
          }
          note("viz.pose", hex(pose->second), hex(fnv1a(replayed_pose)));
        }
      }
    }
    if (tick_differs) {
      if (!report.first_divergence_tick) {
        report.first_divergence_tick = tick->tick_index;
        report.first_divergence_ns = tick->now_ns;
      }
      ++report.ticks_different;
    }
    if (recorded_cut != recorded_path || report.recorded_paths.empty()) {
      recorded_path = std::string(recorded_cut);
      report.recorded_paths.push_back({tick->tick_index, tick->now_ns, recorded_path});
    }
    if (path != replayed_path || report.replayed_paths.empty()) {
      replayed_path = std::string(path);
      report.replayed_paths.push_back({tick->tick_index, tick->now_ns, replayed_path});
    }
    if (on_tick) on_tick(*tick, *out);
  }
  explain_viz_differences(recording, report.differences, viz_pending);
  return report;
}

std::string format_replay_report(const ReplayReport& r, bool summary) {
  std::ostringstream o;
  if (!r.ok) {
    o << "replay failed: " << r.error << "\n";
    return o.str();
  }
  char line[256];
  for (const Difference& d : r.differences) {
    std::snprintf(line, sizeof line, "tick %llu t=%.3f s: %s recorded %s replayed %s\n",
                  static_cast<unsigned long long>(d.tick_index),
                  static_cast<double>(d.now_ns) / 1e9, d.field.c_str(), d.recorded.c_str(),
                  d.replayed.c_str());
    o << line;
  }
  if (r.fields_different > r.differences.size()) {
    o << "... " << (r.fields_different - r.differences.size()) << " more differences\n";
  }
  if (summary && r.first_divergence_tick) {
    std::snprintf(line, sizeof line,
                  "first divergence at tick %llu (t=%.3f s); %llu of %llu ticks differ (%.1f%%)\n",
                  static_cast<unsigned long long>(*r.first_divergence_tick),
                  static_cast<double>(r.first_divergence_ns) / 1e9,
                  static_cast<unsigned long long>(r.ticks_different),
                  static_cast<unsigned long long>(r.ticks),
                  r.ticks == 0 ? 0.0
                               : 100.0 * static_cast<double>(r.ticks_different) /
                                     static_cast<double>(r.ticks));
    o << line;
    if (!r.differences.empty()) {
      const Difference& d = r.differences.front();
      o << "  first: " << d.field << " recorded " << d.recorded << " replayed " << d.replayed
        << "\n";
    }
    auto timeline = [&](const char* name, const std::vector<PathChange>& paths) {
      o << name << " state paths:\n";
      for (const PathChange& p : paths) {
        std::snprintf(line, sizeof line, "  tick %8llu t=%9.3f s  %s\n",
                      static_cast<unsigned long long>(p.tick_index),
                      static_cast<double>(p.now_ns) / 1e9, p.path.c_str());
        o << line;
      }
    };
    timeline("recorded", r.recorded_paths);
    timeline("replayed", r.replayed_paths);
  }
  if (r.first_divergence_tick) {
    for (const PulseDivergence& p : r.pulses) {
      if (p.ticks_different == 0) {
        std::snprintf(line, sizeof line, "%s pulse: identical in every tick\n", p.name.c_str());
      } else {
        std::snprintf(line, sizeof line,
                      "%s pulse: differs in %llu ticks, by up to %u us (tick %llu, t=%.3f s)\n",
                      p.name.c_str(), static_cast<unsigned long long>(p.ticks_different),
                      p.largest_difference_us, static_cast<unsigned long long>(p.largest_at_tick),
                      static_cast<double>(p.largest_at_ns) / 1e9);
      }
      o << line;
    }
  }
  if (r.parameter_sets_applied > 0) {
    o << r.parameter_sets_applied << " live parameter set"
      << (r.parameter_sets_applied == 1 ? "" : "s") << " applied at tick";
    for (const std::uint64_t t : r.parameter_ticks) o << " " << t;
    o << "\n";
  }
  if (r.parameter_sets_refused > 0) {
    o << "warning: " << r.parameter_sets_refused
      << " recorded parameter sets were refused by the replayed core\n";
  }
  if (r.lidar_scans_missing > 0) {
    o << "warning: " << r.lidar_scans_missing
      << " ticks saw a lidar scan missing from /lidar (dropped by the recorder): their inputs "
         "are incomplete\n";
  }
  if (r.ticks_undecodable > 0) {
    o << "warning: " << r.ticks_undecodable << " /tick messages could not be decoded\n";
  }
  std::snprintf(
      line, sizeof line, "%llu ticks replayed: %s\n", static_cast<unsigned long long>(r.ticks),
      r.fields_different == 0 ? "identical"
                              : (std::to_string(r.fields_different) + " differing fields in " +
                                 std::to_string(r.ticks_different) + " ticks")
                                    .c_str());
  o << line;
  return o.str();
}

}  // namespace coxswain::replay
