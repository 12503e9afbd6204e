// SPDX-License-Identifier: Apache-2.0
// A lockstep simulator run of a shipped course recorded as the daemon records, replayed by the
// `coxswain replay` program (every decision identical), replayed with a changed parameter
// (differences reported), and reported by `coxswain report` (every plot drawn, checked in
// headless Chromium when it is installed).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "coxswain/replay/replay.hpp"
#include "coxswain/report/report.hpp"
#include "sim_recording.hpp"
#include "support/run_command.hpp"
#include "support/testdata.hpp"

namespace coxswain {
namespace {

namespace fs = std::filesystem;

struct Ran {
  int status = -1;
  std::string output;
};

// Runs a shell command, capturing stdout and stderr.
Ran run(const std::string& command) {
  const coxswain::test::CommandResult r = coxswain::test::run_shell(command + " 2>&1");
  return {r.status, r.out};
}

std::string quote(const fs::path& p) { return "'" + p.string() + "'"; }

class ReplaySim : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("coxswain-replay-test-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    mcap_ = dir_ / "run.mcap";
    const config::Configuration config = test::shipped_config("hopping");
    result_ = test::record_sim_run(mcap_, config, "kaboat2022_hopping.yaml", 30.0);
  }
  static void TearDownTestSuite() {
    if (std::getenv("COXSWAIN_KEEP_TEST_OUTPUT") != nullptr) return;  // to look at the report
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  static inline fs::path dir_;
  static inline fs::path mcap_;
  static inline test::SimRecordingResult result_;
};

TEST_F(ReplaySim, RecordingHoldsEveryInput) {
  ASSERT_TRUE(result_.ok) << result_.error;
  EXPECT_GE(result_.ticks, 1450U);  // 30 s at 50 Hz
  EXPECT_EQ(result_.dropped, 0U);
  const replay::Recording rec = replay::load_recording(mcap_);
  ASSERT_TRUE(rec.ok) << rec.error;
  EXPECT_TRUE(rec.file.complete);
  EXPECT_FALSE(rec.config_yaml.empty());
  EXPECT_GT(rec.lidar.size(), 250U);  // 10 Hz
  EXPECT_TRUE(rec.file.metadata.contains("course"));
}

TEST_F(ReplaySim, ReplayProgramFindsEveryDecisionIdentical) {
  ASSERT_TRUE(result_.ok) << result_.error;
  const Ran r = run(std::string(COXSWAIN_BINARY) + " replay " + quote(mcap_));
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("identical"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
  // The boat left the start: the run exercised more than waiting.
  const replay::Recording rec = replay::load_recording(mcap_);
  config::ConfigErrors errors;
  const auto config = replay::configuration_from_yaml(rec.config_yaml, errors);
  ASSERT_TRUE(config) << errors.format();
  const replay::ReplayReport report = replay::replay(rec, *config);
  EXPECT_TRUE(report.identical());
  EXPECT_GE(report.recorded_paths.size(), 2U);
  EXPECT_EQ(report.lidar_scans_missing, 0U);
}

TEST_F(ReplaySim, ChangedParameterReportsTheDivergence) {
  ASSERT_TRUE(result_.ok) << result_.error;
  // The shipped hopping mission with a stiffer heading controller.
  std::ifstream in(testing::source_dir() / "config" / "missions" / "hopping.yaml");
  std::stringstream text;
  text << in.rdbuf();
  const std::string changed =
      std::regex_replace(text.str(), std::regex("kp_per_deg: 0\\.0222"), "kp_per_deg: 0.04");
  ASSERT_NE(changed, text.str());
  const fs::path mission = dir_ / "hopping_stiff.yaml";
  std::ofstream(mission) << changed;
  const Ran r = run(std::string(COXSWAIN_BINARY) + " --config-dir " +
                    quote(testing::source_dir() / "config") + " --mission " + quote(mission) +
                    " replay --max-diffs 5 " + quote(mcap_));
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("first divergence at tick"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("command.pulse_us[0]"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("replayed state paths"), std::string::npos) << r.output;
  // And the same files unchanged replay identically through the override path.
  const Ran same =
      run(std::string(COXSWAIN_BINARY) + " --config-dir " +
          quote(testing::source_dir() / "config") + " --mission hopping replay " + quote(mcap_));
  EXPECT_EQ(same.status, 0) << same.output;
}

// `coxswain-sim run --record` (realistic GNSS with wandering bias, IMU, lidar and the rendered
// camera through the daemon's camera pipeline) replayed by `coxswain replay`: every command,
// state path and the visualization (/tf, /viz/scene: full doubles, so they show differences the
// integer pulse widths round away) identical. Once the recorded configuration lost the origin's
// height and printed doubles to 6 digits: the replayed frame moved, the pulses still matched,
// the poses did not.
TEST(ReplaySimProgram, RealisticSensorRunsReplayIdentically) {
  const fs::path dir =
      fs::temp_directory_path() / ("coxswain-replay-realistic-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path config = testing::source_dir() / "config";
  struct Case {
    const char* course;
    const char* mission;
    const char* extra;
  };
  for (const Case& c : {Case{"kaboat2026", "kaboat2026", "--seed 1 --max-time 60"},
                        Case{"kaboat2022_hopping", "hopping", "--seed 2 --disturbances"},
                        Case{"kaboat2022_obstacle_final", "obstacle_course", "--seed 3"}}) {
    const fs::path mcap = dir / (std::string(c.course) + ".mcap");
    // From the source tree, as the README runs it (the boat and devices files by default).
    const Ran sim =
        run("cd " + quote(testing::source_dir()) + " && " + std::string(COXSWAIN_SIM_BINARY) +
            " run --course " + quote(config / "courses" / (std::string(c.course) + ".yaml")) +
            " --mission " + quote(config / "missions" / (std::string(c.mission) + ".yaml")) + " " +
            c.extra + " --record " + quote(mcap));
    ASSERT_LE(sim.status, 1) << sim.output;  // 1: the run did not pass, which is fine here
    const Ran r = run(std::string(COXSWAIN_BINARY) + " replay " + quote(mcap));
    EXPECT_EQ(r.status, 0) << c.course << "\n" << r.output;
    EXPECT_NE(r.output.find("identical"), std::string::npos) << c.course << "\n" << r.output;
    EXPECT_EQ(r.output.find("warning"), std::string::npos) << c.course << "\n" << r.output;
  }
  if (std::getenv("COXSWAIN_KEEP_TEST_OUTPUT") == nullptr) {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
}

TEST_F(ReplaySim, UnreadableRecordingExitsTwo) {
  const fs::path junk = dir_ / "junk.mcap";
  std::ofstream(junk) << "not an mcap file";
  EXPECT_EQ(run(std::string(COXSWAIN_BINARY) + " replay " + quote(junk)).status, 2);
  EXPECT_EQ(run(std::string(COXSWAIN_BINARY) + " replay " + quote(dir_ / "absent.mcap")).status, 2);
}

TEST_F(ReplaySim, DecodeReplaysTheCodecs) {
  ASSERT_TRUE(result_.ok) << result_.error;
  const Ran r = run(std::string(COXSWAIN_BINARY) + " replay --decode " + quote(mcap_));
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("lidar"), std::string::npos) << r.output;
}

TEST_F(ReplaySim, ReportRendersEveryPlotInChromium) {
  ASSERT_TRUE(result_.ok) << result_.error;
  const fs::path html = dir_ / "report.html";
  const Ran r =
      run(std::string(COXSWAIN_BINARY) + " report " + quote(mcap_) + " -o " + quote(html));
  ASSERT_EQ(r.status, 0) << r.output;
  std::ifstream in(html);
  std::stringstream page;
  page << in.rdbuf();
  // Self-contained: no external script, stylesheet, font or image (a url() may only name an
  // element of the page itself, as a clip path does).
  EXPECT_EQ(page.str().find("src="), std::string::npos);
  EXPECT_EQ(page.str().find("<link"), std::string::npos);
  EXPECT_FALSE(std::regex_search(page.str(), std::regex(R"(url\([^#])")));
  if (run("command -v chromium").status != 0) {
    GTEST_SKIP() << "chromium is not installed (apt package chromium): the page was not rendered";
  }
  const fs::path profile = dir_ / "chromium-profile";
  const Ran dom =
      run("timeout 60 chromium --headless --no-sandbox --disable-gpu "
          "--disable-dev-shm-usage --disable-background-networking "
          "--disable-component-update --no-first-run --user-data-dir=" +
          quote(profile) + " --dump-dom " + quote("file://" + html.string()));
  ASSERT_EQ(dom.status, 0) << dom.output.substr(0, 2000);
  for (const char* id : report::kPlotIds) {
    const std::regex rendered(std::string("<svg[^>]*id=\"") + id +
                              "\"[^>]*data-rendered=\"true\"[^>]*data-points=\"([0-9]+)\"");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(dom.output, m, rendered)) << "plot " << id << " not rendered";
    EXPECT_GT(std::stoul(m[1].str()), 0U) << "plot " << id << " drew nothing";
  }
  EXPECT_NE(dom.output.find("<p id=\"error\" style=\"color:#c00\"></p>"), std::string::npos)
      << "the page reported a drawing error";
}

}  // namespace
}  // namespace coxswain
