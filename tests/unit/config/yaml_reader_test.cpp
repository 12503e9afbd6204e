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

// Aliases of aliases: nine levels of nine make a file of under 1 KiB expand to 9^9 values,
// which every reader would walk. Refused with the reason, before any reader sees it.
TEST(LoadYaml, ADocumentThatExpandsPastTheBoundIsRefused) {
  std::string text = "kind: course\na0: &a0 [x, x, x, x, x, x, x, x, x]\n";
  for (int level = 1; level < 9; ++level) {
    const std::string prev = "*a" + std::to_string(level - 1);
    text += "a" + std::to_string(level) + ": &a" + std::to_string(level) + " [";
    for (int i = 0; i < 9; ++i) text += (i ? ", " : "") + prev;
    text += "]\n";
  }
  TempYaml file(text);
  ConfigErrors errors;
  EXPECT_FALSE(load_yaml_file(file.path(), errors));
  ASSERT_EQ(errors.size(), 1U);
  EXPECT_NE(errors.issues()[0].message.find("expands to more than 2000000 values"),
            std::string::npos)
      << errors.format();
}

TEST(LoadYaml, AliasesWithinTheBoundAreRead) {
  TempYaml file("kind: course\na: &a [1, 2, 3]\nb: [*a, *a, *a]\n");
  ConfigErrors errors;
  EXPECT_TRUE(load_yaml_file(file.path(), errors)) << errors.format();
}

TEST(LoadYaml, NestingDeeperThanTheBoundIsRefusedWithItsLine) {
  std::string deep = "kind: course\nx: ";
  for (int i = 0; i < kMaxConfigDepth + 5; ++i) deep += "[";
  for (int i = 0; i < kMaxConfigDepth + 5; ++i) deep += "]";
  TempYaml file(deep + "\n");
  ConfigErrors errors;
  EXPECT_FALSE(load_yaml_file(file.path(), errors));
  ASSERT_EQ(errors.size(), 1U);
  EXPECT_NE(errors.issues()[0].message.find("deeper than 64 levels"), std::string::npos)
      << errors.format();
  EXPECT_EQ(errors.issues()[0].line, 2);

  std::string fine = "kind: course\nx: ";
  for (int i = 0; i < 10; ++i) fine += "[";
  for (int i = 0; i < 10; ++i) fine += "]";
  TempYaml ok(fine + "\n");
  ConfigErrors none;
  EXPECT_TRUE(load_yaml_file(ok.path(), none)) << none.format();
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

namespace coxswain::config {
namespace {

std::string load_errors(const std::string& text) {
  TempYaml file(text);
  ConfigErrors errors;
  EXPECT_FALSE(load_yaml_file(file.path(), errors)) << "accepted:\n" << text;
  return errors.format();
}

TEST(StrictYaml, DuplicateKeyIsAnErrorWithBothLines) {
  const std::string text = load_errors("kind: devices\nbaud: 9600\nbaud: 115200\n");
  EXPECT_NE(text.find(".yaml:3: key 'baud' is a duplicate key (first at line 2)"),
            std::string::npos)
      << text;
}

TEST(StrictYaml, DuplicateSectionIsAnError) {
  const std::string text =
      load_errors("kind: devices\ngnss:\n  baud: 9600\nlidar: {}\ngnss:\n  port: x\n");
  EXPECT_NE(text.find(":5: key 'gnss' is a duplicate key (first at line 2)"), std::string::npos)
      << text;
}

TEST(StrictYaml, DuplicateKeyInsideAListElementIsAnError) {
  const std::string text = load_errors("tasks:\n  - kind: a\n    kind: b\n");
  EXPECT_NE(text.find(":3: key 'kind' is a duplicate key"), std::string::npos) << text;
}

TEST(StrictYaml, SecondDocumentIsAnErrorWithItsLine) {
  const std::string text = load_errors("kind: boat\n---\nkind: devices\n");
  EXPECT_NE(text.find("holds 2 YAML documents"), std::string::npos) << text;
  EXPECT_NE(text.find(".yaml:2:"), std::string::npos) << text;  // the '---' that starts it
}

// yaml-cpp 0.7 alone never returns on these (its parser repeats an empty document forever).
TEST(StrictYaml, AStrayCommaIsASyntaxErrorNotAHang) {
  for (const char* text : {",", "\n,\n", "kind: boat\n---\n,\n"}) {
    const std::string errors = load_errors(text);
    EXPECT_NE(errors.find("YAML syntax error"), std::string::npos) << text << ": " << errors;
  }
}

TEST(StrictYaml, EmptyFileAndCommentOnlyFileAreErrors) {
  EXPECT_NE(load_errors("").find("is empty"), std::string::npos);
  EXPECT_NE(load_errors("# nothing here\n").find("is empty"), std::string::npos);
  EXPECT_NE(load_errors("---\n...\n").find("is empty"), std::string::npos);
}

TEST(StrictYaml, OverLongFileIsRefusedBeforeParsing) {
  TempYaml file("kind: course\n" + std::string(2000, '#') + "\n");
  ConfigErrors errors;
  EXPECT_FALSE(load_yaml_file(file.path(), errors, 1000));
  EXPECT_NE(errors.format().find("more than the 1000 a config file may have"), std::string::npos)
      << errors.format();
}

TEST(StrictYaml, OneDocumentWithDistinctKeysLoads) {
  TempYaml file("---\nkind: boat\na: {x: 1, y: 2}\nb: [{x: 1}, {x: 2}]\n");
  ConfigErrors errors;
  EXPECT_TRUE(load_yaml_file(file.path(), errors)) << errors.format();
}

TEST(StrictYaml, LeadingZeroAndHexIntegersAreErrors) {
  ConfigErrors errors;
  MapReader r(YAML::Load("baud: 0115200\nid: 0x1C\nok: 115200\nneg: -3\nzero: 0\n"), "d.yaml", "",
              errors);
  EXPECT_EQ(r.get<int>("baud", 9600), 9600);
  EXPECT_EQ(r.get<int>("id", 1), 1);
  EXPECT_EQ(r.get<int>("ok", 0), 115200);
  EXPECT_EQ(r.get<int>("neg", 0), -3);
  EXPECT_EQ(r.get<int>("zero", 5), 0);
  r.finish();
  ASSERT_EQ(errors.size(), 2U) << errors.format();
  EXPECT_EQ(errors.issues()[0].to_string(),
            "d.yaml:1: key 'baud' expected a decimal integer, got '0115200'");
  EXPECT_EQ(errors.issues()[1].to_string(),
            "d.yaml:2: key 'id' expected a decimal integer, got '0x1C'");
}

TEST(StrictYaml, DecimalIntegerTextIsRecognised) {
  EXPECT_TRUE(is_decimal_integer("0"));
  EXPECT_TRUE(is_decimal_integer("+7"));
  EXPECT_FALSE(is_decimal_integer("00"));
  EXPECT_FALSE(is_decimal_integer("0o17"));
  EXPECT_FALSE(is_decimal_integer("1e3"));
  EXPECT_FALSE(is_decimal_integer("-"));
  EXPECT_FALSE(is_decimal_integer(""));
  EXPECT_FALSE(is_decimal_integer("1_000"));
}

}  // namespace
}  // namespace coxswain::config
