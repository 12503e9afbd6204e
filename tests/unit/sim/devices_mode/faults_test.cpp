// SPDX-License-Identifier: Apache-2.0
#include "sim/devices_mode/faults.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace coxswain::sim::devices_mode {
namespace {

std::string error_of(std::string_view spec) {
  try {
    (void)parse_fault_spec(spec);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(FaultSpec, ReadsDeviceKindTimeAndDuration) {
  const FaultSpec f = parse_fault_spec("gnss:unplug@40+2.5");
  EXPECT_EQ(f.device, msg::DeviceId::kGnss);
  EXPECT_EQ(f.kind, FaultKind::kUnplug);
  EXPECT_DOUBLE_EQ(f.at_s, 40.0);
  EXPECT_DOUBLE_EQ(f.duration_s, 2.5);
  EXPECT_EQ(fault_spec_text(f), "gnss:unplug@40+2.5");
}

TEST(FaultSpec, EveryKindOnEverySerialDeviceIsUnderstood) {
  for (const char* device : {"lidar", "imu", "gnss", "arduino"}) {
    for (const char* kind : {"unplug", "reset", "garbage", "silence", "baud"}) {
      const std::string spec = std::string(device) + ":" + kind + "@1.5";
      const FaultSpec f = parse_fault_spec(spec);
      EXPECT_EQ(msg::device_name(f.device), device);
      EXPECT_EQ(fault_kind_name(f.kind), kind);
      EXPECT_DOUBLE_EQ(f.at_s, 1.5);
    }
  }
}

TEST(FaultSpec, WithoutADurationTheKindsDefaultApplies) {
  EXPECT_DOUBLE_EQ(parse_fault_spec("imu:silence@10").duration_s,
                   default_fault_duration_s(FaultKind::kSilence));
  EXPECT_DOUBLE_EQ(parse_fault_spec("lidar:reset@10").duration_s,
                   default_fault_duration_s(FaultKind::kReset));
  EXPECT_LT(default_fault_duration_s(FaultKind::kReset),
            default_fault_duration_s(FaultKind::kUnplug));
}

TEST(FaultSpec, MalformedSpecsAreRefusedWithTheReason) {
  EXPECT_NE(error_of("gnss-unplug@4").find("expected DEVICE:KIND@T[+DURATION]"), std::string::npos);
  EXPECT_NE(error_of("gnss:unplug").find("expected DEVICE:KIND@T"), std::string::npos);
  EXPECT_NE(error_of("radar:unplug@4").find("unknown device 'radar'"), std::string::npos);
  EXPECT_NE(error_of("camera:unplug@4").find("unknown device 'camera'"), std::string::npos);
  EXPECT_NE(error_of("gnss:explode@4").find("unknown kind 'explode'"), std::string::npos);
  EXPECT_NE(error_of("gnss:unplug@soon").find("time 'soon'"), std::string::npos);
  EXPECT_NE(error_of("gnss:unplug@-3").find("time '-3'"), std::string::npos);
  EXPECT_NE(error_of("gnss:unplug@4+").find("duration ''"), std::string::npos);
  EXPECT_NE(error_of("gnss:unplug@4+2x").find("duration '2x'"), std::string::npos);
  EXPECT_NE(error_of("gnss:unplug@4+0").find("more than 0 s"), std::string::npos);
}

// Log lines as the daemon writes them (src/app), stamped on arrival in ns.
LogLine line(double t_s, std::string text) {
  return LogLine{static_cast<core::TimeNs>(t_s * 1e9), std::move(text)};
}

FaultRecord applied(std::string_view spec, bool sailing) {
  FaultRecord r;
  r.spec = parse_fault_spec(spec);
  r.began_s = r.spec.at_s;
  r.began_ns = static_cast<core::TimeNs>(r.spec.at_s * 1e9);
  r.ended_s = r.spec.at_s + r.spec.duration_s;
  r.ended_ns = static_cast<core::TimeNs>(*r.ended_s * 1e9);
  r.sailing_at_start = sailing;
  return r;
}

TEST(FaultObservation, AHoldAndAResumeAfterTheDeviceReturnsCountAsRecovered) {
  FaultRecord r = applied("gnss:unplug@10+2", true);
  const std::vector<LogLine> lines{
      line(9.0, "info  device gnss: running (nav-pvt 5 Hz)"),
      line(10.2, "warning device gnss: stale (no frame for 1.5 s)"),
      line(10.25, "info  mission: course1/to_waypoint -> hold/course1/to_waypoint: gnss stale"),
      line(12.5, "info  device gnss: running (nav-pvt 5 Hz)"),
      line(12.7,
           "info  mission: hold/course1/to_waypoint -> course1/to_waypoint: resume: gnss back")};
  observe_fault(lines, r);
  ASSERT_TRUE(r.held_after_ms.has_value());
  EXPECT_NEAR(*r.held_after_ms, 250.0, 1e-6);
  ASSERT_TRUE(r.device_back_s.has_value());
  EXPECT_NEAR(*r.device_back_s, 0.5, 1e-9);
  ASSERT_TRUE(r.resumed_after_s.has_value());
  EXPECT_NEAR(*r.resumed_after_s, 0.7, 1e-9);
  EXPECT_TRUE(fault_recovered(r));
  EXPECT_NE(fault_summary_line(r).find("held after 250 ms"), std::string::npos);
}

// A later fault's lines are its own: the GNSS unplugged after a baud fault it rode through does
// not make the first fault's device come back late.
TEST(FaultObservation, TheLinesOfTheNextFaultAreNotCounted) {
  FaultRecord r = applied("gnss:baud@41+1", true);
  const std::vector<LogLine> lines{
      line(41.3, "info  mission: course1/to_waypoint -> hold/course1/to_waypoint: gnss stale"),
      line(42.2,
           "info  mission: hold/course1/to_waypoint -> course1/to_waypoint: resume: gnss back"),
      line(53.1, "warning device gnss: absent (path gone (unplugged?))"),
      line(54.0, "info  device gnss: running (configured)")};
  observe_fault(lines, r, static_cast<core::TimeNs>(53.0 * 1e9));
  ASSERT_TRUE(r.device_back_s.has_value());
  EXPECT_DOUBLE_EQ(*r.device_back_s, 0.0);
  EXPECT_TRUE(fault_recovered(r));
  FaultRecord unbounded = applied("gnss:baud@41+1", true);
  observe_fault(lines, unbounded);
  EXPECT_NEAR(unbounded.device_back_s.value_or(0.0), 12.0, 1e-9);
}

TEST(FaultObservation, AHoldWithoutAResumeIsNotRecovered) {
  FaultRecord r = applied("imu:silence@10+3", true);
  observe_fault({line(10.4, "warning device imu: stale (no line for 200 ms)"),
                 line(10.45,
                      "info  mission: course1/to_waypoint -> hold/course1/to_waypoint: "
                      "imu stale (no sample for 210 ms)"),
                 line(13.5, "info  device imu: running (ascii 100 Hz)")},
                r);
  EXPECT_TRUE(r.held_after_ms.has_value());
  EXPECT_TRUE(r.device_back_s.has_value());
  EXPECT_FALSE(fault_recovered(r));
  EXPECT_NE(fault_summary_line(r).find("NOT resumed"), std::string::npos);
}

// The mission holds only for a device its task needs: a fault on another is ridden through.
TEST(FaultObservation, AFaultRiddenThroughIsRecoveredOnceTheDeviceRunsAgain) {
  FaultRecord r = applied("lidar:unplug@30+2", true);
  observe_fault({line(30.3, "warning device lidar: absent (path gone (unplugged?))"),
                 line(33.0, "info  device lidar: running (scanning)")},
                r);
  EXPECT_FALSE(r.held_after_ms.has_value());
  EXPECT_TRUE(fault_recovered(r));
  EXPECT_NE(fault_summary_line(r).find("ridden through"), std::string::npos);
}

TEST(FaultObservation, ADeviceThatNeverComesBackIsNotRecovered) {
  FaultRecord r = applied("lidar:reset@20", false);
  observe_fault({line(20.3, "warning device lidar: stale (no scan for 300 ms)")}, r);
  EXPECT_FALSE(r.device_back_s.has_value());
  EXPECT_FALSE(fault_recovered(r));
  EXPECT_NE(fault_summary_line(r).find("device NOT back"), std::string::npos);
}

TEST(FaultObservation, AfterTheMissionFinishedTheDeviceComingBackIsEnough) {
  FaultRecord r = applied("arduino:baud@200+3", false);
  observe_fault({line(200.6, "warning device arduino: stale (no telemetry for 500 ms)"),
                 line(204.0, "info  device arduino: running (fw 1.0.0)")},
                r);
  EXPECT_FALSE(r.held_after_ms.has_value());
  EXPECT_TRUE(fault_recovered(r));
  EXPECT_NE(fault_summary_line(r).find("not sailing"), std::string::npos);
}

}  // namespace
}  // namespace coxswain::sim::devices_mode
