// SPDX-License-Identifier: Apache-2.0
#include "sim/sensors/sensor_config.hpp"

#include <gtest/gtest.h>

#include <string>

namespace coxswain::sim::sensors {
namespace {

TEST(SensorConfig, SampleFileLoadsWithEveryKeyKnown) {
  config::ConfigErrors errors;
  const std::string path = std::string(COXSWAIN_SOURCE_DIR) + "/config/sim/sensors.yaml";
  const std::optional<SensorConfig> c = load_sensor_config_file(path, errors);
  ASSERT_TRUE(c.has_value()) << errors.format();
  EXPECT_FALSE(c->validate().has_value());
  EXPECT_EQ(c->lidar.beams_per_revolution(), 800);
  EXPECT_DOUBLE_EQ(c->lidar.mount.yaw_deg, 180.0);
  EXPECT_DOUBLE_EQ(c->gnss.mount.x_m, -0.6);
  EXPECT_EQ(c->gnss.rtk, RtkMode::kOff);
  ASSERT_EQ(c->imu.disturbances.size(), 1U);
  EXPECT_DOUBLE_EQ(c->imu.disturbances[0].offset_deg, 12.0);
  EXPECT_DOUBLE_EQ(c->camera.hfov_deg, 80.0);
  // Per-sensor seeds differ (derived from the master seed).
  EXPECT_NE(c->lidar.seed, c->gnss.seed);
  EXPECT_NE(c->imu.seed, c->camera.seed);
}

TEST(SensorConfig, ErrorsNameTheKeyAndLine) {
  const YAML::Node root = YAML::Load(
      "sensors:\n"
      "  lidar:\n"
      "    model: a3\n"
      "    rat_hz: 5\n"
      "  gnss:\n"
      "    rtk: maybe\n"
      "  camera:\n"
      "    blur_kernel_px: 4\n");
  config::ConfigErrors errors;
  config::MapReader top(root, "test.yaml", "", errors);
  std::optional<config::MapReader> block = top.map("sensors", true);
  ASSERT_TRUE(block.has_value());
  const SensorConfig c = load_sensor_config(*block);
  const std::string text = errors.format();
  EXPECT_NE(text.find("sensors.lidar.rat_hz"), std::string::npos) << text;
  EXPECT_NE(text.find("test.yaml:4"), std::string::npos) << text;
  EXPECT_NE(text.find("sensors.gnss.rtk"), std::string::npos) << text;
  EXPECT_NE(text.find("blur_kernel_px"), std::string::npos) << text;
  EXPECT_EQ(c.lidar.model, LidarModel::kA3);
  EXPECT_DOUBLE_EQ(c.lidar.max_range_m, 25.0);
}

TEST(SensorConfig, NodeOverloadAndDefaults) {
  config::ConfigErrors errors;
  const SensorConfig c =
      load_sensor_config(YAML::Load("seed: 9\nimu: {rate_hz: 50}\n"), "inline.yaml", errors);
  EXPECT_TRUE(errors.empty()) << errors.format();
  EXPECT_EQ(c.seed, 9U);
  EXPECT_DOUBLE_EQ(c.imu.rate_hz, 50.0);
  EXPECT_FALSE(c.validate().has_value());
  EXPECT_EQ(c.lidar.model, LidarModel::kA2M8);
  EXPECT_EQ(c.imu.seed, derive_seed(9, 3));
}

TEST(SensorConfig, ValidateRejectsBadValues) {
  SensorConfig c;
  EXPECT_FALSE(c.validate().has_value());
  c.gnss.bias_mean_m = 12.0;  // above bias_max_m
  EXPECT_TRUE(c.validate().has_value());
  c = SensorConfig{};
  c.imu.declination_deg = 100.0;
  EXPECT_TRUE(c.validate().has_value());
  c = SensorConfig{};
  c.camera.blur_kernel_px = 4;
  EXPECT_TRUE(c.validate().has_value());
  c = SensorConfig{};
  c.lidar.spurious_max_range_m = 50.0;
  EXPECT_TRUE(c.validate().has_value());
}

TEST(SensorConditions, ACourseFilesValuesWinAndTheOthersAreLeftAlone) {
  SensorConfig c;
  // What the batch's drawn disturbances set for a seed.
  c.gnss.bias_mean_m = 3.0;
  c.gnss.bias_direction_deg = 40.0;
  c.gnss.bias_max_m = 5.0;
  world::SensorConditions k;
  k.gnss_bias_mean_m = 8.0;
  k.camera_glare = true;
  k.camera_sun_bearing_deg = 270.0;
  k.camera_venue = "harbour";
  apply_conditions(k, c);
  EXPECT_EQ(c.camera.venue, Venue::kHarbour);
  EXPECT_DOUBLE_EQ(c.gnss.bias_mean_m, 8.0);
  EXPECT_DOUBLE_EQ(c.gnss.bias_direction_deg, 40.0);  // not given by the course: kept
  // A course bias is not clamped by another source's cap.
  EXPECT_DOUBLE_EQ(c.gnss.bias_max_m, 8.0 + 2.0 * c.gnss.bias_wander_sigma_m);
  EXPECT_TRUE(c.camera.glare);
  EXPECT_DOUBLE_EQ(c.camera.sun_bearing_deg, 270.0);
  EXPECT_FALSE(c.validate().has_value());
  k.gnss_bias_max_m = 9.0;
  apply_conditions(k, c);
  EXPECT_DOUBLE_EQ(c.gnss.bias_max_m, 9.0);
}

// A course file names the venue by the camera's own names: every one of them is a preset.
TEST(SensorConditions, EveryVenueACourseFileMayNameIsACameraPreset) {
  for (const char* name : {"pool", "harbour", "overcast", "low_sun"}) {
    ASSERT_TRUE(parse_venue(name).has_value()) << name;
    SensorConfig c;
    world::SensorConditions k;
    k.camera_venue = name;
    apply_conditions(k, c);
    EXPECT_EQ(venue_name(c.camera.venue), name);
  }
}

}  // namespace
}  // namespace coxswain::sim::sensors
