// SPDX-License-Identifier: Apache-2.0
// `coxswain-sim batch --shard I/N` and `coxswain-sim merge`: the parts of a batch, merged, are
// the batch (every run line identical, sorted by seed, and the same summary), whatever N; a
// missing shard is caught. Also the shard arithmetic and the parameter overrides by name.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "coxswain/config/config.hpp"
#include "sim/batch/batch.hpp"
#include "support/run_command.hpp"

namespace coxswain {
namespace {

namespace fs = std::filesystem;

struct Ran {
  int status = -1;
  std::string out;
};

// Runs a shell command in the source folder (the shipped config paths are relative to it);
// stdout is captured, stderr goes to the test log.
Ran run(const std::string& args) {
  const coxswain::test::CommandResult r = coxswain::test::run_shell(
      std::string("cd '") + COXSWAIN_SOURCE_DIR + "' && '" + COXSWAIN_SIM_BINARY + "' " + args);
  return {r.status, r.out};
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty()) out.push_back(line);
  }
  return out;
}

// Run lines sorted by seed, then the summary (last), each as its canonical JSON text.
std::vector<std::string> canonical(const std::string& text) {
  sim::batch::Collected c;
  std::istringstream in(text);
  std::string why;
  EXPECT_TRUE(sim::batch::read_lines(in, "output", c, &why)) << why;
  std::vector<std::string> out;
  for (const auto& j : c.runs) out.push_back(j.dump());
  return out;
}

// Small and quick: obstacle courses without camera frames, 4 runs (about 0.3 s of CPU each).
constexpr const char* kBatch = "batch --kind obstacle --runs 4 --seed0 11 --jobs 2 --no-camera";

class ShardedBatch : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("coxswain-shard-test-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  // Runs the batch in `n` shards into files (once per n); returns their paths.
  static std::vector<fs::path> shards(int n) {
    auto& files = shard_files_[n];
    if (!files.empty()) return files;
    for (int i = 0; i < n; ++i) {
      const Ran r =
          run(std::string(kBatch) + " --shard " + std::to_string(i) + "/" + std::to_string(n));
      EXPECT_EQ(r.status, 0);
      const fs::path f = dir_ / ("shard-" + std::to_string(n) + "-" + std::to_string(i) + ".jsonl");
      std::ofstream(f) << r.out;
      files.push_back(f);
    }
    return files;
  }
  static std::string merge_args(const std::vector<fs::path>& files) {
    std::string args = "merge";
    for (const auto& f : files) args += " '" + f.string() + "'";
    return args;
  }
  static inline fs::path dir_;
  static inline std::map<int, std::vector<fs::path>> shard_files_;
};

// ctest runs each test in a process of its own: only this one sails the whole batch.
TEST_F(ShardedBatch, MergedShardsEqualTheUnshardedBatchLineForLine) {
  const Ran whole = run(kBatch);
  ASSERT_EQ(whole.status, 0);
  const auto whole_lines = lines_of(whole.out);
  ASSERT_EQ(whole_lines.size(), 5U);  // 4 runs and the summary
  for (const int n : {2, 3}) {
    const Ran merged = run(merge_args(shards(n)));
    ASSERT_EQ(merged.status, 0) << n << " shards";
    EXPECT_EQ(canonical(merged.out), canonical(whole.out)) << n << " shards";
    // The summary: the same text as the unsharded batch prints.
    EXPECT_EQ(lines_of(merged.out).back(), whole_lines.back()) << n << " shards";
  }
  // Each run line prices a failure at the time limit (what the tuner minimises).
  for (const auto& text : canonical(whole.out)) {
    const auto j = nlohmann::json::parse(text);
    if (j["passed"].get<bool>()) {
      EXPECT_EQ(j["contest_score_s"], j["score_s"]);
    } else {
      EXPECT_GE(j["contest_score_s"].get<double>(), j["time_limit_s"].get<double>());
    }
  }
}

TEST_F(ShardedBatch, MergeRefusesABatchWithAShardMissing) {
  auto files = shards(3);
  files.erase(files.begin() + 1);
  const Ran merged = run(merge_args(files) + " 2>/dev/null");
  EXPECT_EQ(merged.status, 1);
}

TEST_F(ShardedBatch, MergeRefusesASeedTwice) {
  const auto files = shards(2);
  const Ran merged = run(merge_args({files[0], files[0], files[1]}) + " 2>/dev/null");
  EXPECT_EQ(merged.status, 1);
}

TEST(Shard, EveryRunBelongsToExactlyOneShard) {
  for (int n = 1; n <= 7; ++n) {
    std::multiset<int> seen;
    for (int i = 0; i < n; ++i) {
      for (const int r : sim::batch::shard_runs(20, {i, n})) seen.insert(r);
    }
    ASSERT_EQ(seen.size(), 20U);
    for (int r = 0; r < 20; ++r) EXPECT_EQ(seen.count(r), 1U);
  }
}

TEST(Shard, ParsesOnlyIndicesInsideTheCount) {
  EXPECT_TRUE(sim::batch::parse_shard("0/1", nullptr).has_value());
  EXPECT_TRUE(sim::batch::parse_shard("3/4", nullptr).has_value());
  std::string why;
  EXPECT_FALSE(sim::batch::parse_shard("4/4", &why).has_value());
  EXPECT_FALSE(why.empty());
  EXPECT_FALSE(sim::batch::parse_shard("-1/4", nullptr).has_value());
  EXPECT_FALSE(sim::batch::parse_shard("1/0", nullptr).has_value());
  EXPECT_FALSE(sim::batch::parse_shard("1", nullptr).has_value());
  EXPECT_FALSE(sim::batch::parse_shard("a/b", nullptr).has_value());
}

TEST(ReadLines, RejectsLinesWhoseFieldsHaveTheWrongTypes) {
  for (const char* text : {R"({"seed": 1, "passed": "yes"})", R"({"seed": 1, "collisions": 1.5})",
                           R"({"summary": true, "shard": "0", "shards": 2})", R"([1, 2])",
                           R"({"passed": true})", "not json"}) {
    std::istringstream in(text);
    sim::batch::Collected c;
    std::string why;
    EXPECT_FALSE(sim::batch::read_lines(in, "bad", c, &why)) << text;
    EXPECT_NE(why.find("bad:1:"), std::string::npos) << why;
  }
}

// A run whose mission declared itself finished while the judge saw the course not completed is
// counted apart: the one failure a team cannot see from the boat.
TEST(Summary, CountsTheRunsThatFinishedWithTheCourseNotCompleted) {
  std::vector<nlohmann::json> runs;
  runs.push_back({{"seed", 1U},
                  {"passed", true},
                  {"completed", true},
                  {"mission_state", "finished"},
                  {"collisions", 0}});
  runs.push_back({{"seed", 2U},
                  {"passed", false},
                  {"completed", false},
                  {"mission_state", "finished"},
                  {"collisions", 1}});
  runs.push_back({{"seed", 3U},
                  {"passed", false},
                  {"completed", false},
                  {"mission_state", "obstacle_course/navigate"},
                  {"collisions", 0}});
  const nlohmann::json s = sim::batch::summarize(runs, "gapwall", false);
  EXPECT_EQ(s["false_finishes"].get<int>(), 1);
  EXPECT_EQ(s["zero_collision_runs"].get<int>(), 2);
  std::istringstream in(R"({"seed": 4, "mission_state": 3})");
  sim::batch::Collected c;
  std::string why;
  EXPECT_FALSE(sim::batch::read_lines(in, "bad", c, &why));
  EXPECT_NE(why.find("mission_state"), std::string::npos) << why;
}

TEST(SetParameter, SetsANamedParameterWithinItsRange) {
  config::MissionConfig m;
  EXPECT_EQ(sim::batch::set_parameter_assignment(m, "avoidance.clearance_m=0.8"), "");
  EXPECT_DOUBLE_EQ(m.avoidance.clearance_m, 0.8);
  EXPECT_EQ(sim::batch::set_parameter_assignment(m, "heading_pid.kp_per_deg=0.05"), "");
  EXPECT_DOUBLE_EQ(m.heading_pid.kp_per_deg, 0.05);
}

TEST(SetParameter, RejectsUnknownNamesOutOfRangeValuesAndNonNumbers) {
  config::MissionConfig m;
  const double before = m.avoidance.clearance_m;
  EXPECT_NE(sim::batch::set_parameter_assignment(m, "avoidance.clearance_m=5"), "");
  EXPECT_NE(sim::batch::set_parameter_assignment(m, "avoidance.no_such_thing=1"), "");
  EXPECT_NE(sim::batch::set_parameter_assignment(m, "avoidance.clearance_m=wide"), "");
  EXPECT_NE(sim::batch::set_parameter_assignment(m, "avoidance.clearance_m"), "");
  EXPECT_DOUBLE_EQ(m.avoidance.clearance_m, before);
}

TEST(SetParameter, AppliesAnOverlayFileWholeOrNotAtAll) {
  const fs::path dir =
      fs::temp_directory_path() / ("coxswain-overlay-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "good.yaml") << "avoidance.clearance_m: 0.6\nspeed.max_thrust_frac: 0.9\n";
  std::ofstream(dir / "bad.yaml") << "avoidance.clearance_m: 0.7\nspeed.max_thrust_frac: 3\n";
  std::ofstream(dir / "nested.yaml") << "avoidance:\n  clearance_m: 0.7\n";
  config::MissionConfig m;
  EXPECT_EQ(sim::batch::apply_overlay_file(m, (dir / "good.yaml").string()), "");
  EXPECT_DOUBLE_EQ(m.avoidance.clearance_m, 0.6);
  EXPECT_DOUBLE_EQ(m.speed.max_thrust_frac, 0.9);
  EXPECT_NE(sim::batch::apply_overlay_file(m, (dir / "bad.yaml").string()), "");
  EXPECT_DOUBLE_EQ(m.avoidance.clearance_m, 0.6);  // nothing of the bad file applied
  EXPECT_NE(sim::batch::apply_overlay_file(m, (dir / "nested.yaml").string()), "");
  std::error_code ec;
  fs::remove_all(dir, ec);
}

}  // namespace
}  // namespace coxswain

namespace coxswain {
namespace {

TEST(Rounded, PrintsSecondsWithoutFloatNoise) {
  EXPECT_EQ(nlohmann::json(sim::batch::rounded(33.019999999999996)).dump(), "33.02");
  EXPECT_EQ(nlohmann::json(sim::batch::rounded(2.0 / 3.0, 4)).dump(), "0.6667");
  EXPECT_EQ(sim::batch::rounded(-1.0005, 3), -1.001);
}

TEST(ShellQuote, LeavesPlainWordsAndQuotesTheRest) {
  EXPECT_EQ(sim::batch::shell_quote("config/missions/hopping.yaml"),
            "config/missions/hopping.yaml");
  EXPECT_EQ(sim::batch::shell_quote("avoidance.clearance_m=0.4"), "avoidance.clearance_m=0.4");
  EXPECT_EQ(sim::batch::shell_quote("my course.yaml"), "'my course.yaml'");
  EXPECT_EQ(sim::batch::shell_quote("it's"), "'it'\\''s'");
  EXPECT_EQ(sim::batch::shell_quote(""), "''");
}

}  // namespace
}  // namespace coxswain
