// SPDX-License-Identifier: Apache-2.0
// The real mission core (MissionPilot) with the realistic simulated sensors and the camera
// pipeline, sailed in lockstep on the shipped courses with the shipped mission files.
#include <gtest/gtest.h>

#include <string>

#include "sim/runner/mission_run.hpp"
#include "sim/world/course.hpp"

namespace coxswain::sim::runner {
namespace {

const std::string kConfig = COXSWAIN_SOURCE_DIR "/config/";

struct Scenario {
  world::Course course;
  config::Configuration config;
};

Scenario load(const std::string& course_file, const std::string& mission_file) {
  config::ConfigErrors errors;
  Scenario s;
  s.course = world::load_course_file(kConfig + "courses/" + course_file, errors);
  s.config.boat = config::load_boat_config(kConfig + "boat.yaml", errors);
  s.config.devices = config::load_devices_config(kConfig + "devices.yaml", errors);
  s.config.mission = config::load_mission_config(kConfig + "missions/" + mission_file, errors);
  EXPECT_TRUE(errors.empty()) << errors.format();
  s.config.mission = fit_mission_to_course(s.config.mission, s.course.world);
  return s;
}

MissionRunOptions options_for(std::uint64_t seed) {
  config::ConfigErrors errors;
  MissionRunOptions o;
  o.seed = seed;
  const auto sensors = sensors::load_sensor_config_file(kConfig + "sim/sensors.yaml", errors);
  EXPECT_TRUE(sensors.has_value()) << errors.format();
  if (sensors) o.sensors = *sensors;
  o.max_time_s = 400.0;
  return o;
}

std::string describe(const MissionRunResult& r) {
  std::string text = result_json(r, 0).dump();
  return text.substr(0, 3000);
}

TEST(Scenario, HoppingCompletesTheKaboat2022Tour) {
  const Scenario s = load("kaboat2022_hopping.yaml", "hopping.yaml");
  for (std::uint64_t seed : {1U, 2U}) {
    const MissionRunResult r = run_mission(s.course, s.config, options_for(seed));
    EXPECT_TRUE(r.passed) << "seed " << seed << ": " << describe(r);
    EXPECT_EQ(r.outcome.score.collisions, 0) << describe(r);
    // The judge counts the last waypoint (half the hull in its 2 m circle) before the core's own
    // arrival radius is reached at the antenna, which ends the run.
    EXPECT_GE(r.status.waypoints_arrived, 3U);
    EXPECT_EQ(r.status.waypoints_missed, 0U);
    EXPECT_TRUE(r.status.gps_calibrated);
  }
}

TEST(Scenario, ObstacleCoursePreliminaryPassesTheFinishGate) {
  const Scenario s = load("kaboat2022_obstacle_preliminary.yaml", "obstacle_course.yaml");
  const MissionRunResult r = run_mission(s.course, s.config, options_for(1));
  EXPECT_TRUE(r.passed) << describe(r);
  EXPECT_FALSE(r.status.holding);
}

TEST(Scenario, ObstacleCourseFinalPassesTheFinishGate) {
  const Scenario s = load("kaboat2022_obstacle_final.yaml", "obstacle_course.yaml");
  const MissionRunResult r = run_mission(s.course, s.config, options_for(1));
  EXPECT_TRUE(r.passed) << describe(r);
}

// The whole stack (sensor noise, camera, core, firmware, dynamics) is deterministic: the same seed
// gives a bit-identical trajectory; another seed a different one.
TEST(Scenario, SameSeedSameTrajectory) {
  const Scenario s = load("kaboat2022_obstacle_preliminary.yaml", "obstacle_course.yaml");
  const MissionRunResult a = run_mission(s.course, s.config, options_for(7));
  const MissionRunResult b = run_mission(s.course, s.config, options_for(7));
  const MissionRunResult c = run_mission(s.course, s.config, options_for(8));
  EXPECT_EQ(a.outcome.trajectory_hash, b.outcome.trajectory_hash);
  EXPECT_EQ(a.outcome.steps, b.outcome.steps);
  EXPECT_EQ(a.transitions.size(), b.transitions.size());
  EXPECT_NE(a.outcome.trajectory_hash, c.outcome.trajectory_hash);
}

// GNSS silent mid-tour: hold within 0.5 s of sim time, resume when fixes come back, and still
// finish the tour.
TEST(Scenario, GnssSilenceHoldsAndResumes) {
  const Scenario s = load("kaboat2022_hopping.yaml", "hopping.yaml");
  MissionRunOptions o = options_for(1);
  o.outages.push_back({.gnss = true, .lidar = false, .from_s = 20.0, .to_s = 26.0});
  const MissionRunResult r = run_mission(s.course, s.config, o);
  ASSERT_EQ(r.hold_delay_s.size(), 1U);
  EXPECT_GE(r.hold_delay_s[0], 0.0) << "never held: " << describe(r);
  EXPECT_LE(r.hold_delay_s[0], 0.5);
  EXPECT_TRUE(r.resumed[0]) << describe(r);
  EXPECT_TRUE(r.passed) << describe(r);
  bool gnss_hold = false;
  for (const auto& t : r.transitions) gnss_hold = gnss_hold || t.to.starts_with("hold");
  EXPECT_TRUE(gnss_hold);
}

// Lidar silent in the obstacle field: hold within 0.5 s, resume, finish. (A silence from 15 to
// 19 s lets the coasting hull touch the field's wall; with collision response it then stays
// against it, since the reactive avoidance stops when every direction is blocked: a recovery
// the planner's no-path behaviour covers, not what this test is about.)
TEST(Scenario, LidarSilenceHoldsAndResumes) {
  const Scenario s = load("kaboat2022_obstacle_preliminary.yaml", "obstacle_course.yaml");
  MissionRunOptions o = options_for(1);
  o.outages.push_back({.gnss = false, .lidar = true, .from_s = 12.0, .to_s = 16.0});
  const MissionRunResult r = run_mission(s.course, s.config, o);
  ASSERT_EQ(r.hold_delay_s.size(), 1U);
  EXPECT_GE(r.hold_delay_s[0], 0.0) << "never held: " << describe(r);
  EXPECT_LE(r.hold_delay_s[0], 0.5);
  EXPECT_TRUE(r.resumed[0]) << describe(r);
  EXPECT_TRUE(r.passed) << describe(r);
}

}  // namespace
}  // namespace coxswain::sim::runner
