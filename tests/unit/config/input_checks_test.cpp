// SPDX-License-Identifier: Apache-2.0
#include "coxswain/config/input_checks.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "coxswain/config/config.hpp"
#include "support/testdata.hpp"

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

// The devices file's addresses, paths and URLs are checked when it is read, so `check-config`
// reports each at its line instead of the daemon failing at run time.
TEST(InputChecks, ADevicesFileWithBadAddressesIsRefusedAtEachLine) {
  std::ifstream in(testing::source_dir() / "config" / "devices.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  const auto swap = [&](const std::string& from, const std::string& to) {
    const auto at = yaml.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    yaml.replace(at, from.size(), to);
  };
  swap("rtcm_input: \"\"", "rtcm_input: ntrip://caster:2101");
  swap("http_address: 127.0.0.1", "http_address: localhost");
  swap("control_socket: \"\"", "control_socket: /" + std::string(120, 's'));
  swap("allowed_hosts: []", "allowed_hosts: [boat.local, \"bad host\"]");
  swap("allowed_origins: [https://app.foxglove.dev]", "allowed_origins: [ftp://boat.local]");
  const auto path = std::filesystem::temp_directory_path() /
                    ("coxswain_devices_checks_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(path) << yaml;
  ConfigErrors errors;
  (void)load_devices_config(path.string(), errors);
  std::filesystem::remove(path);
  for (const char* key : {"gnss.rtcm_input", "live.http_address", "live.control_socket",
                          "live.allowed_hosts", "live.allowed_origins"}) {
    bool found = false;
    for (const ConfigIssue& i : errors.issues()) found |= i.key == key && i.line > 0;
    EXPECT_TRUE(found) << key << " not reported:\n" << errors.format();
  }
}

// The live server's allow-lists are read from the devices file like every other parameter.
TEST(InputChecks, TheLiveAllowListsAreReadFromTheDevicesFile) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("coxswain_devices_allow_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(path) << "kind: devices\n"
                         "lidar: {enabled: false}\nimu: {enabled: false}\ngnss: {enabled: false}\n"
                         "arduino: {enabled: false}\ncamera: {enabled: false}\n"
                         "live: {allowed_hosts: [boat.local, 192.168.4.1],\n"
                         "       allowed_origins: [\"http://boat.local:8765\"]}\n";
  ConfigErrors errors;
  const DevicesConfig d = load_devices_config(path.string(), errors);
  std::filesystem::remove(path);
  ASSERT_TRUE(errors.empty()) << errors.format();
  EXPECT_EQ(d.live.allowed_hosts, (std::vector<std::string>{"boat.local", "192.168.4.1"}));
  EXPECT_EQ(d.live.allowed_origins, (std::vector<std::string>{"http://boat.local:8765"}));
  // Left out, the shipped defaults hold: Foxglove's web app may connect, no extra host name.
  EXPECT_TRUE(DevicesConfig{}.live.allowed_hosts.empty());
  EXPECT_EQ(DevicesConfig{}.live.allowed_origins,
            (std::vector<std::string>{"https://app.foxglove.dev"}));
}

}  // namespace
}  // namespace coxswain::config
