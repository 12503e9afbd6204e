// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/run_dir.hpp"

#include <array>
#include <cstdio>
#include <string_view>

namespace coxswain::app {
namespace {

// Parses NN from "YYMMDD-HHMMSS-<mission>-NN" when the day and mission match; 0 otherwise.
int run_number(std::string_view name, std::string_view day, std::string_view mission) {
  if (name.size() < day.size() + 8 + mission.size() + 3) return 0;
  if (name.substr(0, day.size()) != day || name[6] != '-' || name[13] != '-') return 0;
  const std::string_view rest = name.substr(14);
  if (rest.size() < mission.size() + 2 || rest.substr(0, mission.size()) != mission ||
      rest[mission.size()] != '-') {
    return 0;
  }
  const std::string_view digits = rest.substr(mission.size() + 1);
  int n = 0;
  for (char c : digits) {
    if (c < '0' || c > '9') return 0;
    n = n * 10 + (c - '0');
  }
  return n;
}

}  // namespace

std::filesystem::path create_run_dir(const std::filesystem::path& base, const std::string& mission,
                                     std::time_t when) {
  std::tm local{};
  localtime_r(&when, &local);
  // Two-digit year on purpose: the source team's YYMMDD naming.
  std::array<char, 32> stamp{};
  std::snprintf(stamp.data(), stamp.size(), "%02d%02d%02d-%02d%02d%02d", local.tm_year % 100,
                local.tm_mon + 1, local.tm_mday, local.tm_hour, local.tm_min, local.tm_sec);
  const std::string day(stamp.data(), 6);

  std::filesystem::create_directories(base);
  int highest = 0;
  for (const auto& entry : std::filesystem::directory_iterator(base)) {
    if (entry.is_directory()) {
      highest = std::max(highest, run_number(entry.path().filename().string(), day, mission));
    }
  }
  // create_directory fails if another process took the name first: then try the next number.
  for (int n = highest + 1;; ++n) {
    std::array<char, 16> number{};
    std::snprintf(number.data(), number.size(), "%02d", n);
    const std::filesystem::path dir =
        base / (std::string(stamp.data()) + "-" + mission + "-" + number.data());
    if (std::filesystem::create_directory(dir)) return dir;
  }
}

}  // namespace coxswain::app
