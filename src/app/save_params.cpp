// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/save_params.hpp"

#include <yaml-cpp/yaml.h>

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "coxswain/config/config.hpp"
#include "coxswain/config/vision_config.hpp"
#include "coxswain/mission/tunable_parameters.hpp"

namespace coxswain::app {
namespace {

// The shortest text that reads back as the same double.
std::string shortest(double v) {
  std::array<char, 32> buf{};
  const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return ec == std::errc{} ? std::string(buf.data(), end) : std::to_string(v);
}

// A value as the mission file writes it.
std::string as_text(const mission::TunableSpec& spec, double v) {
  if (spec.boolean) return v != 0.0 ? "true" : "false";
  if (!spec.choices.empty()) {
    const auto i = static_cast<std::size_t>(v);
    if (v >= 0.0 && i < spec.choices.size()) return spec.choices[i];
  }
  if (spec.integer) return std::to_string(static_cast<long long>(std::llround(v)));
  return shortest(v);
}

// node[path[i]][path[i+1]]... = text, making the maps on the way (Node is a handle).
void set_path(YAML::Node node, const std::vector<std::string>& path, std::size_t i,
              const std::string& text) {
  if (i + 1 == path.size()) {
    node[path[i]] = text;
    return;
  }
  if (!node[path[i]] || !node[path[i]].IsMap()) node[path[i]] = YAML::Node(YAML::NodeType::Map);
  set_path(node[path[i]], path, i + 1, text);
}

bool write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream f(path, std::ios::trunc);
  f << text;
  f.close();
  return static_cast<bool>(f);
}

}  // namespace

std::string mission_with_values(const std::string& mission_yaml,
                                const std::vector<std::pair<std::string, double>>& values,
                                std::string& error) {
  YAML::Node root;
  try {
    root = YAML::Load(mission_yaml);
  } catch (const YAML::Exception& e) {
    error = std::string("not YAML: ") + e.what();
    return {};
  }
  if (!root.IsMap() || !root["kind"] || root["kind"].Scalar() != "mission") {
    error = "not a mission file (kind: mission)";
    return {};
  }
  for (const auto& [name, value] : values) {
    const mission::TunableSpec* spec = mission::find_tunable(name);
    if (spec == nullptr || spec->group == mission::TunableGroup::kVision) continue;
    // "avoidance.score.goal_weight": avoidance -> score -> goal_weight, maps made as needed.
    std::vector<std::string> path;
    std::size_t begin = 0;
    while (begin <= name.size()) {
      const std::size_t dot = std::min(name.find('.', begin), name.size());
      path.push_back(name.substr(begin, dot - begin));
      begin = dot + 1;
    }
    set_path(root, path, 0, as_text(*spec, value));
  }
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

std::string save_params(const std::string& answer, const std::filesystem::path& vision_out,
                        const std::filesystem::path& mission_out) {
  const nlohmann::json j = nlohmann::json::parse(answer, nullptr, false);
  if (!j.is_object() || !j.contains("ok") || !j["ok"].is_boolean() || !j["ok"].get<bool>() ||
      !j.contains("vision_yaml") || !j["vision_yaml"].is_string() || !j.contains("parameters") ||
      !j["parameters"].is_object()) {
    const std::string why = j.is_object() && j.contains("error") && j["error"].is_string()
                                ? j["error"].get<std::string>()
                                : answer;
    return "the daemon did not give its parameters: " + why;
  }
  const std::string from = j.contains("vision_file") && j["vision_file"].is_string()
                               ? j["vision_file"].get<std::string>()
                               : "";
  const std::string vision = "# Saved by `coxswain ctl save-params` from the running daemon" +
                             (from.empty() ? std::string() : " (started from " + from + ")") +
                             ".\n" + j["vision_yaml"].get<std::string>();
  if (!write_file(vision_out, vision)) return "cannot write " + vision_out.string();
  config::ConfigErrors errors;
  if (!config::load_vision_file(vision_out.string(), errors)) {
    return "the saved vision file does not load back:\n" + errors.format();
  }
  if (mission_out.empty()) return {};

  const std::string mission_file = j.contains("mission_file") && j["mission_file"].is_string()
                                       ? j["mission_file"].get<std::string>()
                                       : "";
  if (mission_file.empty()) return "the daemon did not name its mission file";
  std::ifstream in(mission_file);
  if (!in) return "cannot read the daemon's mission file " + mission_file;
  std::ostringstream text;
  text << in.rdbuf();
  std::vector<std::pair<std::string, double>> values;
  for (const auto& [name, value] : j["parameters"].items()) {
    if (value.is_number()) values.emplace_back(name, value.get<double>());
  }
  std::string error;
  const std::string mission = mission_with_values(text.str(), values, error);
  if (mission.empty()) return mission_file + ": " + error;
  if (!write_file(mission_out, "# Saved by `coxswain ctl save-params`: " + mission_file +
                                   " with the live values in force.\n" + mission)) {
    return "cannot write " + mission_out.string();
  }
  (void)config::load_mission_config(mission_out.string(), errors);
  if (!errors.empty()) return "the saved mission file does not load back:\n" + errors.format();
  return {};
}

}  // namespace coxswain::app
