// SPDX-License-Identifier: Apache-2.0
// Every config file the project ships must load without a single issue (Cartographer's
// configuration_files_test): a shipped file with a typo would otherwise fail on the water.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "coxswain/config/config.hpp"
#include "coxswain/config/vision_config.hpp"
#include "coxswain/config/yaml_reader.hpp"
#include "support/testdata.hpp"

namespace coxswain::config {
namespace {

std::vector<std::filesystem::path> shipped_yaml_files() {
  std::vector<std::filesystem::path> files;
  for (const auto& entry :
       std::filesystem::recursive_directory_iterator(testing::source_dir() / "config")) {
    if (entry.is_regular_file() && entry.path().extension() == ".yaml") {
      files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(ShippedConfigs, EveryFileValidates) {
  const auto files = shipped_yaml_files();
  ASSERT_GE(files.size(), 4U);
  std::size_t checked = 0;
  for (const auto& path : files) {
    ConfigErrors errors;
    const ConfigKind kind = detect_config_kind(path.string(), errors);
    switch (kind) {
      case ConfigKind::kBoat:
        (void)load_boat_config(path.string(), errors);
        break;
      case ConfigKind::kDevices:
        (void)load_devices_config(path.string(), errors);
        break;
      case ConfigKind::kMission:
        (void)load_mission_config(path.string(), errors);
        break;
      case ConfigKind::kVision:
        EXPECT_TRUE(load_vision_file(path.string(), errors).has_value()) << path;
        break;
      case ConfigKind::kCourse:
      case ConfigKind::kSimSensors:
        continue;  // simulator files: validated by the simulator's own tests
      case ConfigKind::kUnknown:
        break;
    }
    EXPECT_TRUE(errors.empty()) << path << ":\n" << errors.format();
    ++checked;
  }
  EXPECT_GE(checked, 4U);
}

TEST(ShippedConfigs, DefaultsAreTheDocumentedOnes) {
  ConfigErrors errors;
  const std::string dir = (testing::source_dir() / "config").string();
  Configuration c{load_boat_config(dir + "/boat.yaml", errors),
                  load_devices_config(dir + "/devices.yaml", errors),
                  load_mission_config(dir + "/missions/kaboat2026.yaml", errors)};
  ASSERT_TRUE(errors.empty()) << errors.format();
  EXPECT_EQ(c.devices.lidar.path, "/dev/ttyLiDAR");
  EXPECT_EQ(c.devices.arduino.failsafe_ms, 300U);
  EXPECT_DOUBLE_EQ(c.mission.tick_rate_hz, 50.0);
  ASSERT_EQ(c.mission.tasks.size(), 3U);
  EXPECT_DOUBLE_EQ(c.mission.tasks[0].time_limit_s, 180.0);
  EXPECT_DOUBLE_EQ(c.boat.mounts.lidar.yaw_deg, 180.0);
  const std::string yaml = to_yaml(c);
  EXPECT_NE(yaml.find("failsafe_ms: 300"), std::string::npos);
  EXPECT_NE(yaml.find("type: course2"), std::string::npos);
  // The printed config is itself valid YAML.
  EXPECT_NO_THROW((void)YAML::Load(yaml));
}

// A mission written out as a file loads back to the same mission: what the simulator's devices
// mode hands the daemon after fitting the mission to its course. Checked on every shipped
// mission, compared through the full configuration text (every key, doubles to the bit).
TEST(ShippedConfigs, EveryMissionWrittenAsAFileLoadsBackTheSame) {
  const std::filesystem::path dir = testing::source_dir() / "config" / "missions";
  const std::filesystem::path out = std::filesystem::temp_directory_path() /
                                    ("coxswain-mission-roundtrip-" + std::to_string(::getpid()));
  std::size_t checked = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".yaml") continue;
    ConfigErrors errors;
    const MissionConfig original = load_mission_config(entry.path().string(), errors);
    ASSERT_TRUE(errors.empty()) << errors.format();
    {
      std::ofstream f(out);
      f << mission_to_yaml(original);
    }
    MissionConfig again = load_mission_config(out.string(), errors);
    ASSERT_TRUE(errors.empty()) << entry.path() << ":\n" << errors.format();
    again.file = original.file;
    Configuration a;
    a.mission = original;
    Configuration b;
    b.mission = again;
    EXPECT_EQ(to_yaml(a), to_yaml(b)) << entry.path();
    ++checked;
  }
  std::filesystem::remove(out);
  EXPECT_GE(checked, 4U);
}

}  // namespace
}  // namespace coxswain::config
