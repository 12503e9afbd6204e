// SPDX-License-Identifier: Apache-2.0
// Replay against a short recorded simulator run: identical as recorded; every tampered field is
// reported at its tick; missing scans and undecodable ticks are counted; a live parameter change
// is replayed at its tick; the recorded configuration reads back to the same configuration.
#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "coxswain/config/vision_config.hpp"
#include "coxswain/replay/replay.hpp"
#include "sim_recording.hpp"

namespace coxswain::replay {
namespace {

namespace fs = std::filesystem;

class ReplayTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("coxswain-replay-unit-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    config_ = std::make_unique<config::Configuration>(test::shipped_config("hopping"));
    const auto r =
        test::record_sim_run(dir_ / "run.mcap", *config_, "kaboat2022_hopping.yaml", 12.0);
    ASSERT_TRUE(r.ok) << r.error;
    recording_ = std::make_unique<Recording>(load_recording(dir_ / "run.mcap"));
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(dir_, ec);
    recording_.reset();
    config_.reset();
  }
  // Re-encodes tick `i` after `edit` changed it.
  template <class Edit>
  static void tamper(Recording& rec, std::size_t i, Edit edit) {
    auto t = std::make_unique<record::TickRecordData>();
    ASSERT_TRUE(record::decode_tick(rec.encoding, rec.ticks[i], *t));
    edit(*t);
    std::vector<std::uint8_t> out(record::proto::kMaxTickBytes);
    const std::size_t n = record::proto::encode_tick(out, t->tick_index, t->now_ns, t->snapshot,
                                                     t->command, t->state_path);
    ASSERT_GT(n, 0U);
    out.resize(n);
    rec.ticks[i] = out;
  }
  static inline fs::path dir_;
  static inline std::unique_ptr<config::Configuration> config_;
  static inline std::unique_ptr<Recording> recording_;
};

TEST_F(ReplayTest, RecordedRunReplaysIdentically) {
  ASSERT_TRUE(recording_->ok) << recording_->error;
  const ReplayReport r = replay(*recording_, *config_);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_EQ(r.ticks, recording_->ticks.size());
  EXPECT_GE(r.ticks, 590U);
  EXPECT_TRUE(r.identical()) << format_replay_report(r, true);
  EXPECT_EQ(r.lidar_scans_missing, 0U);
  // Every recorded /viz/scene (one per 200 ms of ticks) was rebuilt and matched.
  EXPECT_EQ(r.viz_compared, recording_->viz_scene.size());
  EXPECT_GE(r.viz_compared, r.ticks / 12);
  EXPECT_FALSE(r.first_divergence_tick);
  EXPECT_EQ(r.recorded_paths.size(), r.replayed_paths.size());
  EXPECT_NE(format_replay_report(r, false).find("identical"), std::string::npos);
}

TEST_F(ReplayTest, TamperedFieldsAreReportedWithTickAndField) {
  Recording rec = *recording_;
  tamper(rec, 400, [](record::TickRecordData& t) { t.command.pulse_us[1] += 1; });
  tamper(rec, 450, [](record::TickRecordData& t) { t.state_path = "hold/elsewhere"; });
  tamper(rec, 500, [](record::TickRecordData& t) { t.command.active = !t.command.active; });
  const ReplayReport r = replay(rec, *config_);
  ASSERT_TRUE(r.ok);
  ASSERT_EQ(r.differences.size(), 3U) << format_replay_report(r, true);
  EXPECT_EQ(r.differences[0].tick_index, 400U);
  // Named by what the channel drives (the hopping boat: a servo and a thruster).
  EXPECT_EQ(r.differences[0].field, "thruster pulse_us (command.pulse_us[1])");
  EXPECT_EQ(r.pulses[1].name, "thruster");
  EXPECT_EQ(r.pulses[1].ticks_different, 1U);
  EXPECT_EQ(r.pulses[1].largest_difference_us, 1U);
  EXPECT_EQ(r.pulses[1].largest_at_tick, 400U);
  EXPECT_EQ(r.pulses[0].ticks_different, 0U);
  EXPECT_EQ(r.differences[1].tick_index, 450U);
  EXPECT_EQ(r.differences[1].field, "state_path");
  EXPECT_EQ(r.differences[1].recorded, "hold/elsewhere");
  EXPECT_EQ(r.differences[2].field, "command.active");
  EXPECT_EQ(r.ticks_different, 3U);
  ASSERT_TRUE(r.first_divergence_tick);
  EXPECT_EQ(*r.first_divergence_tick, 400U);
  const std::string text = format_replay_report(r, true);
  EXPECT_NE(text.find("tick 400"), std::string::npos) << text;
  EXPECT_NE(text.find("3 of"), std::string::npos) << text;
  EXPECT_NE(text.find("thruster pulse: differs in 1 ticks, by up to 1 us (tick 400"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("servo pulse: identical in every tick"), std::string::npos) << text;
}

TEST_F(ReplayTest, AlteredVisualizationIsReported) {
  Recording rec = *recording_;
  ASSERT_GT(rec.viz_scene.size(), 50U);
  auto it = std::next(rec.viz_scene.begin(), 50);
  it->second ^= 1U;
  const ReplayReport r = replay(rec, *config_);
  ASSERT_EQ(r.differences.size(), 1U) << format_replay_report(r, true);
  EXPECT_EQ(r.differences[0].field, "viz.scene");
  // Keyed by log time: the tick time plus the recording's UTC offset.
  EXPECT_EQ(static_cast<std::uint64_t>(r.differences[0].now_ns + rec.log_time_offset_ns),
            it->first);
}

TEST_F(ReplayTest, MaxDiffsLimitsTheListNotTheCount) {
  Recording rec = *recording_;
  for (std::size_t i = 300; i < 310; ++i) {
    tamper(rec, i, [](record::TickRecordData& t) { t.command.led = msg::LedColour::kRed; });
  }
  const ReplayReport r = replay(rec, *config_, {4});
  EXPECT_EQ(r.differences.size(), 4U);
  EXPECT_GE(r.fields_different, 10U);
  EXPECT_NE(format_replay_report(r, false).find("more differences"), std::string::npos);
}

TEST_F(ReplayTest, MissingScanAndBrokenTickAreCounted) {
  Recording rec = *recording_;
  ASSERT_FALSE(rec.lidar.empty());
  // The scan tick 300 saw, as if the recorder had dropped it.
  auto t = std::make_unique<record::TickRecordData>();
  ASSERT_TRUE(record::decode_tick(rec.encoding, rec.ticks[300], *t));
  ASSERT_EQ(rec.lidar.erase(t->snapshot.lidar.sequence), 1U);
  rec.ticks[10].assign({99, 1, 2});  // not a message (a group start, which is never written)
  const ReplayReport r = replay(rec, *config_);
  EXPECT_GT(r.lidar_scans_missing, 0U);
  EXPECT_EQ(r.ticks_undecodable, 1U);
  EXPECT_NE(format_replay_report(r, false).find("warning"), std::string::npos);
}

TEST_F(ReplayTest, TheDumpedConfigurationReplaysWithZeroDifferences) {
  const fs::path dump = dir_ / "dump";
  std::vector<fs::path> written;
  std::string error;
  ASSERT_TRUE(dump_configuration(recording_->config_yaml, dump, written, error)) << error;
  ASSERT_GE(written.size(), 3U);
  for (const char* name : {"boat.yaml", "devices.yaml", "mission.yaml"}) {
    EXPECT_TRUE(fs::exists(dump / name)) << name;
  }
  // The files as `coxswain replay --config-dir DUMP --mission DUMP/mission.yaml` loads them.
  config::ConfigErrors errors;
  config::Configuration c{config::load_boat_config((dump / "boat.yaml").string(), errors),
                          config::load_devices_config((dump / "devices.yaml").string(), errors),
                          config::load_mission_config((dump / "mission.yaml").string(), errors)};
  if (fs::exists(dump / "vision.yaml")) {
    if (auto v = config::load_vision_file((dump / "vision.yaml").string(), errors)) {
      c.vision.params = *v;
    }
  }
  ASSERT_TRUE(errors.empty()) << errors.format();
  const ReplayReport r = replay(*recording_, c);
  EXPECT_TRUE(r.identical()) << format_replay_report(r, true);
  EXPECT_EQ(r.viz_compared, recording_->viz_scene.size());

  // Nothing is overwritten: a second dump into the same folder is refused, the files kept.
  const auto before = fs::last_write_time(dump / "mission.yaml");
  written.clear();
  EXPECT_FALSE(dump_configuration(recording_->config_yaml, dump, written, error));
  EXPECT_NE(error.find("exists"), std::string::npos) << error;
  EXPECT_TRUE(written.empty());
  EXPECT_EQ(fs::last_write_time(dump / "mission.yaml"), before);
  EXPECT_FALSE(dump_configuration("not: [yaml", dir_ / "dump2", written, error));
}

TEST_F(ReplayTest, AChangedMissionSaysWhichValueDiffersFirst) {
  config::Configuration c = *config_;
  c.mission.heading_pid.kp_per_deg *= 3.0;  // steers harder
  c.boat.hull.length_m += 0.1;              // the hull drawn in the scene is longer
  const ReplayReport r = replay(*recording_, c, {.max_diffs = 50});
  ASSERT_FALSE(r.identical());
  ASSERT_FALSE(r.differences.empty());
  bool visualization_in_words = false;
  for (const Difference& d : r.differences) {
    // A value, never a hash: the field names the differing value of the scene.
    if (d.field.starts_with("viz.scene ")) {
      visualization_in_words = true;
      EXPECT_FALSE(d.recorded.starts_with("fnv1a:")) << d.field;
      EXPECT_FALSE(d.replayed.starts_with("fnv1a:")) << d.field;
    }
  }
  EXPECT_TRUE(visualization_in_words) << format_replay_report(r, true);
  const Difference& first = r.differences.front();
  EXPECT_EQ(first.tick_index, 0U);  // the hull differs from the first tick on
  EXPECT_EQ(first.field, "viz.scene entities[0].cubes[0].pose.position.x");
  // A stronger gain steers harder: the servo's pulses differ; the summary says by how much.
  EXPECT_GT(r.pulses[0].ticks_different, 0U);
  EXPECT_GT(r.pulses[0].largest_difference_us, 0U);
  const std::string text = format_replay_report(r, true);
  EXPECT_NE(text.find("first: "), std::string::npos) << text;
  EXPECT_NE(text.find("servo pulse: differs in"), std::string::npos) << text;
}

TEST_F(ReplayTest, RecordedConfigurationReadsBack) {
  for (const char* mission : {"hopping", "obstacle_course", "docking", "kaboat2026"}) {
    const config::Configuration c = test::shipped_config(mission);
    const std::string yaml = config::to_yaml(c);
    config::ConfigErrors errors;
    const auto back = configuration_from_yaml(yaml, errors);
    ASSERT_TRUE(back) << mission << ":\n" << errors.format();
    // Everything but where the files were loaded from is the same, to the last bit.
    config::Configuration a = c;
    config::Configuration b = *back;
    a.boat.file = b.boat.file = "";
    a.devices.file = b.devices.file = "";
    a.mission.file = b.mission.file = "";
    EXPECT_EQ(config::to_yaml(a), config::to_yaml(b)) << mission;
  }
  config::ConfigErrors errors;
  EXPECT_FALSE(configuration_from_yaml("boat: {name: x}\n", errors));
  EXPECT_FALSE(errors.empty());
}

// Bit for bit, not just "prints the same": geo heights and doubles that need all 17 digits
// (a 6-digit print moves the origin by metres and the replayed pose no longer matches).
TEST(RecordedConfiguration, DoublesAndHeightsRoundTripExactly) {
  config::Configuration c = test::shipped_config("hopping");
  ASSERT_FALSE(c.mission.tasks.empty());
  c.mission.origin.lat_deg = std::nextafter(37.123456789012345, 90.0);
  c.mission.origin.lon_deg = 126.98765432109876;
  c.mission.origin.height_m = 12.345678901234567;
  config::TaskConfig* with_waypoints = nullptr;
  for (auto& t : c.mission.tasks) {
    if (!t.waypoints.empty()) with_waypoints = &t;
  }
  ASSERT_NE(with_waypoints, nullptr);
  with_waypoints->waypoints[0].lat_deg = 0.1 + 0.2;  // 0.30000000000000004
  with_waypoints->waypoints[0].height_m = -3.0 / 7.0;
  c.mission.tick_rate_hz = 50.0 + 1e-12;

  const std::string yaml = config::to_yaml(c);
  config::ConfigErrors errors;
  const auto back = configuration_from_yaml(yaml, errors);
  ASSERT_TRUE(back) << errors.format();
  const auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v); };
  EXPECT_EQ(bits(back->mission.origin.lat_deg), bits(c.mission.origin.lat_deg));
  EXPECT_EQ(bits(back->mission.origin.lon_deg), bits(c.mission.origin.lon_deg));
  EXPECT_EQ(bits(back->mission.origin.height_m), bits(c.mission.origin.height_m));
  EXPECT_EQ(bits(back->mission.tick_rate_hz), bits(c.mission.tick_rate_hz));
  ASSERT_EQ(back->mission.tasks.size(), c.mission.tasks.size());
  for (std::size_t i = 0; i < c.mission.tasks.size(); ++i) {
    const auto& want = c.mission.tasks[i].waypoints;
    const auto& got = back->mission.tasks[i].waypoints;
    ASSERT_EQ(got.size(), want.size()) << "task " << i;
    for (std::size_t k = 0; k < want.size(); ++k) {
      EXPECT_EQ(bits(got[k].lat_deg), bits(want[k].lat_deg)) << "task " << i << " wp " << k;
      EXPECT_EQ(bits(got[k].lon_deg), bits(want[k].lon_deg)) << "task " << i << " wp " << k;
      EXPECT_EQ(bits(got[k].height_m), bits(want[k].height_m)) << "task " << i << " wp " << k;
    }
  }
}

// The operator retunes the boat mid-run (heading gain and speed schedule, as the live view's
// parameter interface would): the recording carries the applied set on /params and replay applies
// it before the same tick, so every decision matches; left out, the replay diverges from there.
TEST_F(ReplayTest, ALiveParameterChangeIsRecordedAndReplayedAtTheSameTick) {
  test::ParameterChange change;
  change.at_s = 7.0;  // sailing the first leg by then
  change.edit = [](mission::TunableParameters& p) {
    p.heading_pid.kp_per_deg *= 1.8;
    p.speed.min_thrust_frac = 0.5;
    p.speed.max_thrust_frac = 0.8;
  };
  const fs::path mcap = dir_ / "retuned.mcap";
  const auto made = test::record_sim_run(mcap, *config_, "kaboat2022_hopping.yaml", 12.0, change);
  ASSERT_TRUE(made.ok) << made.error;
  ASSERT_EQ(made.parameters_error, "");
  EXPECT_EQ(made.dropped, 0U);
  const Recording rec = load_recording(mcap);
  ASSERT_TRUE(rec.ok) << rec.error;
  ASSERT_EQ(rec.parameter_sets.size(), 1U);
  const record::ParameterSetRecord& set = rec.parameter_sets[0];
  // About 7 s at 50 Hz: the first tick stepped with the new set.
  EXPECT_GE(set.tick_index, 349U);
  EXPECT_LE(set.tick_index, 352U);
  bool kp_recorded = false;
  for (const auto& [name, value] : set.values) {
    if (name == "heading_pid.kp_per_deg") {
      kp_recorded = std::bit_cast<std::uint64_t>(value) ==
                    std::bit_cast<std::uint64_t>(config_->mission.heading_pid.kp_per_deg * 1.8);
    }
  }
  EXPECT_TRUE(kp_recorded);

  const ReplayReport r = replay(rec, *config_);
  ASSERT_TRUE(r.ok) << r.error;
  EXPECT_TRUE(r.identical()) << format_replay_report(r, true);
  EXPECT_EQ(r.parameter_sets_applied, 1U);
  ASSERT_EQ(r.parameter_ticks.size(), 1U);
  EXPECT_EQ(r.parameter_ticks[0], set.tick_index);
  EXPECT_NE(format_replay_report(r, false).find("1 live parameter set applied at tick " +
                                                std::to_string(set.tick_index)),
            std::string::npos)
      << format_replay_report(r, false);

  ReplayOptions without;
  without.apply_parameter_sets = false;
  const ReplayReport w = replay(rec, *config_, without);
  ASSERT_TRUE(w.ok);
  EXPECT_FALSE(w.identical());
  ASSERT_TRUE(w.first_divergence_tick);
  EXPECT_GE(*w.first_divergence_tick, set.tick_index);
  EXPECT_LT(*w.first_divergence_tick, set.tick_index + 50);  // within a second of the change
}

TEST_F(ReplayTest, ARecordedSetTheCoreRefusesIsCountedNotApplied) {
  Recording rec = *recording_;
  rec.parameter_sets.push_back({100, 0, {{"heading_pid.kp_per_deg", 7.0}}});  // out of range
  rec.parameter_sets.push_back({200, 0, {{"no.such.parameter", 1.0}}});
  const ReplayReport r = replay(rec, *config_);
  EXPECT_EQ(r.parameter_sets_refused, 2U);
  EXPECT_EQ(r.parameter_sets_applied, 0U);
  EXPECT_TRUE(r.identical());
  EXPECT_NE(format_replay_report(r, false).find("warning: 2 recorded parameter sets"),
            std::string::npos);
}

TEST_F(ReplayTest, UnreadableFilesAreNotRecordings) {
  EXPECT_FALSE(load_recording(dir_ / "absent.mcap").ok);
  const fs::path junk = dir_ / "junk.mcap";
  std::ofstream(junk) << "junk";
  const Recording r = load_recording(junk);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(replay(r, *config_).ok);
}

}  // namespace
}  // namespace coxswain::replay
