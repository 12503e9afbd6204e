// SPDX-License-Identifier: Apache-2.0
// The parameter tables are the one declaration of every parameter: names, bounds and defaults
// agree between the file, live tuning and the schema; the shipped schemas are the generated ones.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>

#include <unistd.h>

#include "coxswain/config/config.hpp"
#include "coxswain/config/param_tables.hpp"
#include "coxswain/config/reference.hpp"
#include "coxswain/config/vision_config.hpp"

namespace coxswain::config {
namespace {

template <class F>
void for_every_table(F&& f) {
  f(std::string("boat"), BoatConfig{});
  const DevicesConfig devices{};
  for_each_devices_section(
      devices, [&](std::string_view key, const auto& s) { f("devices." + std::string(key), s); });
  const MissionConfig mission{};
  for_each_mission_section(
      mission, [&](std::string_view key, const auto& s) { f("mission." + std::string(key), s); });
  f(std::string("vision"), perception::VisionParams{});
  f(std::string("vision.colours[]"), perception::ColourRange{});
}

TEST(ParamTables, EveryRowHasAUniqueKeyADocAndADefaultWithinItsBounds) {
  std::set<std::string> keys;
  std::size_t rows = 0;
  for_every_table([&](const std::string& section, const auto& value) {
    using S = std::remove_cvref_t<decltype(value)>;
    for (const core::ParamSpec<S>& row : param_table<S>()) {
      ++rows;
      const std::string key = section + ":" + std::string(row.key);
      EXPECT_TRUE(keys.insert(key).second) << key << " twice";
      EXPECT_FALSE(row.doc.empty()) << key;
      EXPECT_NE(row.get, nullptr) << key;
      if (row.type == core::ParamType::kReal || row.type == core::ParamType::kInteger) {
        EXPECT_LE(row.min, row.max) << key;
        const double d = row.default_value();
        EXPECT_GE(d, row.min) << key << " default " << d;
        EXPECT_LE(d, row.max) << key << " default " << d;
      }
      // A colour range's colour is required (an entry has no default colour).
      if (row.type == core::ParamType::kEnum && key != "vision.colours[]:colour") {
        EXPECT_FALSE(row.choice_name(row.default_value()).empty()) << key;
      }
      // set(get(x)) is the identity: a value read from a file is the value the struct holds.
      S copy{};
      if (row.type != core::ParamType::kText) {
        row.set(copy, row.default_value());
        EXPECT_EQ(row.get(copy), row.default_value()) << key;
      }
    }
  });
  EXPECT_GT(rows, 150U);
}

TEST(ParamTables, TheNavigationFilterIsTunedFromTheMissionFileAndItsBoundsAreChecked) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("coxswain_tables_nav_" + std::to_string(::getpid()) + ".yaml");
  const std::string head = "kind: mission\nname: t\norigin: {lat_deg: 35.0, lon_deg: 128.0}\n";
  const std::string tasks =
      "tasks:\n  - type: hopping\n    waypoints:\n"
      "      - {lat_deg: 35.0, lon_deg: 128.0}\n      - {lat_deg: 35.0001, lon_deg: 128.0}\n";
  {
    std::ofstream(path) << head << "navigation:\n  filter:\n    gnss_bias_tau_s: 120\n"
                        << "    max_rejected_fixes: 4\n"
                        << tasks;
    ConfigErrors errors;
    const MissionConfig m = load_mission_config(path.string(), errors);
    EXPECT_TRUE(errors.empty()) << errors.format();
    EXPECT_DOUBLE_EQ(m.navigation.filter.gnss_bias_tau_s, 120.0);
    EXPECT_EQ(m.navigation.filter.max_rejected_fixes, 4U);
    EXPECT_DOUBLE_EQ(m.navigation.filter.accel_noise_mps2,
                     guidance::NavFilterParams{}.accel_noise_mps2);
  }
  {
    std::ofstream(path) << head << "navigation:\n  filter:\n    gate_chi2_2dof: 0\n" << tasks;
    ConfigErrors errors;
    (void)load_mission_config(path.string(), errors);
    bool gate = false;
    for (const ConfigIssue& i : errors.issues()) {
      gate |= i.key == "navigation.filter.gate_chi2_2dof" && i.line == 6;
    }
    EXPECT_TRUE(gate) << errors.format();
  }
  std::filesystem::remove(path);
}

TEST(ParamTables, AFileValueOutsideTheLiveBoundsIsAnErrorAtItsLine) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() /
                                     ("coxswain_tables_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(path) << "kind: mission\nname: t\norigin: {lat_deg: 35.0, lon_deg: 128.0}\n"
                         "avoidance:\n  clearance_m: 5.0\n  score: {goal_weight: 0.0}\n"
                         "tasks:\n  - type: hopping\n    waypoints:\n"
                         "      - {lat_deg: 35.0, lon_deg: 128.0}\n"
                         "      - {lat_deg: 35.0001, lon_deg: 128.0}\n";
  ConfigErrors errors;
  (void)load_mission_config(path.string(), errors);
  std::filesystem::remove(path);
  bool clearance = false;
  bool goal = false;
  for (const ConfigIssue& i : errors.issues()) {
    clearance |= i.key == "avoidance.clearance_m" && i.line == 5;
    goal |= i.key == "avoidance.score.goal_weight" && i.line == 6;
  }
  EXPECT_TRUE(clearance) << errors.format();
  EXPECT_TRUE(goal) << errors.format();
}

TEST(ParamTables, ThePrintedConfigurationLoadsBackBitForBit) {
  const std::filesystem::path dir = std::filesystem::path(COXSWAIN_SOURCE_DIR) / "config";
  ConfigErrors errors;
  Configuration c{load_boat_config((dir / "boat.yaml").string(), errors),
                  load_devices_config((dir / "devices.yaml").string(), errors),
                  load_mission_config((dir / "missions" / "kaboat2026.yaml").string(), errors)};
  ASSERT_TRUE(errors.empty()) << errors.format();
  c.mission.avoidance.clearance_m = 0.1 + 0.2;  // not exactly representable in short decimal
  c.vision.params.background.reject_sigma = 0.1 + 0.2;
  const std::string text = to_yaml(c);
  // Each section of the printout is a file of its kind again.
  const auto section = [&](const std::string& name, const std::string& kind) {
    const std::size_t begin = text.find("\n" + name + ":\n");
    const std::size_t start = begin == std::string::npos ? text.find(name + ":\n") : begin + 1;
    EXPECT_NE(start, std::string::npos) << name;
    std::size_t end = text.size();
    for (const char* next : {"\nboat:\n", "\ndevices:\n", "\nmission:\n", "\nvision:\n"}) {
      const std::size_t at = text.find(next, start + 1);
      if (at != std::string::npos && at < end) end = at;
    }
    std::istringstream lines(text.substr(start, end - start));
    std::string out = "kind: " + kind + "\n";
    std::string line;
    std::getline(lines, line);  // "<name>:"
    while (std::getline(lines, line)) {
      if (line.rfind("  file:", 0) == 0) continue;
      out += line.substr(line.size() >= 2 ? 2 : 0) + "\n";
    }
    const std::filesystem::path p = std::filesystem::temp_directory_path() /
                                    ("coxswain_rt_" + std::to_string(::getpid()) + name + ".yaml");
    std::ofstream(p) << out;
    return p;
  };
  const auto boat = section("boat", "boat");
  const auto devices = section("devices", "devices");
  const auto mission = section("mission", "mission");
  const auto vision = section("vision", "vision");
  ConfigErrors again;
  const auto v = load_vision_file(vision.string(), again);
  const MissionConfig m = load_mission_config(mission.string(), again);
  const BoatConfig b = load_boat_config(boat.string(), again);
  const DevicesConfig d = load_devices_config(devices.string(), again);
  for (const auto& p : {boat, devices, mission, vision}) std::filesystem::remove(p);
  ASSERT_TRUE(again.empty()) << again.format();
  EXPECT_EQ(m.avoidance.clearance_m, 0.1 + 0.2);
  for (const auto& row : param_table<guidance::AvoidanceParams>()) {
    EXPECT_EQ(row.get(m.avoidance), row.get(c.mission.avoidance)) << row.key;
  }
  for (const auto& row : param_table<DockingConfig>()) {
    EXPECT_EQ(row.get(m.docking), row.get(c.mission.docking)) << row.key;
  }
  for (const auto& row : param_table<BoatConfig>()) {
    if (row.type != core::ParamType::kText) {
      EXPECT_EQ(row.get(b), row.get(c.boat)) << row.key;
    }
  }
  EXPECT_EQ(d.gnss.path, c.devices.gnss.path);
  EXPECT_EQ(m.tasks.size(), c.mission.tasks.size());
  ASSERT_TRUE(v.has_value());
  EXPECT_EQ(v->background.reject_sigma, 0.1 + 0.2);
  EXPECT_EQ(v->colour_count, c.vision.params.colour_count);
}

// A colour range without its colour is refused, naming the key.
TEST(ParamTables, AVisionRangeWithoutItsColourIsRefused) {
  ConfigErrors errors;
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / "coxswain_vision_no_colour.yaml";
  { std::ofstream(file) << "kind: vision\ncolours:\n  - {h_min: 10}\n"; }
  EXPECT_FALSE(load_vision_file(file.string(), errors).has_value());
  std::filesystem::remove(file);
  EXPECT_NE(errors.format().find("colour"), std::string::npos) << errors.format();
}

TEST(ParamTables, TheShippedSchemasAreTheGeneratedOnes) {
  const std::filesystem::path dir = std::filesystem::path(COXSWAIN_SOURCE_DIR) / "schemas";
  for (const char* kind : {"boat", "devices", "mission", "vision"}) {
    std::ifstream in(dir / (std::string(kind) + ".schema.json"));
    ASSERT_TRUE(in) << "schemas/" << kind << ".schema.json is missing";
    std::stringstream shipped;
    shipped << in.rdbuf();
    EXPECT_EQ(shipped.str(), json_schema(kind).value_or(""))
        << "schemas/" << kind << ".schema.json is stale: regenerate with `coxswain config schema "
        << kind << "`";
  }
  EXPECT_FALSE(json_schema("nonsense").has_value());
}

TEST(ParamTables, TheReferencePageInDocsIsTheGeneratedOne) {
  std::ifstream in(std::filesystem::path(COXSWAIN_SOURCE_DIR) / "docs" / "parameters.md");
  ASSERT_TRUE(in) << "docs/parameters.md is missing";
  std::stringstream shipped;
  shipped << in.rdbuf();
  EXPECT_EQ(shipped.str(), parameter_reference_markdown())
      << "docs/parameters.md is stale: regenerate with `coxswain config doc > docs/parameters.md`";
}

TEST(ParamTables, TheReferenceNamesEveryKeyAndTheParameterListHasItsBounds) {
  const std::string doc = parameter_reference_markdown();
  EXPECT_NE(doc.find("`avoidance.score.goal_weight`"), std::string::npos);
  EXPECT_NE(doc.find("`actuators.servo.center_us`"), std::string::npos);
  EXPECT_NE(doc.find("`gnss.rtcm_input`"), std::string::npos);
  EXPECT_NE(doc.find("`background.reject_sigma`"), std::string::npos);
  EXPECT_NE(doc.find("`colours[].h_min`"), std::string::npos);
  const std::string json = parameters_json();
  EXPECT_NE(json.find("\"key\": \"avoidance.clearance_m\""), std::string::npos);
  EXPECT_NE(json.find("\"max\": 2.0"), std::string::npos);
}

}  // namespace
}  // namespace coxswain::config
