// SPDX-License-Identifier: Apache-2.0
// The operator's command language, the status answer, the parameter table and the core's
// parameter hand-over (MissionCore::apply_parameters between steps).
#include "coxswain/live/control_protocol.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <nlohmann/json.hpp>

#include "../mission/mission_rig.hpp"

namespace coxswain::live {
namespace {

using mission::test::base_config;
using mission::test::Rig;

TEST(ControlProtocol, ParsesEveryCommand) {
  std::string error;
  EXPECT_EQ(parse_command("start", error)->kind, CommandKind::kStart);
  EXPECT_EQ(parse_command("  hold \r", error)->kind, CommandKind::kHold);
  EXPECT_EQ(parse_command("resume", error)->kind, CommandKind::kResume);
  EXPECT_EQ(parse_command("status", error)->kind, CommandKind::kStatus);
  const auto target = parse_command("target red  triangle", error);
  ASSERT_TRUE(target) << error;
  EXPECT_EQ(target->kind, CommandKind::kTarget);
  EXPECT_EQ(target->colour, msg::Colour::kRed);
  EXPECT_EQ(target->shape, msg::Shape::kTriangle);
}

TEST(ControlProtocol, RefusesMalformedCommandsWithAReason) {
  std::string error;
  EXPECT_FALSE(parse_command("", error));
  EXPECT_FALSE(error.empty());
  EXPECT_FALSE(parse_command("launch", error));
  EXPECT_NE(error.find("unknown command"), std::string::npos);
  EXPECT_FALSE(parse_command("start now", error));
  EXPECT_FALSE(parse_command("target red", error));
  EXPECT_FALSE(parse_command("target mauve circle", error));
  EXPECT_NE(error.find("colour"), std::string::npos);
  EXPECT_FALSE(parse_command("target red hexagon", error));
  EXPECT_NE(error.find("shape"), std::string::npos);
  EXPECT_FALSE(parse_command("target unknown circle", error));  // a target names something
  EXPECT_FALSE(parse_command("START", error));
}

TEST(ControlProtocol, EveryPressCountsOnceAndResumeClearsHold) {
  OperatorState s;
  EXPECT_EQ(s.apply({CommandKind::kStart}, 5).start_count, 1U);
  EXPECT_EQ(s.apply({CommandKind::kStart}, 6).start_count, 2U);
  const msg::OperatorInput& held = s.apply({CommandKind::kHold}, 7);
  EXPECT_TRUE(held.hold);
  EXPECT_EQ(held.hold_count, 1U);
  const msg::OperatorInput& resumed = s.apply({CommandKind::kResume}, 8);
  EXPECT_FALSE(resumed.hold);
  EXPECT_EQ(resumed.hold_count, 2U);
  EXPECT_EQ(resumed.stamp_ns, 8);
  const msg::OperatorInput& t =
      s.apply({CommandKind::kTarget, msg::Colour::kGreen, msg::Shape::kCross}, 9);
  EXPECT_EQ(t.target_colour, msg::Colour::kGreen);
  EXPECT_EQ(t.target_shape, msg::Shape::kCross);
  EXPECT_EQ(t.start_count, 2U);  // a target leaves the counters alone
}

TEST(ControlProtocol, StatusAnswerCarriesStateHoldAndDeviceHealth) {
  core::Sample<TickSummary> tick;
  tick.sequence = 3;
  tick.stamp_ns = 2 * core::kNsPerSec;
  tick.value.tick_index = 99;
  tick.value.status.state_path.assign("hold/course1/avoid");
  tick.value.status.holding = true;
  tick.value.status.hold_reason = mission::HoldReason::kLidarStale;
  auto snap = std::make_unique<core::Snapshot>();
  snap->health[0].sequence = 1;
  snap->health[0].value.state = msg::DeviceState::kStale;
  snap->health[0].value.set_detail("silent for 0.4 s");
  snap->health[1].sequence = 1;
  snap->health[1].value.state = msg::DeviceState::kRunning;
  msg::OperatorInput op;
  op.hold = true;
  op.target_colour = msg::Colour::kBlue;
  const auto j = nlohmann::json::parse(status_json(tick, op, *snap, 3 * core::kNsPerSec));
  EXPECT_EQ(j["state_path"], "hold/course1/avoid");
  EXPECT_EQ(j["tick"], 99);
  EXPECT_DOUBLE_EQ(j["tick_age_s"].get<double>(), 1.0);
  EXPECT_TRUE(j["holding"].get<bool>());
  EXPECT_EQ(j["hold_reason"], "lidar_stale");
  EXPECT_EQ(j["devices"]["lidar"]["state"], "stale");
  EXPECT_EQ(j["devices"]["lidar"]["detail"], "silent for 0.4 s");
  EXPECT_EQ(j["devices"]["imu"]["state"], "running");
  EXPECT_EQ(j["devices"]["camera"]["state"], "disabled");
  EXPECT_FALSE(j["devices_ok"].get<bool>());
  EXPECT_TRUE(j["operator"]["hold"].get<bool>());
  EXPECT_EQ(j["operator"]["target_colour"], "blue");

  snap->health[0].value.state = msg::DeviceState::kRunning;
  const auto ok = nlohmann::json::parse(status_json({}, op, *snap, 0));
  EXPECT_TRUE(ok["devices_ok"].get<bool>());
  EXPECT_EQ(ok["state_path"], "starting");  // before the first tick
}

TEST(ControlProtocol, TokenComparison) {
  EXPECT_TRUE(token_matches("s3cret", "s3cret"));
  EXPECT_FALSE(token_matches("s3cret", "s3creT"));
  EXPECT_FALSE(token_matches("s3cret", "s3cre"));
  EXPECT_FALSE(token_matches("s3cret", ""));
  EXPECT_FALSE(token_matches("", ""));  // no configured token: buttons stay off
}

TEST(ControlProtocol, ParametersAreRangeCheckedAndValidated) {
  mission::TunableParameters p;
  const double kp = p.heading_pid.kp_per_deg;
  EXPECT_EQ(set_parameter(p, "heading_pid.kp_per_deg", 0.05), "");
  EXPECT_DOUBLE_EQ(p.heading_pid.kp_per_deg, 0.05);
  EXPECT_NE(kp, 0.05);
  EXPECT_NE(set_parameter(p, "heading_pid.kp_per_deg", 5.0).find("within"), std::string::npos);
  EXPECT_NE(set_parameter(p, "heading_pid.kp_per_deg", -1.0), "");
  EXPECT_NE(set_parameter(p, "heading_pid.kp_per_deg", std::nan("")), "");
  EXPECT_DOUBLE_EQ(p.heading_pid.kp_per_deg, 0.05);  // unchanged by the refusals
  EXPECT_NE(set_parameter(p, "no.such", 1.0).find("unknown"), std::string::npos);
  EXPECT_NE(set_parameter(p, "clustering.min_group_points", 2.5).find("whole"), std::string::npos);
  EXPECT_EQ(set_parameter(p, "clustering.min_group_points", 6.0), "");
  EXPECT_EQ(p.clustering.min_group_points, 6U);
  for (const ParameterSpec& spec : parameter_specs()) {
    mission::TunableParameters d;
    const double v = spec.get(d);
    EXPECT_GE(v, spec.min) << spec.name << ": the default must lie in the range";
    EXPECT_LE(v, spec.max) << spec.name;
    EXPECT_EQ(set_parameter(d, spec.name, v), "") << spec.name;
    EXPECT_EQ(find_parameter(spec.name), &spec);
  }
}

config::Configuration hopping() {
  config::Configuration c = base_config(config::TaskType::kHopping);
  const core::LocalFrame f(c.mission.origin);
  c.mission.tasks[0].waypoints.push_back(f.to_geo(core::NavPoint{30.0, 0.0}));
  return c;
}

TEST(MissionCoreParameters, ApplyRejectsInvalidSetsAndKeepsTheOldOne) {
  mission::MissionCore core(hopping());
  mission::TunableParameters p = core.parameters();
  const double kp = p.heading_pid.kp_per_deg;
  p.heading_pid.kp_per_deg = -1.0;
  EXPECT_NE(core.apply_parameters(p), "");
  EXPECT_DOUBLE_EQ(core.parameters().heading_pid.kp_per_deg, kp);
  p = core.parameters();
  p.clustering.min_group_points = 0;
  EXPECT_NE(core.apply_parameters(p).find("clustering"), std::string::npos);
  p = core.parameters();
  p.heading_pid.kp_per_deg = 2.0 * kp;
  p.clustering.group_gap_m = 0.2;
  EXPECT_EQ(core.apply_parameters(p), "");
  EXPECT_DOUBLE_EQ(core.parameters().heading_pid.kp_per_deg, 2.0 * kp);
  EXPECT_DOUBLE_EQ(core.parameters().clustering.group_gap_m, 0.2);
}

TEST(MissionCoreParameters, ANewGainChangesTheNextStepsTurn) {
  Rig soft(hopping());
  Rig stiff(hopping());
  for (Rig* r : {&soft, &stiff}) {
    ASSERT_TRUE(r->run_until([&] { return r->path().find("hopping") != std::string::npos; }, 5.0))
        << r->path() << "\n"
        << r->log_text();
  }
  mission::TunableParameters p = soft.core.parameters();
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

}  // namespace
}  // namespace coxswain::live
