// SPDX-License-Identifier: Apache-2.0
// The command lines of `coxswain` and `coxswain-sim` as a user types them: a usage error exits 2
// with a one-line hint, --help and --version exit 0 on both, help shows defaults, every
// invocation the README and docs/ show is accepted, one spelling of the docking target on both,
// the batch's JSON (stdout only, rounded, failed seeds each with a command that reproduces it),
// and devices mode's progress arriving line by line through a pipe while the run goes on.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "support/run_command.hpp"
#include "support/testdata.hpp"

namespace {

using coxswain::test::slurp;

namespace fs = std::filesystem;

using Ran = coxswain::test::CommandResult;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty()) out.push_back(line);
  }
  return out;
}

// What a usage error prints; a command that parsed never prints it.
constexpr const char* kUsageHint = "--help' for the options";

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("coxswain_cli_usage_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Runs `exe args` (a shell command line, so arguments are quoted by the caller where needed) in
  // the source folder, where the shipped relative config paths resolve.
  Ran run(const char* exe, const std::string& args) {
    const std::string cmd = "cd '" + coxswain::testing::source_dir().string() +
                            "' && env -u COXSWAIN_LOG_DIR COXSWAIN_CONTROL_SOCKET='" +
                            (dir_ / "no.sock").string() + "' '" + exe + "' " + args;
    return coxswain::test::run_to_files(cmd, dir_);
  }
  Ran coxswain(const std::string& args) { return run(COXSWAIN_EXE, args); }
  Ran sim(const std::string& args) { return run(COXSWAIN_SIM_EXE, args); }
  std::string path(const std::string& name) const { return "'" + (dir_ / name).string() + "'"; }

  fs::path dir_;
};

TEST_F(Cli, UsageErrorsExitTwoWithTheProblemAndAOneLineHint) {
  for (const auto& [is_sim, args] : std::vector<std::pair<bool, std::string>>{
           {false, "--no-such-option"},
           {false, "replay"},                       // the recording is missing
           {false, "run --target red"},             // COLOUR SHAPE is two words
           {false, "decode --device sonar x"},      // not a codec
           {false, "replay a.mcap b.mcap"},         // one recording
           {false, "replay --dump-config a.mcap"},  // the folder is missing
           {true, "--no-such-option"},
           {true, ""},                                    // a subcommand is required
           {true, "batch --kind submarine"},              // not a kind
           {true, "batch --runs many"},                   // not a number
           {true, "course generate --kind obstacle"}}) {  // -o is required
    const Ran r = is_sim ? sim(args) : coxswain(args);
    EXPECT_EQ(r.status, 2) << args << "\n" << r.err;
    const auto lines = lines_of(r.err);
    ASSERT_EQ(lines.size(), 2U) << args << "\n" << r.err;
    EXPECT_TRUE(lines[0].starts_with(is_sim ? "coxswain-sim" : "coxswain")) << lines[0];
    EXPECT_NE(lines[1].find(kUsageHint), std::string::npos) << lines[1];
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
}

TEST_F(Cli, TheHintNamesTheSubcommandThatWasBeingParsed) {
  const Ran r = coxswain("replay --frobnicate x.mcap");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("Try 'coxswain replay --help'"), std::string::npos) << r.err;
}

TEST_F(Cli, BothProgramsAnswerVersionAndHelpWithStatusZero) {
  const std::regex version(R"(^coxswain(-sim)? \d+\.\d+\.\d+ \(git [0-9a-z-]+\))");
  for (const bool is_sim : {false, true}) {
    const Ran v = is_sim ? sim("--version") : coxswain("--version");
    EXPECT_EQ(v.status, 0);
    EXPECT_TRUE(std::regex_search(v.out, version)) << v.out;
    const Ran h = is_sim ? sim("--help") : coxswain("--help");
    EXPECT_EQ(h.status, 0);
    EXPECT_NE(h.out.find("Usage:"), std::string::npos);
  }
  EXPECT_EQ(sim("batch --help").status, 0);
  EXPECT_EQ(coxswain("run --help").status, 0);
}

TEST_F(Cli, HelpShowsEachDefault) {
  const Ran c = coxswain("--help");
  EXPECT_TRUE(std::regex_search(c.out, std::regex(R"(--mission TEXT=kaboat2026)"))) << c.out;
  EXPECT_TRUE(std::regex_search(c.out, std::regex(R"(--log-dir TEXT=runs)"))) << c.out;
  EXPECT_TRUE(std::regex_search(c.out, std::regex(R"(--log-level TEXT=info)"))) << c.out;
  const Ran b = sim("batch --help");
  EXPECT_TRUE(std::regex_search(b.out, std::regex(R"(--runs INT=100)"))) << b.out;
  EXPECT_TRUE(std::regex_search(b.out, std::regex(R"(--seed0 UINT=1)"))) << b.out;
  EXPECT_TRUE(std::regex_search(b.out, std::regex(R"(--max-time FLOAT=900)"))) << b.out;
  // An empty list says nothing, so it is not shown as a default.
  EXPECT_EQ(b.out.find("=[]"), std::string::npos) << b.out;
}

// Each command line of the README's "Using it" and "Simulator" sections and of docs/ parses: it
// may fail for want of a recording or a daemon, never as a usage error.
TEST_F(Cli, EveryDocumentedCoxswainInvocationParses) {
  const std::string missing_mcap = path("RUN/run.mcap");
  const std::string runs = path("runs");
  const std::vector<std::string> invocations{
      "--print-config",
      "--mission hopping --print-config",
      "--mission config/missions/hopping.yaml --print-config",
      "check-config config/boat.yaml config/devices.yaml",
      "config doc",
      "config schema mission",
      "replay " + missing_mcap,
      "--mission config/missions/hopping.yaml replay " + missing_mcap,
      "replay --mission config/missions/hopping.yaml " + missing_mcap,
      "replay --config-dir config --boat config/boat.yaml " + missing_mcap,
      "replay --decode " + missing_mcap,
      "replay --dump-config " + missing_mcap + " " + path("dump"),
      "replay --config-dir " + path("dump") + " --mission " + path("dump/mission.yaml") + " " +
          missing_mcap,
      "report " + missing_mcap + " -o " + path("report.html"),
      "report --mission hopping " + missing_mcap,
      "decode --device ublox " + path("gnss.raw"),
      "ctl status",
      "ctl --log-dir " + runs + " status",
      "ctl status --log-dir " + runs,
      "ctl target green cross",
      "--log-dir " + runs + " ctl start",
      // A run that stops at its (missing) mission file, after every option parsed.
      "--mission " + path("none.yaml") + " run",
      "run --mission " + path("none.yaml") + " --log-dir " + runs + " --target red triangle",
      "run --mission " + path("none.yaml") + " --run-for-s 10 --stop-when-finished --no-record " +
          "--capture-dir " + path("capture") + " --log-level debug",
  };
  for (const std::string& args : invocations) {
    const Ran r = coxswain(args);
    EXPECT_EQ(r.err.find(kUsageHint), std::string::npos) << "coxswain " << args << "\n" << r.err;
    EXPECT_EQ(r.err.find("not expected"), std::string::npos) << args << "\n" << r.err;
  }
  // The options after the subcommand are the same options: the run's mission is the one named.
  const Ran after = coxswain("run --mission " + path("none.yaml") + " --log-dir " + runs);
  EXPECT_EQ(after.status, 2);
  EXPECT_NE(after.err.find("none.yaml"), std::string::npos) << after.err;
  EXPECT_FALSE(fs::exists(dir_ / "runs")) << "a run with a bad mission creates no run folder";
}

TEST_F(Cli, EveryDocumentedSimulatorInvocationParses) {
  const std::string course = path("course.yaml");
  const std::vector<std::string> invocations{
      "course check config/courses/kaboat2026.yaml",
      "course generate --kind obstacle --seed 3 -o " + course,
      "course svg " + course + " -o " + path("course.svg"),
      "course drive " + course + " --ch0-us 1500 --ch1-us 1700 --seconds 1 --svg " +
          path("drive.svg"),
      "run --course config/courses/kaboat2022_hopping.yaml --mission config/missions/hopping.yaml "
      "--seed 1 --out " +
          path("out") + " --max-time 1 --no-camera",
      "batch --kind obstacle --runs 1 --jobs 1 --seed0 7 --baseline --max-time 1 --no-camera",
  };
  for (const std::string& args : invocations) {
    const Ran r = sim(args);
    EXPECT_EQ(r.err.find(kUsageHint), std::string::npos) << "coxswain-sim " << args << "\n"
                                                         << r.err;
    EXPECT_NE(r.status, 2) << args << "\n" << r.err;
  }
}

TEST_F(Cli, TheDockingTargetIsSpelledTheSameInBothPrograms) {
  const std::string base =
      "run --course config/courses/kaboat2022_docking.yaml --mission config/missions/docking.yaml "
      "--max-time 1 --no-camera ";
  const Ran spelled = sim(base + "--target red triangle");
  EXPECT_NE(spelled.status, 2) << spelled.err;
  EXPECT_NE(spelled.out.find("run: "), std::string::npos) << spelled.out;
  // The former two options still work, and say nothing in the help.
  const Ran former = sim(base + "--target-colour red --target-shape triangle");
  EXPECT_NE(former.status, 2) << former.err;
  EXPECT_EQ(former.out, spelled.out);
  EXPECT_EQ(sim("run --help").out.find("--target-colour"), std::string::npos);
  const Ran wrong = sim(base + "--target mauve triangle");
  EXPECT_EQ(wrong.status, 2);
  EXPECT_NE(wrong.err.find("mauve"), std::string::npos) << wrong.err;
  EXPECT_NE(coxswain("run --help").out.find("--target TEXT x 2"), std::string::npos);
  EXPECT_NE(sim("run --help").out.find("--target TEXT x 2"), std::string::npos);
}

// Runs that cannot finish (a 2 s hard stop) fail fast: the batch's output is checked on them.
TEST_F(Cli, BatchPrintsJsonOnStdoutRoundedAndEachFailedSeedWithItsCommand) {
  const Ran r = sim("batch --kind obstacle --runs 2 --seed0 11 --jobs 2 --max-time 2 --no-camera");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto lines = lines_of(r.out);
  ASSERT_EQ(lines.size(), 3U) << r.out;
  for (const auto& line : lines) {
    const auto j = nlohmann::json::parse(line, nullptr, false);
    EXPECT_TRUE(j.is_object()) << line;
    // No float noise: at most four decimals on any number.
    EXPECT_FALSE(std::regex_search(line, std::regex(R"(\d\.\d{5,})"))) << line;
  }
  // stderr is not a terminal here: no progress bar, only the failures and their commands.
  EXPECT_EQ(r.err.find('\r'), std::string::npos);
  EXPECT_NE(r.err.find("failed: 2 of 2 runs"), std::string::npos) << r.err;
  const std::regex command_line(R"(^\s+(\S*coxswain-sim batch .*--seed0 (\d+) --runs 1 .*)$)");
  std::vector<std::pair<std::string, std::string>> commands;  // seed, command
  for (const auto& line : lines_of(r.err)) {
    std::smatch m;
    if (std::regex_match(line, m, command_line)) commands.emplace_back(m[2], m[1]);
  }
  ASSERT_EQ(commands.size(), 2U) << r.err;
  EXPECT_EQ(commands[0].first, "11");
  EXPECT_EQ(commands[1].first, "12");
  // The command, run as printed, sails that run again: the same JSON line.
  const std::string printed = commands[1].second;
  const std::string args = printed.substr(printed.find(" batch ") + 1);
  const Ran again = sim(args);
  ASSERT_EQ(again.status, 0) << again.err;
  const auto again_lines = lines_of(again.out);
  ASSERT_EQ(again_lines.size(), 2U);
  // Runs are printed as they finish (two jobs): find seed 12's line by its seed.
  std::string first_run_line;
  for (const auto& line : lines) {
    if (line.find("\"seed\":12,") != std::string::npos) first_run_line = line;
  }
  EXPECT_EQ(again_lines[0], first_run_line);
}

// On a terminal (both streams on one pseudo-terminal, through `script`) the progress bar is taken
// off the line before each JSON line: as displayed, every JSON line stands alone.
TEST_F(Cli, OnATerminalTheBatchProgressBarNeverSharesALineWithTheJson) {
  if (std::system("command -v script > /dev/null 2>&1") != 0) {
    GTEST_SKIP() << "script (util-linux) is not installed: no pseudo-terminal to test on";
  }
  const Ran r = run("/usr/bin/env",
                    "script -qec \"'" + std::string(COXSWAIN_SIM_EXE) +
                        "' batch --kind obstacle --runs 3 --jobs 1 --max-time 1 --no-camera\" "
                        "/dev/null");
  ASSERT_EQ(r.status, 0) << r.err;
  int json_lines = 0;
  bool saw_bar = false;
  for (std::string line : lines_of(r.out)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    saw_bar = saw_bar || line.find("] 1/3") != std::string::npos;
    // What the terminal shows: the text after the last carriage return, the erase code gone.
    if (const auto cr = line.rfind('\r'); cr != std::string::npos) line = line.substr(cr + 1);
    if (line.starts_with("\033[K")) line = line.substr(3);
    if (line.find('{') == std::string::npos) continue;
    EXPECT_EQ(line.front(), '{') << line;
    EXPECT_TRUE(nlohmann::json::parse(line, nullptr, false).is_object()) << line;
    ++json_lines;
  }
  EXPECT_EQ(json_lines, 4) << r.out;  // three runs and the summary
  EXPECT_TRUE(saw_bar) << "no progress bar on the terminal:\n" << r.out;
}

// The quick start runs devices mode with a run directory relative to the working directory:
// the devices file it writes for the daemon must still be one the daemon accepts.
TEST_F(Cli, DevicesModeWithARelativeRunDirectoryStartsTheDaemon) {
  const fs::path relative = fs::relative(dir_ / "rel", coxswain::testing::source_dir());
  ASSERT_FALSE(relative.is_absolute());
  const Ran r = sim(
      "devices --course config/courses/kaboat2022_hopping.yaml "
      "--mission config/missions/hopping.yaml --quiet --no-progress --time-limit 1 --run-dir '" +
      relative.string() + "'");
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("daemon exit status 0"), std::string::npos) << r.out << r.err;
}

TEST_F(Cli, DevicesModeProgressArrivesThroughAPipeEverySecondWhileTheRunGoesOn) {
  const std::string cmd = "cd '" + coxswain::testing::source_dir().string() + "' && '" +
                          COXSWAIN_SIM_EXE +
                          "' devices --course config/courses/kaboat2022_hopping.yaml "
                          "--mission config/missions/hopping.yaml --quiet "
                          "--time-limit 3 --run-dir " +
                          path("devices") + " 2>/dev/null";
  using Clock = std::chrono::steady_clock;
  FILE* p = ::popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::vector<std::pair<Clock::time_point, std::string>> got;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), p) != nullptr)
    got.emplace_back(Clock::now(), buf.data());
  const Clock::time_point end = Clock::now();
  ::pclose(p);
  std::vector<Clock::time_point> progress_at;
  for (const auto& [when, line] : got) {
    if (line.starts_with("progress: ")) {
      progress_at.push_back(when);
      EXPECT_TRUE(std::regex_search(line, std::regex(R"(^progress: t \d+ s, state \S+)"))) << line;
      EXPECT_NE(line.find("collisions "), std::string::npos) << line;
    }
  }
  ASSERT_GE(progress_at.size(), 2U);
  // Line by line: the first progress line was read while the run still had seconds to go.
  EXPECT_GT(std::chrono::duration<double>(end - progress_at.front()).count(), 1.0);
  EXPECT_NE(got.back().second.find("result: "), std::string::npos);

  const std::string quiet = "cd '" + coxswain::testing::source_dir().string() + "' && '" +
                            COXSWAIN_SIM_EXE + "' devices --help";
  FILE* h = ::popen(quiet.c_str(), "r");
  ASSERT_NE(h, nullptr);
  std::string help;
  while (std::fgets(buf.data(), buf.size(), h) != nullptr) help += buf.data();
  ::pclose(h);
  EXPECT_NE(help.find("--no-progress"), std::string::npos);
}

TEST_F(Cli, InfoSummarisesASimulatorRecording) {
  const std::string mcap = path("run.mcap");
  const Ran sailed =
      sim("run --course config/courses/kaboat2022_hopping.yaml --mission "
          "config/missions/hopping.yaml --max-time 4 --no-camera --record " +
          mcap);
  ASSERT_NE(sailed.status, 2) << sailed.err;
  const Ran text = coxswain("info " + mcap);
  ASSERT_EQ(text.status, 0) << text.err;
  EXPECT_NE(text.out.find("complete, every CRC valid"), std::string::npos) << text.out;
  EXPECT_NE(text.out.find("mission: hopping"), std::string::npos) << text.out;
  EXPECT_TRUE(std::regex_search(text.out, std::regex(R"(\n/tick +200 +50\.0 Hz)"))) << text.out;

  const Ran j = coxswain("info --json " + mcap);
  ASSERT_EQ(j.status, 0) << j.err;
  const auto info = nlohmann::json::parse(j.out);
  EXPECT_NEAR(info["duration_s"].get<double>(), 4.0, 0.05);
  EXPECT_EQ(info["ticks"], 200);
  EXPECT_EQ(info["mission"], "hopping");
  EXPECT_EQ(info["crc_ok"], true);
  EXPECT_EQ(info["dropped"], 0);
  EXPECT_EQ(info["final_state"].get<std::string>().rfind("hopping/", 0), 0U) << info.dump();
  EXPECT_TRUE(
      std::regex_match(info["config_hash"].get<std::string>(), std::regex("fnv1a:[0-9a-f]{16}")));
  bool saw_imu = false;
  for (const auto& c : info["channels"]) {
    if (c["topic"] == "/imu") {
      saw_imu = true;
      EXPECT_NEAR(c["rate_hz"].get<double>(), 100.0, 2.0);
      EXPECT_EQ(c["schema"], "coxswain.ImuSample");
    }
  }
  EXPECT_TRUE(saw_imu);
  // The same configuration hashes the same: a second run of it, another seed.
  const std::string other = path("other.mcap");
  ASSERT_NE(sim("run --course config/courses/kaboat2022_hopping.yaml --mission "
                "config/missions/hopping.yaml --max-time 1 --no-camera --seed 2 --record " +
                other)
                .status,
            2);
  EXPECT_EQ(nlohmann::json::parse(coxswain("info --json " + other).out)["config_hash"],
            info["config_hash"]);

  const Ran missing = coxswain("info " + path("none.mcap"));
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("cannot read"), std::string::npos) << missing.err;
  EXPECT_EQ(missing.err.find(kUsageHint), std::string::npos);
}

}  // namespace
