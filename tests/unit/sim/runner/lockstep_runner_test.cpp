// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "coxswain/core/angles.hpp"
#include "coxswain/core/geodesy.hpp"
#include "sim/runner/ideal_sensors.hpp"
#include "sim/runner/lockstep_runner.hpp"
#include "sim/world/generator.hpp"
#include "support/testdata.hpp"

namespace coxswain::sim::runner {
namespace {

// Plays a fixed pulse pair, changing to a second pair at `switch_s`.
class ScriptedPilot final : public Pilot {
 public:
  ScriptedPilot(std::array<std::uint16_t, 2> first, std::array<std::uint16_t, 2> second,
                double switch_s)
      : first_(first), second_(second), switch_ns_(core::sec_to_ns(switch_s)) {}
  void step(const core::Snapshot& /*snapshot*/, core::TimeNs now_ns,
            msg::ActuatorCommand& out) override {
    out.pulse_us = now_ns < switch_ns_ ? first_ : second_;
    out.active = true;
  }

 private:
  std::array<std::uint16_t, 2> first_;
  std::array<std::uint16_t, 2> second_;
  core::TimeNs switch_ns_;
};

// An open field without goals: nothing ends the run but max_time_s.
world::Course open_water() {
  world::Course c;
  c.world.name = "open";
  c.world.kind = world::CourseKind::kObstacle;
  c.world.origin = {35.0695, 128.828, 0.0};
  return c;
}

world::Course shipped(const std::string& name) {
  config::ConfigErrors errors;
  world::Course c = world::load_course_file(
      (testing::source_dir() / "config" / "courses" / name).string(), errors);
  EXPECT_TRUE(errors.empty()) << errors.format();
  return c;
}

TEST(LockstepRunner, ScriptedCommandsMoveTheBoatExactlyAsTheDynamicsPredict) {
  const world::Course course = open_water();
  const config::BoatConfig boat;
  RunnerOptions options;
  options.max_time_s = 60.0;
  const dynamics::DynamicsParams p = dynamics::make_params(boat, course.dynamics);
  {
    // Straight ahead for a minute: the hand-computed terminal speed, thrust = d_u u + d_uu u^2.
    ScriptedPilot pilot({1500, 1725}, {1500, 1725}, 0.0);
    LockstepRunner runner(course, boat, options, nullptr, &pilot);
    const RunOutcome out = runner.run();
    EXPECT_EQ(out.steps, 6000U);
    EXPECT_EQ(out.end_ns, 60 * core::kNsPerSec);
    const double thrust = 0.25 * p.thrust_fwd_max_n;
    const double u = (-p.d_u + std::sqrt(p.d_u * p.d_u + 4.0 * p.d_uu * thrust)) / (2.0 * p.d_uu);
    EXPECT_NEAR(runner.truth().u_mps, u, 1e-6);
    EXPECT_NEAR(runner.truth().pose.position.east_m, 0.0, 1e-9);
    // Distance run: terminal speed for the whole time less what the start-up cost.
    EXPECT_GT(runner.truth().pose.position.north_m, u * 60.0 - 5.0);
    EXPECT_LT(runner.truth().pose.position.north_m, u * 60.0);
  }
  // A sequence: straight for 20 s, then hard to starboard with more thrust. The pilot's tick,
  // the driver's command slot and the firmware all fall on the 20 s step, so the model driven
  // directly with the same pulses at the same step must end bit-identical.
  ScriptedPilot pilot({1500, 1725}, {1900, 1800}, 20.0);
  LockstepRunner runner(course, boat, options, nullptr, &pilot);
  (void)runner.run();
  dynamics::BoatModel model(boat, p, {}, options.seed);
  model.reset(course.world.start);
  model.set_pulses({1500, 1725});
  for (int i = 0; i < 2000; ++i) model.step();
  model.set_pulses({1900, 1800});
  for (int i = 2000; i < 6000; ++i) model.step();
  EXPECT_EQ(runner.boat().state().north_m, model.state().north_m);
  EXPECT_EQ(runner.boat().state().east_m, model.state().east_m);
  EXPECT_EQ(runner.boat().state().psi_rad, model.state().psi_rad);
  EXPECT_EQ(runner.boat().state().r_radps, model.state().r_radps);
  EXPECT_GT(runner.truth().yaw_rate_dps, 5.0);  // and it is turning to starboard
}

TEST(LockstepRunner, AHullDrivenAtAWallStopsThereCountsOneContactAndEndsPinned) {
  world::Course course = open_water();
  course.world.walls.push_back({{{8.0, -10.0}, {8.0, 10.0}}, 0.5});
  course.world.gates.push_back({"finish", {20.0, -1.5}, {20.0, 1.5}});
  const config::BoatConfig boat;
  RunnerOptions options;
  options.max_time_s = 120.0;
  ScriptedPilot pilot({1500, 1900}, {1500, 1900}, 0.0);  // full ahead throughout
  LockstepRunner runner(course, boat, options, nullptr, &pilot);
  double furthest_bow_n = -1e9;
  while (runner.step()) {
    furthest_bow_n =
        std::max(furthest_bow_n, runner.truth().pose.position.north_m + boat.hull.bow_overhang_m);
  }
  const RunOutcome out = runner.run();
  EXPECT_LE(furthest_bow_n, 8.0 + 1e-9);  // never through the wall
  EXPECT_NEAR(runner.truth().pose.position.north_m + boat.hull.bow_overhang_m, 8.0, 1e-3);
  EXPECT_EQ(out.score.collisions, 1);  // one touch, held: one contact
  EXPECT_TRUE(out.score.pinned);
  EXPECT_FALSE(out.score.completed);
  EXPECT_LT(core::ns_to_sec(out.end_ns), 60.0);  // ended by the pinned rule, not max_time_s
}

TEST(LockstepRunner, WithoutCollisionResponseTheHullPassesThroughAsBefore) {
  world::Course course = open_water();
  course.world.walls.push_back({{{8.0, -10.0}, {8.0, 10.0}}, 0.5});
  const config::BoatConfig boat;
  RunnerOptions options;
  options.max_time_s = 30.0;
  options.collision_response = false;
  ScriptedPilot pilot({1500, 1900}, {1500, 1900}, 0.0);
  LockstepRunner runner(course, boat, options, nullptr, &pilot);
  (void)runner.run();
  EXPECT_GT(runner.truth().cg.north_m, 12.0);
}

TEST(LockstepRunner, SameSeedGivesTheSameTrajectoryBitForBit) {
  const world::Course course = shipped("kaboat2022_obstacle_final.yaml");  // waves and current
  world::Course windy = course;
  windy.environment.wind_speed_mps = 3.0;
  windy.environment.gust_std_mps = 1.5;
  const config::BoatConfig boat;
  auto hash_of = [&](std::uint64_t seed) {
    ScriptedPilot pilot({1650, 1800}, {1400, 1700}, 8.0);
    IdealSensorSuite sensors(windy.world.origin, boat);
    RunnerOptions options;
    options.seed = seed;
    options.max_time_s = 20.0;
    LockstepRunner runner(windy, boat, options, &sensors, &pilot);
    return runner.run().trajectory_hash;
  };
  const std::uint64_t a = hash_of(3);
  EXPECT_EQ(a, hash_of(3));
  EXPECT_NE(a, hash_of(4));
}

TEST(LockstepRunner, CutLinkTripsTheFirmwareFailsafeAfter300ms) {
  const world::Course course = open_water();
  const config::BoatConfig boat;
  ScriptedPilot pilot({1500, 1800}, {1500, 1800}, 0.0);
  RunnerOptions options;
  options.max_time_s = 30.0;
  LockstepRunner runner(course, boat, options, nullptr, &pilot);
  while (runner.now_ns() < 10 * core::kNsPerSec) runner.step();
  EXPECT_EQ(runner.arduino_outputs().pulse_us[1], 1800);
  runner.set_command_link(false);  // the last command reached the firmware at 9.95 s
  while (runner.now_ns() < core::sec_to_ns(10.2)) runner.step();
  EXPECT_EQ(runner.arduino_outputs().pulse_us[1], 1800);
  while (runner.now_ns() < core::sec_to_ns(10.3)) runner.step();
  EXPECT_EQ(runner.arduino_outputs().pulse_us[1], 1500);
  EXPECT_TRUE(runner.arduino_outputs().failsafe);
  while (runner.now_ns() < core::sec_to_ns(10.5)) runner.step();
  EXPECT_TRUE(runner.store().arduino.read().value.failsafe);
  const double speed_at_cut = runner.truth().u_mps;
  while (runner.now_ns() < core::sec_to_ns(25.0)) runner.step();
  EXPECT_LT(runner.truth().u_mps, 0.2 * speed_at_cut);  // coasting to a stop
  runner.set_command_link(true);
  while (runner.now_ns() < core::sec_to_ns(25.2)) runner.step();
  EXPECT_EQ(runner.arduino_outputs().pulse_us[1], 1800);
}

// A heading hold (PD on the IMU heading and yaw rate the ideal sensors publish): proves the loop
// closes. (Plain P leaves a +-3.5 deg limit cycle: the stern actuator acts late.)
class HeadingHoldPilot final : public Pilot {
 public:
  explicit HeadingHoldPilot(double heading_deg) : heading_deg_(heading_deg) {}
  void step(const core::Snapshot& snapshot, core::TimeNs /*now_ns*/,
            msg::ActuatorCommand& out) override {
    out.active = true;
    out.pulse_us[1] = 1725;
    if (!snapshot.imu.valid()) {
      out.pulse_us[0] = 1500;
      return;
    }
    const double error = core::angle_diff_deg(heading_deg_, snapshot.imu.value.heading_deg);
    const double rate_dps = snapshot.imu.value.gyro_dps[2];
    const double servo = std::clamp(1500.0 + 16.0 * error - 12.0 * rate_dps, 1100.0, 1900.0);
    out.pulse_us[0] = static_cast<std::uint16_t>(std::lround(servo));
  }

 private:
  double heading_deg_;
};

TEST(LockstepRunner, HeadingHoldOnTheSimulatedImuTurnsAndHolds) {
  const world::Course course = open_water();
  const config::BoatConfig boat;
  HeadingHoldPilot pilot(90.0);
  IdealSensorSuite sensors(course.world.origin, boat);
  RunnerOptions options;
  options.max_time_s = 30.0;
  LockstepRunner runner(course, boat, options, &sensors, &pilot);
  (void)runner.run();
  EXPECT_NEAR(runner.truth().pose.heading_deg, 90.0, 2.0);
  EXPECT_GT(runner.truth().pose.position.east_m, 15.0);
}

// A waypoint follower on the simulated GNSS and IMU: bearing to the next waypoint, heading P.
class WaypointPilot final : public Pilot {
 public:
  explicit WaypointPilot(const world::World& world)
      : frame_(world.origin), waypoints_(world.waypoints) {}
  void step(const core::Snapshot& s, core::TimeNs /*now_ns*/, msg::ActuatorCommand& out) override {
    out.active = true;
    out.pulse_us = {1500, 1500};
    if (!s.imu.valid() || !s.gnss.valid() || next_ >= waypoints_.size()) return;
    const double heading = s.imu.value.heading_deg;
    const core::NavPoint antenna = frame_.to_nav({s.gnss.value.lat_deg, s.gnss.value.lon_deg, 0.0});
    // The GNSS sits at mid-length (boat.yaml): steer the boat's middle onto the waypoint.
    const core::NavPoint middle = antenna;
    const core::NavPoint goal = waypoints_[next_].position;
    if (core::distance_m(middle, goal) < 0.8) ++next_;
    if (next_ >= waypoints_.size()) return;
    const double bearing = core::bearing_deg(middle, waypoints_[next_].position);
    const double error = core::angle_diff_deg(bearing, heading);
    out.pulse_us[0] =
        static_cast<std::uint16_t>(std::lround(std::clamp(1500.0 + 16.0 * error, 1100.0, 1900.0)));
    // Slow down for sharp turns and near the goal.
    const double dist = core::distance_m(middle, waypoints_[next_].position);
    const double fwd = std::abs(error) > 45.0 ? 1650.0 : (dist < 4.0 ? 1700.0 : 1780.0);
    out.pulse_us[1] = static_cast<std::uint16_t>(fwd);
  }

 private:
  core::LocalFrame frame_;
  std::vector<world::Waypoint> waypoints_;
  std::size_t next_ = 0;
};

TEST(LockstepRunner, WaypointFollowerCompletesTheShippedHoppingTour) {
  const world::Course course = shipped("kaboat2022_hopping.yaml");
  const config::BoatConfig boat;
  WaypointPilot pilot(course.world);
  IdealSensorSuite sensors(course.world.origin, boat);
  RunnerOptions options;
  LockstepRunner runner(course, boat, options, &sensors, &pilot);
  const RunOutcome out = runner.run();
  EXPECT_TRUE(out.score.completed) << to_json(out.score).dump(2);
  EXPECT_EQ(out.score.collisions, 0);
  EXPECT_EQ(out.score.waypoints.size(), 4U);
  EXPECT_LT(out.score.elapsed_s, 200.0);
  EXPECT_DOUBLE_EQ(out.score.score_s, out.score.elapsed_s);
  const std::string svg =
      scoring::trajectory_svg(course.world, boat.hull, runner.path(), &out.score);
  EXPECT_NE(svg.find("class=\"path\""), std::string::npos);
  if (const char* dir = std::getenv("COXSWAIN_SIM_TEST_OUTPUT")) {
    std::ofstream(std::string(dir) + "/hopping.svg") << svg;
    std::ofstream(std::string(dir) + "/hopping.json") << to_json(out.score).dump(2);
  }
}

}  // namespace
}  // namespace coxswain::sim::runner
