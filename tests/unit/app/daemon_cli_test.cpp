// SPDX-License-Identifier: Apache-2.0
// The coxswain executable end to end: version, check-config exit codes and messages, print-config,
// and a run with no devices present that keeps ticking and stops cleanly on SIGTERM, records its
// own log lines, leaves a replayable recording when killed and sails on when the file-size limit
// stops the recording.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "coxswain/config/vision_config.hpp"
#include "coxswain/record/layouts.hpp"
#include "coxswain/record/mcap_reader.hpp"
#include "support/run_command.hpp"
#include "support/testdata.hpp"

namespace {

using coxswain::test::slurp;

namespace fs = std::filesystem;

// What a recording holds: messages per topic, the /log lines (level and text) and the report.
struct RecordingSummary {
  coxswain::record::McapReadReport report;
  std::map<std::string, std::uint64_t> counts;
  std::vector<std::pair<int, std::string>> log;  // foxglove.Log level, message
};

RecordingSummary read_recording(const fs::path& mcap) {
  RecordingSummary s;
  coxswain::record::McapReader reader;
  if (!reader.open(mcap)) return s;
  s.report = reader.read([&](const coxswain::record::McapMessageView& m) {
    const std::string topic = reader.channels().at(m.channel_id).topic;
    ++s.counts[topic];
    if (topic == "/log") {
      const auto j = nlohmann::json::parse(m.data.begin(), m.data.end());
      s.log.emplace_back(j["level"].get<int>(), j["message"].get<std::string>());
    }
  });
  return s;
}

// The one run directory under `runs`.
fs::path only_run(const fs::path& runs) {
  fs::path run_dir;
  for (const auto& e : fs::directory_iterator(runs)) run_dir = e.path();
  return run_dir;
}

using Result = coxswain::test::CommandResult;

class CoxswainCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("coxswain_cli_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  Result run(const std::vector<std::string>& args) {
    std::string cmd = std::string("'") + COXSWAIN_EXE + "'";
    for (const auto& a : args) cmd += " '" + a + "'";
    return coxswain::test::run_to_files(cmd, dir_);
  }

  fs::path write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p;
  }

  // A devices file whose every device points at a path that does not exist.
  fs::path absent_devices() {
    std::string text = slurp(coxswain::testing::source_dir() / "config/devices.yaml");
    for (const char* dev :
         {"/dev/ttyLiDAR", "/dev/ttyIMU", "/dev/ttyGPS", "/dev/ttyARDUINO", "/dev/videoCAM"}) {
      const std::string from = dev;
      text.replace(text.find(from), from.size(), (dir_ / ("missing" + from.substr(5))).string());
    }
    return write("devices.yaml", text);
  }

  // Starts `coxswain --devices <absent> --log-dir runs run` (stderr to dir_/err) with an optional
  // file-size limit (bytes; 0 = none) and SIGXFSZ at its default action, as a shell leaves it.
  pid_t spawn_daemon(std::uint64_t file_size_limit = 0, const fs::path& runs_dir = {},
                     const fs::path& devices_file = {},
                     const std::vector<std::string>& extra = {}) {
    const std::string devices = (devices_file.empty() ? absent_devices() : devices_file).string();
    const std::string runs = (runs_dir.empty() ? dir_ / "runs" : runs_dir).string();
    const std::string err = (dir_ / "err").string();
    const pid_t pid = ::fork();
    if (pid == 0) {
      const int fd = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd >= 0) ::dup2(fd, 2);
      ::signal(SIGXFSZ, SIG_DFL);
      if (file_size_limit > 0) {
        const rlimit limit{file_size_limit, file_size_limit};
        ::setrlimit(RLIMIT_FSIZE, &limit);
      }
      std::vector<std::string> args{COXSWAIN_EXE, "--devices", devices, "--log-dir", runs};
      args.insert(args.end(), extra.begin(), extra.end());
      args.emplace_back("run");
      std::vector<char*> argv;
      for (std::string& a : args) argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execv(COXSWAIN_EXE, argv.data());
      ::_exit(127);
    }
    return pid;
  }

  // Waits (up to `timeout`) until the run's coxswain.log holds `text`.
  bool wait_for_log(const std::string& text, std::chrono::seconds timeout,
                    const fs::path& runs_dir = {}) {
    const fs::path runs = runs_dir.empty() ? dir_ / "runs" : runs_dir;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      if (fs::is_directory(runs)) {
        for (const auto& e : fs::directory_iterator(runs)) {
          if (slurp(e.path() / "coxswain.log").find(text) != std::string::npos) return true;
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
  }

  fs::path dir_;
};

TEST_F(CoxswainCli, VersionHasGitHash) {
  const Result r = run({"--version"});
  EXPECT_EQ(r.status, 0);
  EXPECT_TRUE(std::regex_search(r.out, std::regex(R"(^coxswain \d+\.\d+\.\d+ \(git [0-9a-z-]+\))")))
      << r.out;
}

TEST_F(CoxswainCli, CheckConfigAcceptsShippedFiles) {
  const fs::path config = coxswain::testing::source_dir() / "config";
  const Result r =
      run({"check-config", (config / "boat.yaml").string(), (config / "devices.yaml").string(),
           (config / "missions/kaboat2026.yaml").string()});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("boat.yaml: ok (boat)"), std::string::npos);
}

TEST_F(CoxswainCli, CheckConfigWrongTypeUnknownKeyOutOfRange) {
  const fs::path bad = write("bad_mission.yaml",
                             "kind: mission\n"
                             "name: test\n"
                             "tick_rate_hz: fast\n"
                             "origin: {lat_deg: 35.0, lon_deg: 128.0}\n"
                             "tasks:\n"
                             "  - type: docking\n"
                             "    time_limit_s: 99999\n"
                             "    speling: 1\n");
  const Result r = run({"check-config", bad.string()});
  EXPECT_EQ(r.status, 2);
  const std::string f = bad.string();
  EXPECT_NE(r.err.find(f + ":3: key 'tick_rate_hz' expected a number"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(f + ":7: key 'tasks[0].time_limit_s' must be"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(f + ":8: key 'tasks[0].speling' is not a known key"), std::string::npos)
      << r.err;
}

TEST_F(CoxswainCli, RunRefusesBadConfigWithStatus2) {
  const fs::path bad = write("boat.yaml", "kind: boat\nhull: {length_m: -1, beam_m: 0.5}\n");
  const Result r = run({"--boat", bad.string(), "--log-dir", (dir_ / "runs").string(), "run"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("key 'hull.length_m'"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "runs"));  // nothing was started
}

TEST_F(CoxswainCli, PrintConfig) {
  const Result r = run({"--mission", "hopping", "--print-config"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("name: hopping"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("failsafe_ms: 300"), std::string::npos);
}

// `coxswain run` with no device present keeps ticking at its rate, reports each missing device
// once (not per tick) and exits cleanly on SIGTERM after commanding neutral outputs.
TEST_F(CoxswainCli, RunsWithoutDevicesAndStopsOnSigterm) {
  const fs::path runs = dir_ / "runs";
  const pid_t pid = spawn_daemon();
  ASSERT_GT(pid, 0);
  // The first tick reports every device (a loaded or sanitized machine starts slowly), then the
  // daemon ticks for 2 s more before it is asked to stop.
  EXPECT_TRUE(wait_for_log("device camera: absent", std::chrono::seconds(30)));
  std::this_thread::sleep_for(std::chrono::milliseconds(2000));
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0);

  ASSERT_TRUE(fs::is_directory(runs));
  fs::path run_dir;
  for (const auto& e : fs::directory_iterator(runs)) run_dir = e.path();
  EXPECT_TRUE(
      std::regex_match(run_dir.filename().string(), std::regex(R"(\d{6}-\d{6}-kaboat2026-01)")))
      << run_dir;
  const std::string log = slurp(run_dir / "coxswain.log");
  for (const char* dev : {"lidar", "imu", "gnss", "arduino", "camera"}) {
    const std::string line = std::string("device ") + dev + ": absent";
    const auto first = log.find(line);
    EXPECT_NE(first, std::string::npos) << dev << "\n" << log;
    EXPECT_EQ(log.find(line, first + 1), std::string::npos) << "reported twice: " << dev;
  }
  EXPECT_NE(log.find("missingttyLiDAR: No such file or directory"), std::string::npos) << log;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      log, m, std::regex(R"(stopping on SIGTERM: commanded neutral actuators; (\d+) ticks)")))
      << log;
  // 2 s at 50 Hz is 100 ticks; a loaded test machine may skip some.
  EXPECT_GE(std::stoi(m[1].str()), 50);

  // The daemon's own log lines are in the recording's /log (info and above), warnings as
  // warnings (foxglove.Log level 3).
  const RecordingSummary rec = read_recording(run_dir / "run.mcap");
  EXPECT_TRUE(rec.report.complete) << rec.report.error;
  ASSERT_TRUE(rec.counts.contains("/tick"));
  EXPECT_GE(rec.counts.at("/tick"), 50U);
  auto logged = [&](int level, const std::string& text) {
    for (const auto& [l, message] : rec.log) {
      if (l == level && message.find(text) != std::string::npos) return true;
    }
    return false;
  };
  EXPECT_TRUE(logged(2, "flight recording to")) << rec.log.size() << " lines";
  EXPECT_TRUE(logged(2, "mission 'kaboat2026'"));
  for (const char* dev : {"lidar", "imu", "gnss", "arduino", "camera"}) {
    EXPECT_TRUE(logged(3, std::string("device ") + dev + ": absent")) << dev;
  }
}

// SIGKILL mid-run: the file holds every chunk closed before (about all but the last second), and
// `coxswain replay` re-runs those ticks bit for bit.
TEST_F(CoxswainCli, KilledMidRunReplays) {
  const fs::path runs = dir_ / "runs";
  const pid_t pid = spawn_daemon();
  ASSERT_GT(pid, 0);
  EXPECT_TRUE(wait_for_log("device camera: absent", std::chrono::seconds(30)));
  std::this_thread::sleep_for(std::chrono::milliseconds(3000));  // some chunks closed
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << "exited " << WEXITSTATUS(status) << "\n"
                                   << slurp(dir_ / "err");

  const fs::path mcap = only_run(runs) / "run.mcap";
  const RecordingSummary rec = read_recording(mcap);
  EXPECT_TRUE(rec.report.header_ok);
  EXPECT_FALSE(rec.report.complete);  // no summary, no footer: it was killed
  EXPECT_EQ(rec.report.chunk_crc_errors, 0U);
  EXPECT_GE(rec.counts.at("/tick"), 50U);  // at least a second of ticks survived
  const Result r = run({"replay", mcap.string()});
  EXPECT_EQ(r.status, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("truncated"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("identical"), std::string::npos) << r.out;
}

// The recording's disk fills up (here: a 64 KiB file-size limit, so write(2) fails with EFBIG a
// few seconds in, after the schemas, the configuration and the first chunks):
// the recording stops with an error line, the file keeps what was written, the boat's process
// keeps ticking and stops normally.
TEST_F(CoxswainCli, FullDiskSailsOn) {
  const fs::path runs = dir_ / "runs";
  const pid_t pid = spawn_daemon(64 * 1024);
  ASSERT_GT(pid, 0);
  const bool stopped =
      wait_for_log("recorder: recording stopped, the run continues", std::chrono::seconds(60));
  std::this_thread::sleep_for(std::chrono::milliseconds(2000));  // sailing on without it
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "the daemon died of signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0) << slurp(dir_ / "err");
  EXPECT_TRUE(stopped) << "the recording never hit the limit";
  const fs::path run_dir = only_run(runs);
  const std::string log = slurp(run_dir / "coxswain.log");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      log, m, std::regex(R"(stopping on SIGTERM: commanded neutral actuators; (\d+) ticks)")))
      << log;
  // Ticking went on after the recording stopped (2 s at 50 Hz after it, and the time before).
  EXPECT_GE(std::stoi(m[1].str()), 100);
  const fs::path mcap = run_dir / "run.mcap";
  EXPECT_LE(fs::file_size(mcap), 64U * 1024U);
  const RecordingSummary rec = read_recording(mcap);
  EXPECT_TRUE(rec.report.header_ok);
  EXPECT_EQ(rec.report.chunk_crc_errors, 0U);
  EXPECT_TRUE(rec.counts.contains("/tick"));  // the chunks closed before the disk filled
}

// A run directory too deep for a Unix socket's path (108 bytes) costs the control socket only:
// the live view and status page (which take start, hold and the target too) still run.
TEST_F(CoxswainCli, SocketPathTooLongKeepsTheLiveView) {
  fs::path runs = dir_;
  while (runs.string().size() < 120) runs /= "a-rather-long-folder-name";
  std::string devices = slurp(absent_devices());
  const std::string port = "http_port: 8765";
  ASSERT_NE(devices.find(port), std::string::npos);
  devices.replace(devices.find(port), port.size(), "http_port: 0");
  const pid_t pid = spawn_daemon(0, runs, write("devices-any-port.yaml", devices));
  ASSERT_GT(pid, 0);
  const bool fell_back = wait_for_log("no control socket; live view and status page only",
                                      std::chrono::seconds(30), runs);
  const bool ticking = wait_for_log("device camera: absent", std::chrono::seconds(30), runs);
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << slurp(dir_ / "err");
  EXPECT_TRUE(fell_back) << slurp(dir_ / "err");
  EXPECT_TRUE(ticking);
  const fs::path run_dir = only_run(runs);
  EXPECT_TRUE(fs::exists(run_dir / "live.port")) << slurp(run_dir / "coxswain.log");
  EXPECT_NE(slurp(run_dir / "coxswain.log").find("status page and live view on"),
            std::string::npos);
}

// `coxswain decode` prints one JSON object per message and a summary line; it needs no config.
// The daemon sails on the vision file it is given (--vision), records it, and `ctl save-params`
// writes the colour model in force and the mission with its live values: files that load back.
TEST_F(CoxswainCli, SaveParamsWritesVisionInForce) {
  const fs::path runs = dir_ / "runs";
  std::string vision = slurp(coxswain::testing::source_dir() / "config/vision.yaml");
  const std::string blue = "{colour: blue, h_min: 95,";
  ASSERT_NE(vision.find(blue), std::string::npos);
  vision.replace(vision.find(blue), blue.size(), "{colour: blue, h_min: 103,");
  const fs::path venue = write("venue-vision.yaml", vision);
  const pid_t pid = spawn_daemon(0, {}, {}, {"--vision", venue.string()});
  ASSERT_GT(pid, 0);
  EXPECT_TRUE(wait_for_log("device camera: absent", std::chrono::seconds(30)));
  EXPECT_TRUE(wait_for_log("vision: " + venue.string(), std::chrono::seconds(1)));

  const fs::path saved_vision = dir_ / "saved-vision.yaml";
  const fs::path saved_mission = dir_ / "saved-mission.yaml";
  const Result saved = run({"--log-dir", runs.string(), "ctl", "save-params", saved_vision.string(),
                            saved_mission.string()});
  ASSERT_EQ(::kill(pid, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_EQ(saved.status, 0) << saved.out << saved.err;

  const Result check = run({"check-config", saved_vision.string(), saved_mission.string()});
  EXPECT_EQ(check.status, 0) << check.err;
  coxswain::config::ConfigErrors errors;
  const auto back = coxswain::config::load_vision_file(saved_vision.string(), errors);
  ASSERT_TRUE(back.has_value()) << errors.format();
  const int i = back->find_colour(coxswain::msg::Colour::kBlue);
  ASSERT_GE(i, 0);
  EXPECT_EQ(back->colours[static_cast<std::size_t>(i)].hsv.h_min, 103);
  // The recording holds the vision file with the rest of the configuration.
  const RecordingSummary rec = read_recording(only_run(runs) / "run.mcap");
  ASSERT_TRUE(rec.report.metadata.contains("config"));
  const std::string recorded = rec.report.metadata.at("config").at("yaml");
  EXPECT_NE(recorded.find("file: " + venue.string()), std::string::npos) << recorded;
  EXPECT_NE(recorded.find("{colour: blue, h_min: 103,"), std::string::npos) << recorded;
}

TEST_F(CoxswainCli, DecodePrintsJsonLinesAndSummary) {
  const std::string body = "GNGGA,123519.00,3507.12345,N,12648.00000,E,1,08,1.0,5.0,M,20.0,M,,";
  unsigned x = 0;
  for (const char c : body) x ^= static_cast<unsigned char>(c);
  char tail[8];
  std::snprintf(tail, sizeof tail, "*%02X\r\n", x);
  const fs::path capture = write("gnss.raw", "noise$" + body + tail);
  const Result r = run({"decode", "--device", "ublox", capture.string()});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(
      std::regex_search(r.out, std::regex(R"(^\{.*"type":"fix".*\}\n\{.*"summary":true.*\}\n$)")))
      << r.out;
  EXPECT_NE(r.out.find("\"lat_deg\":35.1187"), std::string::npos) << r.out;

  EXPECT_EQ(run({"decode", "--device", "ublox", (dir_ / "missing.raw").string()}).status, 1);
  EXPECT_NE(run({"decode", "--device", "gps", capture.string()}).status, 0);
}

// Capture mode creates its folder and runs; with no device present it captures nothing.
TEST_F(CoxswainCli, RunWithCaptureDir) {
  const fs::path capture = dir_ / "capture";
  const Result r =
      run({"--devices", absent_devices().string(), "--log-dir", (dir_ / "runs").string(), "run",
           "--run-for-s", "0.3", "--capture-dir", capture.string()});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::is_directory(capture));
  EXPECT_TRUE(fs::is_empty(capture));
}

}  // namespace
