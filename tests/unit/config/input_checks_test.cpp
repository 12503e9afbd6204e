// SPDX-License-Identifier: Apache-2.0
#include "coxswain/config/input_checks.hpp"

#include <gtest/gtest.h>

#include <string>

namespace coxswain::config {
namespace {

TEST(InputChecks, RtcmInputAcceptsTcpHostPortAndPaths) {
  EXPECT_FALSE(validate_rtcm_input(""));
  EXPECT_FALSE(validate_rtcm_input("tcp://127.0.0.1:2101"));
  EXPECT_FALSE(validate_rtcm_input("tcp://base.local:2101"));
  EXPECT_FALSE(validate_rtcm_input("tcp://[::1]:2101"));
  EXPECT_FALSE(validate_rtcm_input("/run/coxswain/rtcm.pipe"));
  EXPECT_FALSE(validate_rtcm_input("corrections.rtcm3"));
}

TEST(InputChecks, MalformedRtcmInputSaysWhy) {
  EXPECT_NE(validate_rtcm_input("tcp://base.local").value_or(""), "");
  EXPECT_NE(validate_rtcm_input("tcp://base.local:").value_or("").find("port"), std::string::npos);
  EXPECT_NE(validate_rtcm_input("tcp://base.local:99999").value_or("").find("1..65535"),
            std::string::npos);
  EXPECT_NE(validate_rtcm_input("tcp://::1:2101").value_or("").find("brackets"), std::string::npos);
  EXPECT_NE(validate_rtcm_input("ntrip://caster:2101/MOUNT").value_or("").find("not supported"),
            std::string::npos);
  EXPECT_NE(validate_rtcm_input("tcp://caster:2101/MOUNT").value_or("").find("no path"),
            std::string::npos);
  EXPECT_NE(validate_rtcm_input("tcp://bad_host!:2101").value_or(""), "");
  EXPECT_TRUE(validate_rtcm_input("/var/lib/"));
}

TEST(InputChecks, HttpAddressMustBeAnIpAddress) {
  EXPECT_FALSE(validate_http_address("127.0.0.1"));
  EXPECT_FALSE(validate_http_address("0.0.0.0"));
  EXPECT_FALSE(validate_http_address("::1"));
  EXPECT_TRUE(validate_http_address("localhost"));
  EXPECT_TRUE(validate_http_address("127.0.0.1:8765"));
  EXPECT_TRUE(validate_http_address(""));
}

TEST(InputChecks, ControlSocketMustFitAUnixSocketAddress) {
  EXPECT_FALSE(validate_control_socket(""));
  EXPECT_FALSE(validate_control_socket("/run/coxswain/control.sock"));
  EXPECT_NE(validate_control_socket("/" + std::string(120, 'a')).value_or("").find("at most 107"),
            std::string::npos);
  EXPECT_TRUE(validate_control_socket("/run/coxswain/"));
}

TEST(InputChecks, DevicePathsTokensHostsAndOrigins) {
  EXPECT_FALSE(validate_device_path("/dev/ttyUSB0"));
  EXPECT_TRUE(validate_device_path("ttyUSB0"));
  EXPECT_TRUE(validate_device_path(""));
  EXPECT_FALSE(validate_live_token(""));
  EXPECT_FALSE(validate_live_token("shore-token-1234"));
  EXPECT_TRUE(validate_live_token("short"));
  EXPECT_TRUE(validate_live_token("has space in it"));
  EXPECT_TRUE(validate_live_token("a&token=b-long-enough"));
  EXPECT_FALSE(validate_allowed_host("boat.local"));
  EXPECT_TRUE(validate_allowed_host("boat.local:8765"));
  EXPECT_FALSE(validate_allowed_origin("https://app.foxglove.dev"));
  EXPECT_FALSE(validate_allowed_origin("http://192.168.4.2:8080"));
  EXPECT_TRUE(validate_allowed_origin("app.foxglove.dev"));
  EXPECT_TRUE(validate_allowed_origin("https://app.foxglove.dev/"));
}

}  // namespace
}  // namespace coxswain::config
