// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/run_dir.hpp"

#include <gtest/gtest.h>

#include <filesystem>

namespace coxswain::app {
namespace {

namespace fs = std::filesystem;

TEST(RunDir, NamesCountRunsOfTheMissionPerDay) {
  const fs::path base = fs::temp_directory_path() / "coxswain_run_dir_test";
  fs::remove_all(base);
  std::tm tm{};
  tm.tm_year = 122;  // 2022
  tm.tm_mon = 7;
  tm.tm_mday = 23;
  tm.tm_hour = 14;
  tm.tm_min = 5;
  tm.tm_sec = 9;
  tm.tm_isdst = -1;
  const std::time_t when = std::mktime(&tm);
  EXPECT_EQ(create_run_dir(base, "hopping", when).filename(), "220823-140509-hopping-01");
  EXPECT_EQ(create_run_dir(base, "hopping", when).filename(), "220823-140509-hopping-02");
  EXPECT_EQ(create_run_dir(base, "docking", when).filename(), "220823-140509-docking-01");
  EXPECT_EQ(create_run_dir(base, "hopping", when + 60).filename(), "220823-140609-hopping-03");
  EXPECT_EQ(create_run_dir(base, "hopping", when + 86400).filename(), "220824-140509-hopping-01");
  fs::remove_all(base);
}

}  // namespace
}  // namespace coxswain::app
