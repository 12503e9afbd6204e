// SPDX-License-Identifier: Apache-2.0
// The engine sections of a mission file: read into the engines' own parameter structs, validated
// by the engines' own rules, errors at file:line:key.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "coxswain/config/config.hpp"
#include "coxswain/config/yaml_reader.hpp"

namespace coxswain::config {
namespace {

class TempMission {
 public:
  explicit TempMission(const std::string& body) {
    path_ = std::filesystem::temp_directory_path() /
            ("coxswain_mission_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".yaml");
    std::ofstream(path_) << "kind: mission\nname: t\norigin: {lat_deg: 35.0, lon_deg: 128.0}\n"
                         << body;
  }
  ~TempMission() { std::filesystem::remove(path_); }
  [[nodiscard]] std::string path() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

const char* kCourse3Task =
    "tasks:\n"
    "  - type: docking\n"
    "    style: course3\n";

bool has_issue(const ConfigErrors& e, const std::string& key, int line) {
  for (const auto& i : e.issues()) {
    if (i.key == key && (line == 0 || i.line == line)) return true;
  }
  return false;
}

TEST(MissionEngines, SectionsReachTheEngineParameters) {
  TempMission f(std::string("course_frame: {zero_heading_deg: 12.5}\n"
                            "avoidance: {strategy: risk_bin, detection_range_m: 6.0,\n"
                            "            risk: {threshold: 0.01}}\n"
                            "clustering: {min_group_points: 6, hull_box: {forward_min_m: -1.0}}\n"
                            "heading_pid: {kp_per_deg: 0.03}\n"
                            "speed: {cruise_thrust_frac: 0.5, rise_per_s: 0.1}\n"
                            "waypoints: {arrival_radius_m: 1.2, lookahead_m: 3.0}\n"
                            "course2: {colours: [yellow, blue], exit_course_deg: 90.0}\n"
                            "docking: {stop_range_m: 0.4, slip_max_range_m: 18.0}\n"
                            "vision_vote: {window_s: 3.0, min_ratio: 0.7}\n"
                            "start: {mode: immediate, require_arduino: false}\n") +
                kCourse3Task + "    on_timeout: finish\n");
  ConfigErrors errors;
  const MissionConfig m = load_mission_config(f.path(), errors);
  ASSERT_TRUE(errors.empty()) << errors.format();
  ASSERT_TRUE(m.navigation.course_zero_deg.has_value());
  EXPECT_DOUBLE_EQ(*m.navigation.course_zero_deg, 12.5);
  EXPECT_EQ(m.avoidance.strategy, guidance::Strategy::kRiskBin);
  EXPECT_DOUBLE_EQ(m.avoidance.detection_range_m, 6.0);
  EXPECT_DOUBLE_EQ(m.avoidance.risk_threshold, 0.01);
  EXPECT_EQ(m.clustering.min_group_points, 6U);
  EXPECT_DOUBLE_EQ(m.clustering.hull.forward_min_m, -1.0);
  EXPECT_DOUBLE_EQ(m.heading_pid.kp_per_deg, 0.03);
  EXPECT_DOUBLE_EQ(m.speed.cruise_thrust_frac, 0.5);
  EXPECT_DOUBLE_EQ(m.speed.rise_per_s, 0.1);
  EXPECT_DOUBLE_EQ(m.waypoints.arrival_radius_m, 1.2);
  EXPECT_DOUBLE_EQ(m.waypoints.line.lookahead_m, 3.0);
  ASSERT_EQ(m.course2.colours.size(), 2U);
  EXPECT_EQ(m.course2.colours[0], msg::Colour::kYellow);
  EXPECT_DOUBLE_EQ(m.course2.exit_course_deg, 90.0);
  EXPECT_DOUBLE_EQ(m.docking.approach.stop_range_m, 0.4);
  EXPECT_DOUBLE_EQ(m.docking.slip.max_range_m, 18.0);
  EXPECT_EQ(m.vision_vote.window_ns, 3 * core::kNsPerSec);
  EXPECT_DOUBLE_EQ(m.vision_vote.min_ratio, 0.7);
  EXPECT_FALSE(m.require_arduino);
  ASSERT_EQ(m.tasks.size(), 1U);
  EXPECT_EQ(m.tasks[0].docking_style, DockingStyle::kCourse3);
  EXPECT_EQ(m.tasks[0].on_timeout, TimeoutOutcome::kFinish);
  // --print-config shows the effective engine parameters.
  Configuration c;
  c.mission = m;
  const std::string yaml = to_yaml(c);
  EXPECT_NE(yaml.find("strategy: risk_bin"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("zero_heading_deg: 12.5"), std::string::npos);
  EXPECT_NE(yaml.find("colours: [yellow, blue]"), std::string::npos);
  EXPECT_NE(yaml.find("style: course3"), std::string::npos);
  EXPECT_NE(yaml.find("slip_max_range_m: 18"), std::string::npos);
  EXPECT_NO_THROW((void)YAML::Load(yaml));
}

TEST(MissionEngines, ErrorsNameFileLineAndKey) {
  TempMission f(std::string("avoidance:\n"
                            "  strategy: zigzag\n"  // line 5
                            "course2:\n"
                            "  colour: red\n"  // line 7: misspelt key
                            "vision_vote: {window_s: 1.0, min_span_s: 2.0}\n") +  // line 8
                kCourse3Task);
  ConfigErrors errors;
  (void)load_mission_config(f.path(), errors);
  EXPECT_TRUE(has_issue(errors, "avoidance.strategy", 5)) << errors.format();
  EXPECT_TRUE(has_issue(errors, "course2.colour", 7)) << errors.format();
  EXPECT_TRUE(has_issue(errors, "vision_vote.min_span_s", 8)) << errors.format();
  EXPECT_NE(errors.format().find(f.path()), std::string::npos);
}

TEST(MissionEngines, TheEnginesOwnRulesApply) {
  TempMission f(std::string("avoidance: {bin_width_deg: 7.0}\n"
                            "course2: {target_bearing_deg: 5.0}\n") +
                kCourse3Task);
  ConfigErrors errors;
  (void)load_mission_config(f.path(), errors);
  EXPECT_TRUE(has_issue(errors, "avoidance", 4)) << errors.format();
  EXPECT_TRUE(has_issue(errors, "course2", 5)) << errors.format();
}

TEST(MissionEngines, TaskShapesAreChecked) {
  TempMission f(
      "tasks:\n"
      "  - type: docking\n"  // 2022 style without slips
      "  - type: course1\n"  // no waypoint
      "  - type: hopping\n"
      "    style: course3\n"  // style on a non-docking task
      "    waypoints: [{lat_deg: 35.0, lon_deg: 128.0}, {lat_deg: 35.001, lon_deg: 128.0}]\n");
  ConfigErrors errors;
  (void)load_mission_config(f.path(), errors);
  EXPECT_TRUE(has_issue(errors, "tasks[0].slips", 0)) << errors.format();
  EXPECT_TRUE(has_issue(errors, "tasks[1].waypoints", 0)) << errors.format();
  EXPECT_TRUE(has_issue(errors, "tasks[2].style", 0)) << errors.format();
}

}  // namespace
}  // namespace coxswain::config
