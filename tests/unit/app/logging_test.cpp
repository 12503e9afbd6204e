// SPDX-License-Identifier: Apache-2.0
// The daemon's log: a repeated warning is written once per window and then counted ("... N
// similar suppressed"), the same in the file and in what the tap (the recording's /log) gets;
// the file rotates at its size cap; a device's health is one line per change of its words, not
// one per telemetry frame whose detail only re-measures.
#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "coxswain/app/health_reporter.hpp"
#include "coxswain/app/logging.hpp"

namespace coxswain::app {
namespace {

namespace fs = std::filesystem;
using Clock = RepeatLimiter::Clock;
using std::chrono::seconds;

constexpr int kWarn = 3;
constexpr int kError = 4;

struct Reported {
  int level;
  std::uint64_t count;
  std::string last;
};

std::vector<Reported> expire(RepeatLimiter& limiter, Clock::time_point now) {
  std::vector<Reported> out;
  limiter.expire(now, [&](int level, std::uint64_t count, const std::string& last) {
    out.push_back({level, count, last});
  });
  return out;
}

TEST(RepeatLimiter, WritesTheFirstLineAndCountsItsRepeatsUntilTheWindowEnds) {
  RepeatLimiter limiter(seconds(10));
  const Clock::time_point t0{};
  EXPECT_TRUE(limiter.admit(kWarn, "gnss: no fix for 120 ms", t0));
  EXPECT_FALSE(limiter.admit(kWarn, "gnss: no fix for 170 ms", t0 + seconds(1)));
  EXPECT_FALSE(limiter.admit(kWarn, "gnss: no fix for 9.5 ms", t0 + seconds(9)));
  EXPECT_TRUE(expire(limiter, t0 + seconds(5)).empty()) << "the window is still open";
  const auto reported = expire(limiter, t0 + seconds(10));
  ASSERT_EQ(reported.size(), 1U);
  EXPECT_EQ(reported[0].level, kWarn);
  EXPECT_EQ(reported[0].count, 2U);
  EXPECT_EQ(reported[0].last, "gnss: no fix for 9.5 ms");
  // A new window: the next repeat is written again.
  EXPECT_TRUE(limiter.admit(kWarn, "gnss: no fix for 300 ms", t0 + seconds(11)));
}

TEST(RepeatLimiter, OtherWordsOrAnotherLevelAreNotSimilar) {
  RepeatLimiter limiter(seconds(10));
  const Clock::time_point t0{};
  EXPECT_TRUE(limiter.admit(kWarn, "lidar: closed /dev/ttyLiDAR: unplugged", t0));
  EXPECT_TRUE(limiter.admit(kWarn, "imu: closed /dev/ttyIMU: unplugged", t0));
  EXPECT_TRUE(limiter.admit(kError, "lidar: closed /dev/ttyLiDAR: unplugged", t0));
  EXPECT_FALSE(limiter.admit(kWarn, "lidar: closed /dev/ttyLiDAR: unplugged", t0));
}

TEST(RepeatLimiter, StateChangesAreNeverLimited) {
  RepeatLimiter limiter(seconds(10));
  const Clock::time_point t0{};
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(limiter.admit(kWarn, "device lidar: absent (no /dev/ttyLiDAR)", t0));
    EXPECT_TRUE(limiter.admit(kWarn, "mission: transit -> hold: lidar stale", t0));
  }
  EXPECT_TRUE(expire(limiter, t0 + seconds(20)).empty());
}

TEST(RepeatLimiter, AWindowWithoutRepeatsReportsNothing) {
  RepeatLimiter limiter(seconds(1));
  const Clock::time_point t0{};
  EXPECT_TRUE(limiter.admit(kWarn, "once", t0));
  EXPECT_TRUE(expire(limiter, t0 + seconds(2)).empty());
}

TEST(RepeatLimiter, PastItsKeyCapNewLinesPassUnlimited) {
  RepeatLimiter limiter(seconds(10), 2);
  const Clock::time_point t0{};
  EXPECT_TRUE(limiter.admit(kWarn, "a", t0));
  EXPECT_TRUE(limiter.admit(kWarn, "b", t0));
  EXPECT_TRUE(limiter.admit(kWarn, "c", t0));
  EXPECT_TRUE(limiter.admit(kWarn, "c", t0));
  EXPECT_FALSE(limiter.admit(kWarn, "a", t0));
}

TEST(RepeatLimiter, SimilarMeansEqualButForNumbers) {
  EXPECT_EQ(RepeatLimiter::key_of("supply 12.00 V, seq 4/17"), "supply # V, seq #/#");
  EXPECT_NE(RepeatLimiter::key_of("failsafe no"), RepeatLimiter::key_of("failsafe yes"));
}

TEST(HealthReporter, DetailsThatOnlyReMeasureHaveTheSameWords) {
  EXPECT_TRUE(HealthReporter::same_words(
      "running: source auto, failsafe no, supply 12.00 V, last seq 3/3",
      "running: source auto, failsafe no, supply 11.98 V, last seq 104/104"));
  EXPECT_FALSE(HealthReporter::same_words("running: source auto, failsafe no, supply 12.00 V",
                                          "running: source auto, failsafe yes, supply 12.00 V"));
  EXPECT_FALSE(HealthReporter::same_words("stale: 300 ms", "stale: 300 ms, reopening"));
  EXPECT_FALSE(HealthReporter::same_words("ab", "a"));
  EXPECT_TRUE(HealthReporter::same_words("", ""));
}

// An absent device names where its path is set, once for the outage (not at every retry), and
// the line devices mode parses ("device gnss: absent (") keeps its shape.
TEST(HealthReporter, AnAbsentDeviceIsLoggedOnceWithWhereItsPathIsSet) {
  std::ostringstream text;
  auto logger = std::make_shared<spdlog::logger>(
      "health_test", std::make_shared<spdlog::sinks::ostream_sink_mt>(text));
  logger->set_pattern("%l %v");
  const auto previous = spdlog::default_logger();
  spdlog::set_default_logger(logger);
  core::LatestStore store;
  core::Snapshot snapshot;
  HealthReporter reporter;
  reporter.set_origin(msg::DeviceId::kGnss, "gnss.path in devices.yaml");
  msg::DeviceHealth h;
  h.device = msg::DeviceId::kGnss;
  h.state = msg::DeviceState::kAbsent;
  for (int retry = 0; retry < 5; ++retry) {
    h.set_detail("/dev/ttyGPS: No such file or directory (device not plugged in?)");
    store.health_of(msg::DeviceId::kGnss).publish(h, 1000 + retry);
    store.snapshot(snapshot);
    (void)reporter.report_changes(snapshot);
  }
  h.state = msg::DeviceState::kRunning;
  h.set_detail("nav-pvt 5 Hz");
  store.health_of(msg::DeviceId::kGnss).publish(h, 2000);
  store.snapshot(snapshot);
  (void)reporter.report_changes(snapshot);
  spdlog::set_default_logger(previous);
  const std::string log = text.str();
  EXPECT_NE(log.find("warning device gnss: absent (/dev/ttyGPS: No such file or directory (device "
                     "not plugged in?)) [gnss.path in devices.yaml]"),
            std::string::npos)
      << log;
  EXPECT_EQ(log.find("gnss.path"), log.rfind("gnss.path")) << "logged more than once:\n" << log;
  EXPECT_NE(log.find("info device gnss: running (nav-pvt 5 Hz)\n"), std::string::npos) << log;
}

class Logging : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("coxswain_logging_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
  static int count(const std::string& text, const std::string& what) {
    int n = 0;
    for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
  }
  fs::path dir_;
};

TEST_F(Logging, ARepeatedWarningIsOneLineAndACountInTheFileAndTheTap) {
  setup_logging(dir_ / "coxswain.log", 2);  // info
  std::ostringstream tapped;
  const auto tap = std::make_shared<spdlog::sinks::ostream_sink_mt>(tapped);
  ASSERT_TRUE(attach_log_sink(tap, 2));
  spdlog::info("starting");
  for (int i = 0; i < 50; ++i) spdlog::warn("arduino: telemetry {} late by {} ms", i, 20 + i);
  spdlog::info("stopping");
  shutdown_logging();
  for (const std::string& text : {slurp(dir_ / "coxswain.log"), tapped.str()}) {
    EXPECT_EQ(count(text, "telemetry 0 late by 20 ms"), 1) << text;
    EXPECT_EQ(count(text, "late by"), 2) << text;  // the first line and the count's last one
    EXPECT_EQ(count(text, "... 49 similar suppressed (last: arduino: telemetry 49 late by 69 ms)"),
              1)
        << text;
    EXPECT_EQ(count(text, "starting"), 1);
    EXPECT_EQ(count(text, "stopping"), 1);
  }
}

TEST_F(Logging, TheFileRotatesAtItsSizeCap) {
  setup_logging(dir_ / "coxswain.log", 2, LogFileLimits{4096, 2});
  for (int i = 0; i < 400; ++i) spdlog::info("line {} of a long run, different every time", i);
  shutdown_logging();
  ASSERT_TRUE(fs::exists(dir_ / "coxswain.log"));
  EXPECT_LE(fs::file_size(dir_ / "coxswain.log"), 4096U);
  EXPECT_TRUE(fs::exists(dir_ / "coxswain.1.log"));
  EXPECT_TRUE(fs::exists(dir_ / "coxswain.2.log"));
  EXPECT_FALSE(fs::exists(dir_ / "coxswain.3.log"));
  EXPECT_NE(slurp(dir_ / "coxswain.log").find("line 399 "), std::string::npos);
}

}  // namespace
}  // namespace coxswain::app
