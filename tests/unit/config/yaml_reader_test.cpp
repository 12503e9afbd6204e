// SPDX-License-Identifier: Apache-2.0
#include "coxswain/config/yaml_reader.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "coxswain/config/config.hpp"

namespace coxswain::config {
namespace {

class TempYaml {
 public:
  explicit TempYaml(const std::string& text) {
    path_ = std::filesystem::temp_directory_path() /
            ("coxswain_cfg_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
             "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".yaml");
    std::ofstream(path_) << text;
  }
  ~TempYaml() { std::filesystem::remove(path_); }
  [[nodiscard]] std::string path() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

TEST(MapReader, ReadsTypedValuesAndDefaults) {
  ConfigErrors errors;
  MapReader r(YAML::Load("a: 1.5\nb: 7\nc: true\nd: text\n"), "f.yaml", "", errors);
  EXPECT_DOUBLE_EQ(r.get("a", 0.0), 1.5);
  EXPECT_EQ(r.get<int>("b", 0), 7);
  EXPECT_TRUE(r.get("c", false));
  EXPECT_EQ(r.get<std::string>("d", ""), "text");
  EXPECT_DOUBLE_EQ(r.get("missing", 4.0), 4.0);
  r.finish();
  EXPECT_TRUE(errors.empty()) << errors.format();
}

TEST(MapReader, WrongTypeNamesFileLineAndKey) {
  ConfigErrors errors;
  MapReader root(YAML::Load("top: 1\nservo:\n  max_deg: fast\n"), "boat.yaml", "", errors);
  (void)root.get("top", 0);
  auto servo = root.map("servo");
  ASSERT_TRUE(servo);
  EXPECT_DOUBLE_EQ(servo->get("max_deg", 25.0), 25.0);  // fallback keeps validation going
  ASSERT_EQ(errors.size(), 1U);
  EXPECT_EQ(errors.issues()[0].to_string(),
            "boat.yaml:3: key 'servo.max_deg' expected a number, got 'fast'");
}

TEST(MapReader, OutOfRangeIsAnError) {
  ConfigErrors errors;
  MapReader r(YAML::Load("rate: 500\n"), "m.yaml", "", errors);
  (void)r.get("rate", 50.0, {1.0, 200.0});
  ASSERT_EQ(errors.size(), 1U);
  EXPECT_EQ(errors.issues()[0].line, 1);
  EXPECT_EQ(errors.issues()[0].key, "rate");
  EXPECT_NE(errors.issues()[0].message.find("<= 200"), std::string::npos);
}

TEST(MapReader, UnknownKeysAreErrors) {
  ConfigErrors errors;
  MapReader r(YAML::Load("known: 1\nknwon: 2\n"), "x.yaml", "p", errors);
  (void)r.get("known", 0);
  r.finish();
  r.finish();  // idempotent
  ASSERT_EQ(errors.size(), 1U);
  EXPECT_EQ(errors.issues()[0].to_string(), "x.yaml:2: key 'p.knwon' is not a known key");
}

TEST(MapReader, RequiredAndEnum) {
  ConfigErrors errors;
  MapReader r(YAML::Load("mode: sideways\n"), "x.yaml", "", errors);
  enum class Mode { kA, kB };
  EXPECT_EQ(r.get_enum("mode", Mode::kA, {{"a", Mode::kA}, {"b", Mode::kB}}), Mode::kA);
  (void)r.require<double>("needed");
  r.finish();
  ASSERT_EQ(errors.size(), 2U);
  EXPECT_NE(errors.issues()[0].message.find("must be one of: a, b"), std::string::npos);
  EXPECT_EQ(errors.issues()[1].key, "needed");
}

TEST(MapReader, NestedMapWhereScalarExpected) {
  ConfigErrors errors;
  MapReader r(YAML::Load("x: {a: 1}\n"), "x.yaml", "", errors);
  (void)r.get("x", 1.0);
  ASSERT_EQ(errors.size(), 1U);
  EXPECT_NE(errors.issues()[0].message.find("got a map"), std::string::npos);
}

TEST(LoadYaml, SyntaxErrorHasLine) {
  TempYaml file("kind: boat\nhull: [1, 2\nname: x\n");
  ConfigErrors errors;
  EXPECT_FALSE(load_yaml_file(file.path(), errors));
  ASSERT_EQ(errors.size(), 1U);
  EXPECT_GT(errors.issues()[0].line, 1);
  EXPECT_NE(errors.issues()[0].message.find("YAML syntax error"), std::string::npos);
}

TEST(LoadYaml, MissingFile) {
  ConfigErrors errors;
  EXPECT_FALSE(load_yaml_file("/nonexistent/boat.yaml", errors));
  EXPECT_EQ(errors.size(), 1U);
}

TEST(MissionConfig, BadValuesAreAllReported) {
  TempYaml file(
      "kind: mission\n"
      "name: bad name\n"
      "tick_rate_hz: 5000\n"
      "origin: {lat_deg: 95, lon_deg: 128}\n"
      "tasks:\n"
      "  - type: hopping\n"
      "    waypoints: [{lat_deg: 35, lon_deg: 128}]\n"
      "    colour: red\n");
  ConfigErrors errors;
  (void)load_mission_config(file.path(), errors);
  const std::string text = errors.format();
  EXPECT_NE(text.find(":2: key 'name'"), std::string::npos) << text;
  EXPECT_NE(text.find(":3: key 'tick_rate_hz'"), std::string::npos) << text;
  EXPECT_NE(text.find(":4: key 'origin.lat_deg'"), std::string::npos) << text;
  EXPECT_NE(text.find("key 'tasks[0].waypoints' a hopping task needs"), std::string::npos) << text;
  EXPECT_NE(text.find(":8: key 'tasks[0].colour' is not a known key"), std::string::npos) << text;
}

TEST(BoatConfig, KindMismatchIsAnError) {
  TempYaml file("kind: devices\n");
  ConfigErrors errors;
  (void)load_boat_config(file.path(), errors);
  EXPECT_NE(errors.format().find("key 'kind' must be 'boat'"), std::string::npos)
      << errors.format();
}

TEST(BoatConfig, ThrusterOrderingChecked) {
  TempYaml file(
      "kind: boat\nhull: {length_m: 1, beam_m: 0.5}\nmounts: {}\n"
      "actuators:\n  servo: {}\n  thruster: {forward_start_us: 1400}\n");
  ConfigErrors errors;
  (void)load_boat_config(file.path(), errors);
  EXPECT_NE(errors.format().find("actuators.thruster"), std::string::npos) << errors.format();
}

}  // namespace
}  // namespace coxswain::config
