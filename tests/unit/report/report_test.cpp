// SPDX-License-Identifier: Apache-2.0
// The postmortem report of a short recorded simulator run: one self-contained page holding
// every plot element, the course, the transitions with their reasons and parseable data.
// (Rendering in headless Chromium is checked in tests/integration/replay.)
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "coxswain/report/report.hpp"
#include "sim_recording.hpp"

namespace coxswain::report {
namespace {

namespace fs = std::filesystem;

std::string read_page(const fs::path& html) {
  std::ifstream in(html);
  std::stringstream page;
  page << in.rdbuf();
  return page.str();
}

class ReportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("coxswain-report-unit-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    const config::Configuration c = test::shipped_config("hopping");
    const auto r = test::record_sim_run(dir_ / "run.mcap", c, "kaboat2022_hopping.yaml", 10.0);
    ASSERT_TRUE(r.ok) << r.error;
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  static inline fs::path dir_;
};

// A run the operator retuned live: the page lists each changed value with its tick.
TEST_F(ReportTest, LiveParameterChangesAreListed) {
  const config::Configuration c = test::shipped_config("hopping");
  test::ParameterChange change;
  change.at_s = 5.0;
  change.edit = [](mission::TunableParameters& p) { p.heading_pid.kd_per_dps = 0.05; };
  const fs::path mcap = dir_ / "retuned.mcap";
  const auto made = test::record_sim_run(mcap, c, "kaboat2022_hopping.yaml", 8.0, change);
  ASSERT_TRUE(made.ok) << made.error;
  std::ostringstream out;
  std::ostringstream err;
  ASSERT_EQ(run_report_command(mcap, dir_ / "retuned.html", nullptr, out, err), 0) << err.str();
  const std::string html = read_page(dir_ / "retuned.html");
  const auto table = html.find("<table id=\"parameters\">");
  ASSERT_NE(table, std::string::npos);
  const std::string rows = html.substr(table, html.find("</table>", table) - table);
  EXPECT_NE(rows.find("<td>heading_pid.kd_per_dps</td><td>" +
                      std::to_string(c.mission.heading_pid.kd_per_dps).substr(0, 4)),
            std::string::npos)
      << rows;
  EXPECT_NE(rows.find("<td>0.05</td></tr>"), std::string::npos) << rows;
  EXPECT_EQ(rows.find("kp_per_deg"), std::string::npos) << "only what changed: " << rows;
  // And a page without changes says so.
  std::ostringstream out2;
  ASSERT_EQ(run_report_command(dir_ / "run.mcap", dir_ / "plain.html", nullptr, out2, err), 0);
  EXPECT_NE(read_page(dir_ / "plain.html").find("<td colspan=\"5\">none</td>"), std::string::npos);
}

nlohmann::json page_data(const std::string& html) {
  const std::string open = "<script type=\"application/json\" id=\"report-data\">";
  const auto a = html.find(open);
  const auto b = html.find("</script>", a);
  if (a == std::string::npos || b == std::string::npos) return {};
  return nlohmann::json::parse(html.substr(a + open.size(), b - a - open.size()));
}

TEST_F(ReportTest, PageIsSelfContainedWithEveryPlot) {
  std::ostringstream out;
  std::ostringstream err;
  ASSERT_EQ(run_report_command(dir_ / "run.mcap", {}, nullptr, out, err), 0) << err.str();
  ASSERT_TRUE(fs::exists(dir_ / "run.html"));  // the default output name
  const std::string html = read_page(dir_ / "run.html");
  for (const char* id : kPlotIds) {
    EXPECT_NE(html.find(std::string("class=\"plot\" id=\"") + id + "\""), std::string::npos) << id;
  }
  EXPECT_EQ(html.find("src="), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_EQ(html.find("@import"), std::string::npos);
  const nlohmann::json d = page_data(html);
  ASSERT_TRUE(d.is_object());
  EXPECT_GE(d["t"].size(), 490U);
  EXPECT_EQ(d["t"].size(), d["heading"].size());
  EXPECT_EQ(d["course"]["waypoints"].size(), 4U);
  EXPECT_FALSE(d["course"]["walls"].empty());
  ASSERT_FALSE(d["transitions"].empty());
  EXPECT_EQ(d["transitions"][0]["from"], "wait_for_start");
  EXPECT_FALSE(d["transitions"][0]["reason"].get<std::string>().empty());
  EXPECT_EQ(d["rates"].size(), 5U);
  // The map: the mission's own waypoints (four, as the course has); the start calibration's
  // moment, so the estimate before it is drawn apart; the Arduino's lanes sample for sample.
  EXPECT_EQ(d["map"]["marks"].size(), 4U);
  ASSERT_TRUE(d["events"]["calibration_t"].is_number());
  EXPECT_GT(d["events"]["calibration_t"].get<double>(), 0.0);
  EXPECT_TRUE(d["events"]["start_t"].is_number());
  for (const char* lane : {"supply_v", "estop", "rc_present", "autonomous", "failsafe"}) {
    EXPECT_EQ(d["power"][lane].size(), d["t"].size()) << lane;
  }
  EXPECT_EQ(d["goal_n"].size(), d["t"].size());
}

// The top of the page: mission, date, result and the simulator judge's score, before any plot.
TEST_F(ReportTest, SummaryComesFirstWithDateResultAndScore) {
  std::ostringstream out;
  std::ostringstream err;
  ASSERT_EQ(run_report_command(dir_ / "run.mcap", dir_ / "summary.html", nullptr, out, err), 0)
      << err.str();
  const std::string html = read_page(dir_ / "summary.html");
  const auto summary = html.find("<table id=\"summary\">");
  ASSERT_NE(summary, std::string::npos);
  EXPECT_LT(summary, html.find("class=\"plot\""));
  const std::string table = html.substr(summary, html.find("</table>", summary) - summary);
  EXPECT_TRUE(std::regex_search(
      table, std::regex(R"(<th>date</th><td>\d{4}-\d\d-\d\d \d\d:\d\d:\d\d UTC<)")))
      << table;
  // 10 s of the hopping course: started, not finished, and the judge says why it failed.
  EXPECT_NE(table.find("<th>result</th><td>not finished: "), std::string::npos) << table;
  EXPECT_NE(table.find("<th>score</th><td class=\"failed\">none, failed: "), std::string::npos)
      << table;
  EXPECT_NE(table.find("the simulator's judge"), std::string::npos) << table;
  EXPECT_NE(html.find("<title>coxswain: hopping, "), std::string::npos);
}

TEST_F(ReportTest, UnreadableRecordingIsRefused) {
  std::ostringstream out;
  std::ostringstream err;
  EXPECT_EQ(run_report_command(dir_ / "absent.mcap", dir_ / "x.html", nullptr, out, err), 2);
  EXPECT_FALSE(fs::exists(dir_ / "x.html"));
}

}  // namespace
}  // namespace coxswain::report
