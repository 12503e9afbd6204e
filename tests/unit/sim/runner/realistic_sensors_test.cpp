// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <cmath>

#include "coxswain/core/angles.hpp"
#include "coxswain/perception/camera_pipeline.hpp"
#include "sim/runner/mission_run.hpp"
#include "sim/runner/realistic_sensors.hpp"
#include "sim/sensors/camera_sim.hpp"
#include "sim/world/course.hpp"

namespace coxswain::sim::runner {
namespace {

const std::string kConfig = COXSWAIN_SOURCE_DIR "/config/";

world::Course load_course(const std::string& name) {
  config::ConfigErrors errors;
  world::Course c = world::load_course_file(kConfig + "courses/" + name, errors);
  EXPECT_TRUE(errors.empty()) << errors.format();
  return c;
}

config::Configuration load_config(const std::string& mission) {
  config::ConfigErrors errors;
  config::Configuration c;
  c.boat = config::load_boat_config(kConfig + "boat.yaml", errors);
  c.devices = config::load_devices_config(kConfig + "devices.yaml", errors);
  c.mission = config::load_mission_config(kConfig + "missions/" + mission, errors);
  EXPECT_TRUE(errors.empty()) << errors.format();
  return c;
}

TEST(ToBoatTruth, CarriesEveryFieldWithTheBodyOriginsVelocity) {
  dynamics::TruthState t;
  t.pose = {{1.0, 2.0}, 90.0};  // heading east
  t.cg = {1.0, 1.5};            // 0.5 m aft of the bow
  t.yaw_rate_dps = 10.0;
  t.accel_forward_mps2 = 0.2;
  t.accel_starboard_mps2 = -0.3;
  t.vel_north_mps = 0.1;
  t.vel_east_mps = 1.5;
  const sensors::BoatTruth b = to_boat_truth(t);
  EXPECT_EQ(b.pose.position.north_m, 1.0);
  EXPECT_EQ(b.pose.position.east_m, 2.0);
  EXPECT_EQ(b.pose.heading_deg, 90.0);
  EXPECT_EQ(b.yaw_rate_dps, 10.0);
  EXPECT_EQ(b.accel_forward_mps2, 0.2);
  EXPECT_EQ(b.accel_starboard_mps2, -0.3);
  // Turning to starboard, the bow (0.5 m ahead of the centre) swings south at r * 0.5 m.
  const double swing = core::deg_to_rad(10.0) * 0.5;
  EXPECT_NEAR(b.vel_north_mps, 0.1 - swing, 1e-12);
  EXPECT_NEAR(b.vel_east_mps, 1.5, 1e-12);
  EXPECT_NEAR(b.surge_mps, 1.5, 1e-12);
  EXPECT_NEAR(b.sway_mps, swing - 0.1, 1e-12);
}

// From each 2022 docking decision point, facing the slip, the daemon's camera pipeline finds the
// slip's own marker (colour and shape) near the bow.
TEST(RealisticSensors, DockMarkersSeenFromTheDecisionPoints) {
  const world::Course course = load_course("kaboat2022_docking.yaml");
  const config::Configuration config = load_config("docking.yaml");
  const sensors::SensorConfig s = fitted_sensor_config({}, course.world, config, 1);
  sensors::CameraSim camera(s.camera, course.world);
  perception::CameraPipeline pipeline(perception::VisionParams::defaults(),
                                      config.devices.camera.hfov_deg, config.boat.mounts.camera);
  ASSERT_FALSE(course.world.docks.empty());
  for (const auto& dock : course.world.docks) {
    const double h = core::deg_to_rad(dock.entry_heading_deg);
    const double back = config.mission.docking.decision_distance_m;
    const core::NavPose pose{
        {dock.entrance.north_m - back * std::cos(h), dock.entrance.east_m - back * std::sin(h)},
        dock.entry_heading_deg};
    cv::Mat frame;
    camera.render(pose, frame);
    msg::CameraDetections det;
    ASSERT_TRUE(pipeline.process(frame, 0, det));
    bool found = false;
    for (std::uint32_t i = 0; i < det.count; ++i) {
      const auto& d = det.detections[i];
      if (d.colour == dock.marker.colour && d.shape == dock.marker.shape &&
          std::abs(static_cast<double>(d.bearing_deg)) < config.mission.docking.marker_window_deg) {
        found = true;
      }
    }
    EXPECT_TRUE(found) << dock.name << ": " << det.count << " detections";
  }
}

TEST(FitMission, TakesTheCourseGeometry) {
  const world::Course course = load_course("kaboat2022_obstacle_final.yaml");
  const config::Configuration config = load_config("obstacle_course.yaml");
  const config::MissionConfig m = fit_mission_to_course(config.mission, course.world);
  ASSERT_EQ(m.tasks.size(), 1U);
  // Through the centre of every gate in order (the task ends on crossing the last).
  const auto& gates = course.world.gates;
  ASSERT_FALSE(gates.empty());
  ASSERT_EQ(m.tasks[0].waypoints.size(), gates.size());
  const core::LocalFrame frame(course.world.origin);
  for (std::size_t i = 0; i < gates.size(); ++i) {
    const core::NavPoint c = frame.to_nav(m.tasks[0].waypoints[i]);
    EXPECT_NEAR(c.north_m, (gates[i].left.north_m + gates[i].right.north_m) / 2.0, 1e-3);
    EXPECT_NEAR(c.east_m, (gates[i].left.east_m + gates[i].right.east_m) / 2.0, 1e-3);
  }
  const core::NavPoint goal = frame.to_nav(m.tasks[0].waypoints.back());
  // The finish gate is at north 40 m, centred on east 0; the course runs north.
  EXPECT_NEAR(goal.north_m, 40.0, 1e-3);
  EXPECT_NEAR(goal.east_m, 0.0, 1e-3);
  // The engine parameters are untouched.
  EXPECT_EQ(m.avoidance.strategy, config.mission.avoidance.strategy);
}

}  // namespace
}  // namespace coxswain::sim::runner
