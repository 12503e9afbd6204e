// SPDX-License-Identifier: Apache-2.0
// The operator's command language and the status answer.
#include "coxswain/live/control_protocol.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <nlohmann/json.hpp>

namespace coxswain::live {
namespace {

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

}  // namespace
}  // namespace coxswain::live
