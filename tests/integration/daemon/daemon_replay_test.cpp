// SPDX-License-Identifier: Apache-2.0
// The flight recording of the real daemon (a child process sailing the 2026 course against the
// device emulators in real time, sim/devices_mode) replayed by `coxswain replay`: every decision
// the daemon took (command, state path, visualization) is reproduced bit for bit from the
// recorded inputs, and every input replay needs is in the file (no scan missing). The run is
// kept short (about 30 s of wall time) so CI can afford it.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>

#include "coxswain/replay/replay.hpp"
#include "sim/devices_mode/devices_mode.hpp"
#include "support/run_command.hpp"

namespace coxswain::sim::devices_mode {
namespace {

namespace fs = std::filesystem;

const fs::path kConfig = COXSWAIN_TEST_CONFIG_DIR;

struct Ran {
  int status = -1;
  std::string output;
};

// Runs a shell command, capturing stdout and stderr.
Ran run_command(const std::string& command) {
  const coxswain::test::CommandResult r = coxswain::test::run_shell(command + " 2>&1");
  return {r.status, r.out};
}

TEST(DaemonReplay, ADevicesModeRecordingReplaysBitForBit) {
  const fs::path run_dir =
      fs::temp_directory_path() / ("coxswain-daemon-replay-" + std::to_string(::getpid()));
  fs::remove_all(run_dir);
  DevicesModeOptions o;
  o.course_file = kConfig / "courses" / "kaboat2026.yaml";
  o.mission_file = kConfig / "missions" / "kaboat2026.yaml";
  o.run_dir = run_dir;
  o.time_limit_s = 26.0;  // start-up, GPS calibration, then sailing course 1
  o.record = true;
  DevicesOutcome outcome;
  {
    DevicesMode mode(o);
    const std::atomic<bool> never{false};
    outcome = mode.run(&never);
  }
  EXPECT_EQ(outcome.daemon_exit_status, 0);

  fs::path mcap;
  for (const auto& e : fs::recursive_directory_iterator(run_dir / "daemon")) {
    if (e.path().filename() == "run.mcap") mcap = e.path();
  }
  ASSERT_FALSE(mcap.empty()) << "the daemon wrote no recording under " << run_dir / "daemon";

  // The program CI and an operator run.
  const Ran r =
      run_command(std::string("'") + COXSWAIN_BINARY + "' replay '" + mcap.string() + "'");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("identical"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("truncated"), std::string::npos) << r.output;

  // And what it compared: the run got past the start, every tick's scene was rebuilt.
  const replay::Recording rec = replay::load_recording(mcap);
  ASSERT_TRUE(rec.ok) << rec.error;
  EXPECT_TRUE(rec.file.complete);
  config::ConfigErrors errors;
  const auto config = replay::configuration_from_yaml(rec.config_yaml, errors);
  ASSERT_TRUE(config) << errors.format();
  const replay::ReplayReport report = replay::replay(rec, *config);
  ASSERT_TRUE(report.ok) << report.error;
  EXPECT_TRUE(report.identical()) << replay::format_replay_report(report, true);
  EXPECT_GE(report.ticks, 800U);  // 50 Hz for most of the run
  // Every recorded /viz/scene (one per 200 ms of the 50 Hz ticks) was rebuilt and matched.
  EXPECT_EQ(report.viz_compared, rec.viz_scene.size());
  EXPECT_GE(report.viz_compared, report.ticks / 12);
  EXPECT_EQ(report.lidar_scans_missing, 0U);
  bool sailed = false;
  for (const auto& p : report.recorded_paths) sailed = sailed || p.path.starts_with("course1/");
  EXPECT_TRUE(sailed) << replay::format_replay_report(report, true);
  EXPECT_GT(rec.lidar.size(), 100U);  // the scans the core saw, at 10 Hz

  std::error_code ec;
  fs::remove_all(run_dir, ec);
}

}  // namespace
}  // namespace coxswain::sim::devices_mode
