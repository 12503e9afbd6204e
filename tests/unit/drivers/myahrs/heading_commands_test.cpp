// SPDX-License-Identifier: Apache-2.0
// Heading conversion (frames, seam, declination) and the request encoder / start-up plan.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "coxswain/drivers/myahrs/codec.hpp"
#include "coxswain/drivers/myahrs/commands.hpp"
#include "coxswain/drivers/myahrs/heading.hpp"

namespace coxswain::drivers::myahrs {
namespace {

// ---------------------------------------------------------------------------------------------
// Heading.

struct HeadingCase {
  double sensor_yaw_deg;
  double mount_yaw_deg;
  double declination_deg;
  double expected_deg;
};

TEST(MyahrsHeading, SeamDeclinationAndMount) {
  const std::vector<HeadingCase> cases = {
      {0.0, 0.0, 0.0, 0.0},         {97.31, 0.0, 0.0, 97.31},
      {179.0, 0.0, 2.0, -179.0},     // east declination pushes across the seam
      {-179.0, 0.0, -2.0, 179.0},    // west declination, other direction
      {-178.0, 0.0, -2.0, 180.0},    // exactly the seam: 180, never -180
      {180.0, 0.0, 0.0, 180.0},      // sensor prints 180
      {-180.0, 0.0, 0.0, 180.0},     // ... or -180: same heading
      {10.0, 180.0, 0.0, -170.0},    // board mounted backwards
      {-170.0, -90.0, -8.5, -88.5},  // board x to port, Korea-like declination
      {170.0, 20.0, 15.0, 165.0},   {350.0, 0.0, 0.0, -10.0},  // 0..360 input wraps too
  };
  for (const HeadingCase& c : cases) {
    HeadingConfig cfg;
    cfg.mount_yaw_deg = c.mount_yaw_deg;
    cfg.declination_deg = c.declination_deg;
    const double h = true_heading_deg(c.sensor_yaw_deg, cfg);
    EXPECT_NEAR(h, c.expected_deg, 1e-9)
        << c.sensor_yaw_deg << " " << c.mount_yaw_deg << " " << c.declination_deg;
    EXPECT_GT(h, -180.0);
    EXPECT_LE(h, 180.0);
  }
}

TEST(MyahrsHeading, ConfigValidation) {
  EXPECT_FALSE(HeadingConfig{}.validate().has_value());
  EXPECT_TRUE((HeadingConfig{400.0, 0.0}.validate().has_value()));
  EXPECT_TRUE((HeadingConfig{0.0, 91.0}.validate().has_value()));
  EXPECT_TRUE((HeadingConfig{std::nan(""), 0.0}.validate().has_value()));
}

// Quaternion of Z-Y-X Euler angles, built independently (product of three axis rotations).
std::array<double, 4> quat_of(double roll_deg, double pitch_deg, double yaw_deg) {
  const double r = roll_deg * std::numbers::pi / 360.0;
  const double p = pitch_deg * std::numbers::pi / 360.0;
  const double y = yaw_deg * std::numbers::pi / 360.0;
  // qz(y) * qy(p) * qx(r), Hamilton product, stored x y z w.
  const double cr = std::cos(r), sr = std::sin(r), cp = std::cos(p), sp = std::sin(p);
  const double cy = std::cos(y), sy = std::sin(y);
  return {sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy,
          cr * cp * cy + sr * sp * sy};
}

TEST(MyahrsHeading, QuaternionToEulerRoundTrip) {
  const std::vector<std::array<double, 3>> poses = {
      {0, 0, 0}, {30, 0, 0}, {0, 20, 0}, {0, 0, 90}, {-20, 10, 120}, {5, -3, -170}, {1, 2, 179.9}};
  for (const auto& pose : poses) {
    const auto q = quat_of(pose[0], pose[1], pose[2]);
    const auto e = quaternion_to_euler_deg(q[0], q[1], q[2], q[3]);
    ASSERT_TRUE(e.has_value());
    EXPECT_NEAR(e->roll_deg, pose[0], 1e-9);
    EXPECT_NEAR(e->pitch_deg, pose[1], 1e-9);
    EXPECT_NEAR(e->yaw_deg, pose[2], 1e-9);
    // Scaled and negated quaternions describe the same rotation.
    const auto e2 = quaternion_to_euler_deg(-2 * q[0], -2 * q[1], -2 * q[2], -2 * q[3]);
    ASSERT_TRUE(e2.has_value());
    EXPECT_NEAR(e2->yaw_deg, pose[2], 1e-9);
  }
  EXPECT_FALSE(quaternion_to_euler_deg(0, 0, 0, 0).has_value());
  EXPECT_FALSE(quaternion_to_euler_deg(std::nan(""), 0, 0, 1).has_value());
  // Gimbal lock: pitch exactly 90 must not be NaN.
  const auto q = quat_of(0, 90, 0);
  const auto e = quaternion_to_euler_deg(q[0], q[1], q[2], q[3]);
  ASSERT_TRUE(e.has_value());
  EXPECT_NEAR(e->pitch_deg, 90.0, 1e-6);
}

// ---------------------------------------------------------------------------------------------
// Commands.

TEST(MyahrsCommands, DocumentedVersionRequest) {
  EXPECT_EQ(version_command().text(), "@version*3A\r\n");
  EXPECT_EQ(version_command().name(), "version");
}

// Every encoded request must pass the decoder's own checksum check.
void expect_verifies(const EncodedCommand& c) {
  Decoder d;
  std::span<const std::uint8_t> rest = c.data();
  while (!rest.empty()) rest = rest.subspan(d.decode(rest).consumed);
  EXPECT_EQ(d.stats().requests_seen, 1U) << c.text();
  EXPECT_EQ(d.stats().codec.checksum_errors, 0U) << c.text();
}

TEST(MyahrsCommands, EncodersProduceCheckedRequests) {
  // Expected checksums worked out independently (XOR of the bytes before '*').
  const std::vector<std::pair<EncodedCommand, std::string>> cases = {
      {mode_command("T").value(), "@mode,T*3B\r\n"},
      {continuous_mode_command(OutputForm::kAscii), "@mode,AC*6D\r\n"},
      {continuous_mode_command(OutputForm::kBinary), "@mode,BC*6E\r\n"},
      {asc_out_command(Content::kRpyImu), "@asc_out,RPYIMU*26\r\n"},
      {asc_out_command(Content::kQuatImu), "@asc_out,QUATIMU*6C\r\n"},
      {bin_out_command(Content::kRpyImu), "@bin_out,EULER, IMU*2E\r\n"},
      {bin_out_command(Content::kQuatImu), "@bin_out,QUATERNION, IMU*65\r\n"},
      {divider_command(1).value(), "@divider,1*3C\r\n"},
      {divider_command(10).value(), "@divider,10*0C\r\n"},
      {trig_command(), "@trig*48\r\n"},
  };
  for (const auto& [cmd, text] : cases) {
    EXPECT_EQ(cmd.text(), text);
    expect_verifies(cmd);
  }
  EXPECT_EQ(bin_out_command(Content::kRpyImu).name(), "bin_out");
}

TEST(MyahrsCommands, RejectsBadInput) {
  EXPECT_FALSE(mode_command("").has_value());
  EXPECT_FALSE(mode_command("ACT").has_value());
  EXPECT_FALSE(mode_command("X").has_value());
  EXPECT_FALSE(divider_command(0).has_value());
  EXPECT_FALSE(divider_command(kMaxDivider + 1).has_value());
  EXPECT_TRUE(divider_command(kMaxDivider).has_value());
  EXPECT_FALSE(encode_request("").has_value());
  EXPECT_FALSE(encode_request("Mode").has_value());
  EXPECT_FALSE(encode_request("mode", "A*C").has_value());
  EXPECT_FALSE(encode_request("mode", "A\r").has_value());
  EXPECT_FALSE(encode_request("mode", "$").has_value());
  EXPECT_FALSE(encode_request("calib", std::string(100, '1')).has_value());
  EXPECT_TRUE(encode_request("calib", "A,1,0,0,0,1,0,0,0,1,0,0,0").has_value());
}

TEST(MyahrsCommands, DividerForRate) {
  EXPECT_EQ(divider_for_rate(100.0), 1);
  EXPECT_EQ(divider_for_rate(50.0), 2);
  EXPECT_EQ(divider_for_rate(30.0), 3);  // 33.3 Hz actual
  EXPECT_EQ(divider_for_rate(7.0), 14);
  EXPECT_EQ(divider_for_rate(1.0), 100);
  EXPECT_EQ(divider_for_rate(500.0), 1);
  EXPECT_EQ(divider_for_rate(0.0), 1);
  EXPECT_EQ(divider_for_rate(-5.0), 1);
  EXPECT_EQ(divider_for_rate(0.01), kMaxDivider);
}

TEST(MyahrsCommands, StartupParamsValidate) {
  EXPECT_FALSE(StartupParams{}.validate().has_value());
  StartupParams p;
  p.rate_hz = 0.0;
  EXPECT_TRUE(p.validate().has_value());
  p.rate_hz = 101.0;
  EXPECT_TRUE(p.validate().has_value());
  p.rate_hz = 0.05;
  EXPECT_TRUE(p.validate().has_value());
  p.rate_hz = 0.1;
  EXPECT_FALSE(p.validate().has_value());
}

std::vector<std::pair<std::string, std::string>> plan_text(const StartupPlan& plan) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const StartupStep& s : plan.view()) {
    out.emplace_back(std::string(s.command.text()), std::string(s.awaits));
  }
  return out;
}

TEST(MyahrsCommands, StartupPlanAscii) {
  StartupParams p;
  p.form = OutputForm::kAscii;
  p.rate_hz = 10.0;
  p.content = Content::kRpyImu;
  const StartupPlan plan = make_startup_plan(p);
  const std::vector<std::pair<std::string, std::string>> expected = {
      {"@mode,T*3B\r\n", "mode"},        {"@version*3A\r\n", "version"},
      {"@divider,10*0C\r\n", "divider"}, {"@asc_out,RPYIMU*26\r\n", "asc_out"},
      {"@mode,AC*6D\r\n", "mode"},
  };
  EXPECT_EQ(plan_text(plan), expected);
}

TEST(MyahrsCommands, StartupPlanBinaryAndResponseMatching) {
  StartupParams p;
  p.form = OutputForm::kBinary;
  p.rate_hz = 100.0;
  p.content = Content::kQuatImu;
  const StartupPlan plan = [&] {
    const StartupPlan tmp = make_startup_plan(p);
    return tmp;  // a copy: awaits must not dangle
  }();
  const auto text = plan_text(plan);
  ASSERT_EQ(text.size(), 5U);
  EXPECT_EQ(text[2].first, "@divider,1*3C\r\n");
  EXPECT_EQ(text[3].first, "@bin_out,QUATERNION, IMU*65\r\n");
  EXPECT_EQ(text[3].second, "bin_out");
  EXPECT_EQ(text[4].first, "@mode,BC*6E\r\n");

  // The decoder's responses are what the plan waits for.
  Decoder d;
  const std::string ok = "~bin_out,OK,fmt=QUATERNION, IMU*";
  std::uint8_t cs = xor_checksum(std::string_view(ok).substr(0, ok.size() - 1));
  char hex[3];
  std::snprintf(hex, sizeof hex, "%02X", cs);
  const std::string line = ok + hex + "\r\n";
  std::span<const std::uint8_t> rest(reinterpret_cast<const std::uint8_t*>(line.data()),
                                     line.size());
  const DecodeStep step = d.decode(rest);
  ASSERT_TRUE(step.produced);
  EXPECT_TRUE(is_awaited_ok(plan.steps[3], d.response()));
  EXPECT_FALSE(is_awaited_ok(plan.steps[4], d.response()));
  CommandResponse err = d.response();
  err.ok = false;
  EXPECT_FALSE(is_awaited_ok(plan.steps[3], err));
}

}  // namespace
}  // namespace coxswain::drivers::myahrs
