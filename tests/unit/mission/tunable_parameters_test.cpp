// SPDX-License-Identifier: Apache-2.0
// The live-tunable parameters: the named table (ranges, whole numbers, the engines' own checks)
// and the core's hand-over between steps (MissionCore::apply_parameters): a new heading gain,
// avoidance range, speed schedule or HSV box is in force on the next step, a bad set changes
// nothing.
#include "coxswain/mission/tunable_parameters.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <set>
#include <string>

#include "coxswain/config/config.hpp"
#include "mission_rig.hpp"

namespace coxswain::mission::test {
namespace {

static_assert(std::is_trivially_copyable_v<TunableParameters>);

config::Configuration hopping(double north_m = 30.0) {
  config::Configuration c = base_config(config::TaskType::kHopping);
  const core::LocalFrame f(c.mission.origin);
  c.mission.tasks[0].waypoints.push_back(f.to_geo(core::NavPoint{north_m, 0.0}));
  return c;
}

TEST(TunableParameters, RangesWholeNumbersAndTheEnginesChecks) {
  TunableParameters p;
  const double kp = p.heading_pid.kp_per_deg;
  EXPECT_EQ(set_tunable(p, "heading_pid.kp_per_deg", 0.05), "");
  EXPECT_DOUBLE_EQ(p.heading_pid.kp_per_deg, 0.05);
  EXPECT_NE(kp, 0.05);
  EXPECT_NE(set_tunable(p, "heading_pid.kp_per_deg", 5.0).find("within"), std::string::npos);
  EXPECT_NE(set_tunable(p, "heading_pid.kp_per_deg", -1.0), "");
  EXPECT_NE(set_tunable(p, "heading_pid.kp_per_deg", std::nan("")), "");
  EXPECT_DOUBLE_EQ(p.heading_pid.kp_per_deg, 0.05);  // unchanged by the refusals
  EXPECT_NE(set_tunable(p, "no.such", 1.0).find("unknown"), std::string::npos);
  EXPECT_NE(set_tunable(p, "clustering.min_group_points", 2.5).find("whole"), std::string::npos);
  EXPECT_EQ(set_tunable(p, "clustering.min_group_points", 6.0), "");
  EXPECT_EQ(p.clustering.min_group_points, 6U);
  // Avoidance: the engine's own cross-checks apply (minimum range above the detection range).
  EXPECT_EQ(set_tunable(p, "avoidance.clearance_m", 0.6), "");
  EXPECT_DOUBLE_EQ(p.avoidance.clearance_m, 0.6);
  EXPECT_EQ(set_tunable(p, "avoidance.strategy", 2.0), "");
  EXPECT_EQ(p.avoidance.strategy, guidance::Strategy::kRiskBin);
  EXPECT_NE(set_tunable(p, "avoidance.strategy", 3.0), "");  // the 2022 defects: never live
  EXPECT_NE(set_tunable(p, "avoidance.min_detection_range_m", 20.0).find("avoidance"),
            std::string::npos);
  // Speed schedule: its own checks too.
  EXPECT_EQ(set_tunable(p, "speed.max_thrust_frac", 0.8), "");
  EXPECT_DOUBLE_EQ(p.speed.max_thrust_frac, 0.8);
  EXPECT_NE(set_tunable(p, "speed.min_thrust_frac", 0.9).find("speed"), std::string::npos);
  // HSV: per colour, OpenCV's 8-bit ranges.
  const int found = p.vision.find_colour(msg::Colour::kRed);
  ASSERT_GE(found, 0);
  const auto red = static_cast<std::size_t>(found);
  EXPECT_EQ(set_tunable(p, "vision.red.s_min", 120.0), "");
  EXPECT_EQ(p.vision.colours[red].hsv.s_min, 120);
  EXPECT_NE(set_tunable(p, "vision.red.h_max", 180.0).find("within"), std::string::npos);
  EXPECT_NE(set_tunable(p, "vision.red.s_max", 100.0).find("s_min > s_max"), std::string::npos);
  EXPECT_EQ(p.vision.colours[red].hsv.s_max, 255);
}

TEST(TunableParameters, EveryGroupIsNamedOnceAndEveryShippedMissionLiesInTheRanges) {
  std::set<std::string> names;
  std::set<TunableGroup> groups;
  for (const TunableSpec& spec : tunable_specs()) {
    EXPECT_TRUE(names.insert(spec.name).second) << spec.name << " twice";
    groups.insert(spec.group);
    EXPECT_EQ(find_tunable(spec.name), &spec);
  }
  EXPECT_EQ(groups.size(), 5U);
  for (const char* colour : {"red", "orange", "yellow", "green", "blue", "purple", "black"}) {
    EXPECT_NE(find_tunable(std::string("vision.") + colour + ".h_min"), nullptr) << colour;
  }
  const std::filesystem::path dir = std::filesystem::path(COXSWAIN_SOURCE_DIR) / "config";
  for (const auto& entry : std::filesystem::directory_iterator(dir / "missions")) {
    config::ConfigErrors errors;
    const config::Configuration c{
        config::load_boat_config((dir / "boat.yaml").string(), errors),
        config::load_devices_config((dir / "devices.yaml").string(), errors),
        config::load_mission_config(entry.path().string(), errors)};
    ASSERT_TRUE(errors.empty()) << errors.format();
    MissionCore core(c.boat, c.mission);
    TunableParameters p = core.parameters();
    for (const TunableSpec& spec : tunable_specs()) {
      const double v = spec.get(p);
      EXPECT_EQ(check_tunable(spec, v), "") << entry.path().filename() << ": " << spec.name;
      EXPECT_EQ(set_tunable(p, spec.name, v), "") << spec.name;
    }
    EXPECT_EQ(core.apply_parameters(p), "") << entry.path().filename();
  }
}

TEST(MissionCoreParameters, TheAvoidanceKeepsClearTheHullOfTheBoatFile) {
  config::Configuration hop = hopping();
  hop.boat.hull = {2.0, 1.1, 0.3};  // length, beam, bow overhang
  MissionCore core(hop.boat, hop.mission);
  EXPECT_DOUBLE_EQ(core.parameters().avoidance.half_beam_m, 0.55);
  EXPECT_DOUBLE_EQ(core.parameters().avoidance.hull_length_m, 2.0);
  EXPECT_DOUBLE_EQ(core.parameters().avoidance.bow_ahead_m, 0.3);
}

TEST(MissionCoreParameters, ApplyRejectsInvalidSetsAndKeepsTheOldOne) {
  const config::Configuration hop = hopping();
  MissionCore core(hop.boat, hop.mission);
  TunableParameters p = core.parameters();
  const double kp = p.heading_pid.kp_per_deg;
  p.heading_pid.kp_per_deg = -1.0;
  EXPECT_NE(core.apply_parameters(p), "");
  EXPECT_DOUBLE_EQ(core.parameters().heading_pid.kp_per_deg, kp);
  p = core.parameters();
  p.clustering.min_group_points = 0;
  EXPECT_NE(core.apply_parameters(p).find("clustering"), std::string::npos);
  p = core.parameters();
  p.avoidance.min_detection_range_m = 50.0;  // outside its range
  p.heading_pid.kp_per_deg = 2.0 * kp;       // fine, but the set is refused as a whole
  EXPECT_NE(core.apply_parameters(p).find("avoidance.min_detection_range_m"), std::string::npos);
  EXPECT_DOUBLE_EQ(core.parameters().heading_pid.kp_per_deg, kp);
  p = core.parameters();
  p.heading_pid.kp_per_deg = 2.0 * kp;
  p.clustering.group_gap_m = 0.2;
  p.avoidance.clearance_m = 0.5;
  p.speed.rise_per_s = 0.4;
  p.vision.colours[0].hsv.v_min = 99;
  EXPECT_EQ(core.apply_parameters(p), "");
  const TunableParameters in_force = core.parameters();
  EXPECT_DOUBLE_EQ(in_force.heading_pid.kp_per_deg, 2.0 * kp);
  EXPECT_DOUBLE_EQ(in_force.clustering.group_gap_m, 0.2);
  EXPECT_DOUBLE_EQ(in_force.avoidance.clearance_m, 0.5);
  EXPECT_DOUBLE_EQ(in_force.speed.rise_per_s, 0.4);
  EXPECT_EQ(in_force.vision.colours[0].hsv.v_min, 99);
}

TEST(MissionCoreParameters, FieldsWithoutANameAreNotTakenFromTheSet) {
  const config::Configuration obs = obstacle_config();
  MissionCore core(obs.boat, obs.mission);
  TunableParameters p = core.parameters();
  const double fan_min = p.avoidance.fan.min_deg;
  p.avoidance.fan.min_deg = -45.0;  // not live-tunable
  p.avoidance.clearance_m = 0.2;
  EXPECT_EQ(core.apply_parameters(p), "");
  EXPECT_DOUBLE_EQ(core.parameters().avoidance.fan.min_deg, fan_min);
  EXPECT_DOUBLE_EQ(core.parameters().avoidance.clearance_m, 0.2);
}

TEST(MissionCoreParameters, ANewGainChangesTheNextStepsTurn) {
  Rig soft(hopping());
  Rig stiff(hopping());
  for (Rig* r : {&soft, &stiff}) {
    ASSERT_TRUE(r->run_until([&] { return r->path().find("hopping") != std::string::npos; }, 5.0))
        << r->path() << "\n"
        << r->log_text();
  }
  TunableParameters p = soft.core.parameters();
  ASSERT_EQ(soft.core.apply_parameters(p), "");  // same gains, fresh PID: a fair comparison
  p.heading_pid.kp_per_deg *= 2.0;
  ASSERT_EQ(stiff.core.apply_parameters(p), "");
  soft.heading_deg = stiff.heading_deg = 8.0;  // the waypoint is due north: 8 deg to port
  soft.tick();
  stiff.tick();
  const double a = soft.out.viz.turn_command;
  const double b = stiff.out.viz.turn_command;
  EXPECT_LT(a, 0.0);  // turn to port
  EXPECT_LT(b, a);    // harder to port with twice the gain
  EXPECT_NEAR(b / a, 2.0, 0.3);
}

TEST(MissionCoreParameters, AShorterDetectionRangeIgnoresABuoyTheLongerOneAvoids) {
  // A buoy 4 m ahead on the line to the gate: avoided at the default 5 m detection range, ignored
  // (steered straight at the goal) once the operator shortens the range to 2 m.
  auto make = [] {
    auto rig = std::make_unique<Rig>(obstacle_config());
    rig->world_buoys.push_back({{4.0, 0.2}, 0.5});
    return rig;
  };
  auto near = make();
  auto far = make();
  for (Rig* r : {near.get(), far.get()}) {
    ASSERT_TRUE(r->run_until([&] { return r->path() == "obstacle_course/navigate"; }, 5.0))
        << r->path() << "\n"
        << r->log_text();
  }
  TunableParameters p = near->core.parameters();
  ASSERT_GT(p.avoidance.detection_range_m, 4.5);
  p.avoidance.detection_range_m = 2.0;
  p.avoidance.min_detection_range_m = 1.0;
  p.avoidance.score_block_range_m = 2.0;
  ASSERT_EQ(near->core.apply_parameters(p), "");
  near->run_for(0.2);
  far->run_for(0.2);
  const auto avoiding = static_cast<std::uint8_t>(guidance::AvoidanceStatus::kAvoiding);
  const auto clear = static_cast<std::uint8_t>(guidance::AvoidanceStatus::kClear);
  EXPECT_EQ(far->out.viz.avoidance_status, avoiding);
  EXPECT_EQ(near->out.viz.avoidance_status, clear);
  EXPECT_NEAR(near->out.viz.avoidance_bearing_body_deg, 0.0, 1.0);
  EXPECT_GT(std::abs(far->out.viz.avoidance_bearing_body_deg), 5.0);
}

TEST(MissionCoreParameters, ALowerMaximumThrustSlowsTheNextSteps) {
  Rig full(hopping(80.0));
  Rig slow(hopping(80.0));
  for (Rig* r : {&full, &slow}) {
    r->move = true;
    r->run_for(8.0);  // up to speed, far from the waypoint (the schedule's maximum)
  }
  ASSERT_GT(full.thrust_frac(), 0.6);
  TunableParameters p = slow.core.parameters();
  p.speed.max_thrust_frac = 0.5;
  p.speed.min_thrust_frac = 0.2;
  ASSERT_EQ(slow.core.apply_parameters(p), "");
  full.run_for(4.0);
  slow.run_for(4.0);  // the ramp falls at fall_per_s from where it was, not from zero
  EXPECT_GT(full.thrust_frac(), 0.6);
  EXPECT_LT(slow.thrust_frac(), 0.52);
  EXPECT_GT(slow.thrust_frac(), 0.3);
}

// The vision file's HSV bounds are live as "vision.<colour>.<key>", with the table's bounds; the
// colour's other keys are not.
TEST(TunableParameters, TheVisionRangesAreTunedLiveWithTheFileTablesBounds) {
  const TunableSpec* h = find_tunable("vision.red.h_min");
  ASSERT_NE(h, nullptr);
  EXPECT_EQ(h->max, 179.0);
  EXPECT_TRUE(h->integer);
  const TunableSpec* v = find_tunable("vision.blue.v_max");
  ASSERT_NE(v, nullptr);
  EXPECT_EQ(v->max, 255.0);
  EXPECT_EQ(find_tunable("vision.red.markers"), nullptr);
  TunableParameters p;
  v->set(p, 200.0);
  EXPECT_EQ(v->get(p), 200.0);
  EXPECT_EQ(p.vision.colours[static_cast<std::size_t>(p.vision.find_colour(msg::Colour::kBlue))]
                .hsv.v_max,
            200);
}

}  // namespace
}  // namespace coxswain::mission::test
