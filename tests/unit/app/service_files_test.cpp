// SPDX-License-Identifier: Apache-2.0
// The shipped unit files and udev rules say what the daemon relies on.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "support/testdata.hpp"

namespace {

std::string read_file(const std::string& relative) {
  std::ifstream in(coxswain::testing::source_dir() / relative);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool has_line(const std::string& text, const std::string& line) {
  return std::regex_search(text, std::regex("(^|\n)" + line + "(\n|$)"));
}

TEST(ServiceFiles, NotifyWatchdogRestartAndUser) {
  for (const char* unit : {"systemd/coxswain.service", "systemd/coxswain@.service"}) {
    const std::string text = read_file(unit);
    ASSERT_FALSE(text.empty()) << unit;
    EXPECT_TRUE(has_line(text, "Type=notify")) << unit;
    EXPECT_TRUE(has_line(text, "WatchdogSec=2s")) << unit;
    EXPECT_TRUE(has_line(text, "Restart=on-failure")) << unit;
    EXPECT_TRUE(has_line(text, "User=coxswain")) << unit;
    EXPECT_TRUE(has_line(text, "SupplementaryGroups=dialout video")) << unit;
    EXPECT_TRUE(has_line(text, "NoNewPrivileges=yes")) << unit;
  }
  EXPECT_NE(read_file("systemd/coxswain@.service").find("--mission %i run"), std::string::npos);
  const std::string users = read_file("systemd/coxswain.sysusers");
  EXPECT_TRUE(has_line(users, "m coxswain dialout"));
}

TEST(UdevRules, StableNamesByVendorAndProduct) {
  const std::string rules = read_file("udev/99-coxswain.rules");
  const struct {
    const char* vid;
    const char* pid;
    const char* name;
  } devices[] = {{"0483", "5740", "ttyIMU"},
                 {"10c4", "ea60", "ttyLiDAR"},
                 {"1546", "01a9", "ttyGPS"},
                 {"2341", "0044", "ttyARDUINO"}};
  for (const auto& d : devices) {
    const std::regex line(std::string("ATTRS\\{idVendor\\}==\"") + d.vid +
                          "\", ATTRS\\{idProduct\\}==\"" + d.pid + "\", SYMLINK\\+=\"" + d.name +
                          "\"[^\n]*ID_MM_DEVICE_IGNORE\\}=\"1\"");
    EXPECT_TRUE(std::regex_search(rules, line)) << d.name;
  }
  EXPECT_NE(rules.find("SYMLINK+=\"videoCAM\""), std::string::npos);
  EXPECT_EQ(rules.find("0777"), std::string::npos);  // never world-writable devices
}

}  // namespace
