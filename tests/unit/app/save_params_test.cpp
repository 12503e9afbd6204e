// SPDX-License-Identifier: Apache-2.0
// `ctl save-params`: the daemon's parameters in force written back as a vision file and a mission
// file, each of which loads back with the values that were in force.
#include "coxswain/app/save_params.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "coxswain/config/config.hpp"
#include "coxswain/config/vision_config.hpp"
#include "coxswain/mission/tunable_parameters.hpp"
#include "support/testdata.hpp"

namespace coxswain::app {
namespace {

namespace fs = std::filesystem;

class SaveParams : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("coxswain_save_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The `params` answer a daemon sailing the shipped kaboat2026 mission with `in_force` gives.
  static std::string answer_for(const mission::TunableParameters& in_force) {
    nlohmann::json values = nlohmann::json::object();
    for (const mission::TunableSpec& spec : mission::tunable_specs()) {
      values[spec.name] = spec.get(in_force);
    }
    std::ostringstream vision;
    config::write_vision(in_force.vision, vision);
    return nlohmann::json{
        {"ok", true},
        {"parameters", values},
        {"vision_yaml", vision.str()},
        {"mission_file",
         (coxswain::testing::source_dir() / "config/missions/kaboat2026.yaml").string()}}
        .dump();
  }

  fs::path dir_;
};

TEST_F(SaveParams, SavedFilesLoadBackWithTheValuesInForce) {
  config::ConfigErrors errors;
  const config::MissionConfig shipped = config::load_mission_config(
      (coxswain::testing::source_dir() / "config/missions/kaboat2026.yaml").string(), errors);
  ASSERT_TRUE(errors.empty()) << errors.format();
  mission::TunableParameters p{shipped.heading_pid, shipped.clustering, shipped.avoidance,
                               shipped.speed, perception::VisionParams::defaults()};
  // A venue's tuning: a plain value, a nested one, an enumeration and the colour model.
  ASSERT_TRUE(mission::set_tunable(p, "heading_pid.kp_per_deg", 0.0625).empty());
  ASSERT_TRUE(mission::set_tunable(p, "avoidance.score.goal_weight", 2.375).empty());
  const double policy = mission::find_tunable("avoidance.all_blocked")->get(p);
  ASSERT_TRUE(mission::set_tunable(p, "avoidance.all_blocked", 1.0 - policy).empty());
  ASSERT_TRUE(mission::set_tunable(p, "vision.blue.h_min", 104).empty());
  p.vision.background.reject_sigma = 3.75;  // carried whole, not only the named values

  const fs::path vision_out = dir_ / "vision.yaml";
  const fs::path mission_out = dir_ / "mission.yaml";
  ASSERT_EQ(save_params(answer_for(p), vision_out, mission_out), "");

  const auto vision = config::load_vision_file(vision_out.string(), errors);
  ASSERT_TRUE(vision.has_value()) << errors.format();
  const config::MissionConfig m = config::load_mission_config(mission_out.string(), errors);
  ASSERT_TRUE(errors.empty()) << errors.format();
  const mission::TunableParameters back{m.heading_pid, m.clustering, m.avoidance, m.speed, *vision};
  for (const mission::TunableSpec& spec : mission::tunable_specs()) {
    EXPECT_EQ(spec.get(back), spec.get(p)) << spec.name;
  }
  EXPECT_EQ(vision->background.reject_sigma, 3.75);
  // The rest of the mission is the daemon's file as it was.
  EXPECT_EQ(m.name, shipped.name);
  ASSERT_EQ(m.tasks.size(), shipped.tasks.size());
  EXPECT_EQ(m.docking.open_max_range_m, shipped.docking.open_max_range_m);
}

TEST_F(SaveParams, ARefusedAnswerWritesNothingAndSaysWhy) {
  const std::string problem =
      save_params(R"({"ok": false, "error": "no parameters in force yet"})", dir_ / "v.yaml", {});
  EXPECT_NE(problem.find("no parameters in force yet"), std::string::npos) << problem;
  EXPECT_FALSE(fs::exists(dir_ / "v.yaml"));
}

TEST(MissionWithValues, RefusesTextThatIsNotAMission) {
  std::string error;
  EXPECT_EQ(mission_with_values("kind: boat\n", {{"heading_pid.kp_per_deg", 0.1}}, error), "");
  EXPECT_NE(error.find("mission"), std::string::npos);
}

}  // namespace
}  // namespace coxswain::app
