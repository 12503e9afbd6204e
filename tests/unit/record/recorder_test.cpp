// SPDX-License-Identifier: Apache-2.0
// The threaded Recorder: every channel written with counts matching its stats, producers never
// blocking on full queues, disk-full at start and mid-run, and a readable file after SIGKILL.
#include <gtest/gtest.h>
#include <signal.h>
#include <spdlog/logger.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>
#include <vector>

#include "coxswain/record/layouts.hpp"
#include "coxswain/record/mcap_reader.hpp"
#include "coxswain/record/proto_codec.hpp"
#include "coxswain/record/recorder.hpp"
#include "coxswain/record/track_line.hpp"

namespace coxswain::record {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

fs::path temp_path(const std::string& name) {
  return fs::temp_directory_path() / ("coxswain_rec_" + std::to_string(::getpid()) + "_" + name);
}

/// Polls `done` every millisecond for up to `limit`.
template <class F>
bool wait_for(F done, std::chrono::milliseconds limit = 20s) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (!done()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(1ms);
  }
  return true;
}

RecorderOptions fast_options(const fs::path& path) {
  RecorderOptions o;
  o.path = path;
  o.chunk_period_ns = 50 * core::kNsPerMs;
  o.idle_sleep_ns = core::kNsPerMs;
  o.sync = false;  // tmpfs or not, the tests need no durability
  o.config_yaml = "boat:\n  name: test\n";
  o.build_version = "0.1.0-test";
  return o;
}

struct FileSummary {
  McapReadReport report;
  std::map<std::string, std::uint64_t> counts;  // per topic
  std::map<msg::DeviceId, std::vector<std::uint8_t>> raw_from_device;
  std::vector<TickRecordData> ticks;
  std::vector<ParameterSetRecord> parameter_sets;
  std::map<std::string, std::string> schema_encoding;  // per topic
};

FileSummary summarize(const fs::path& path) {
  FileSummary s;
  McapReader reader;
  EXPECT_TRUE(reader.open(path));
  std::map<std::uint16_t, std::string> topics;
  s.report = reader.read([&](const McapMessageView& m) {
    if (topics.empty()) {
      for (const auto& [id, c] : reader.channels()) topics[id] = c.topic;
    }
    const std::string& topic = topics[m.channel_id];
    ++s.counts[topic];
    if (topic.starts_with("/raw/")) {
      RawRecord raw;
      EXPECT_TRUE(proto::decode_raw(m.data, raw));
      if (raw.direction == drivers::RawDirection::kFromDevice) {
        auto& v = s.raw_from_device[raw.device];
        v.insert(v.end(), raw.bytes.begin(), raw.bytes.end());
      }
    } else if (topic == "/tick") {
      s.ticks.emplace_back();
      EXPECT_TRUE(proto::decode_tick(m.data, s.ticks.back()));
    } else if (topic == "/params") {
      s.parameter_sets.emplace_back();
      EXPECT_TRUE(proto::decode_parameters(m.data, s.parameter_sets.back()));
    }
  });
  for (const auto& [id, c] : reader.channels()) {
    s.schema_encoding[c.topic] = c.schema_id == 0 ? "" : reader.schemas().at(c.schema_id).encoding;
    if (s.schema_encoding[c.topic] == "jsonschema") {
      const auto& data = reader.schemas().at(c.schema_id).data;
      EXPECT_TRUE(nlohmann::json::accept(data.begin(), data.end())) << c.topic;
    }
  }
  return s;
}

/// The JSON of every message on `topic`, in file order.
std::vector<nlohmann::json> json_messages(const fs::path& path, std::string_view topic) {
  std::vector<nlohmann::json> out;
  McapReader reader;
  EXPECT_TRUE(reader.open(path));
  (void)reader.read([&](const McapMessageView& m) {
    // The channels are known once reading has begun.
    if (reader.channels().at(m.channel_id).topic == topic) {
      out.push_back(nlohmann::json::parse(m.data.begin(), m.data.end()));
    }
  });
  return out;
}

std::vector<std::uint8_t> pattern(std::size_t n, std::uint32_t seed) {
  std::vector<std::uint8_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<std::uint8_t>((i * 131 + seed) & 0xFF);
  return v;
}

TEST(Recorder, MapIsWrittenEveryPeriodWithTheWholeTrackThinned) {
  const fs::path path = temp_path("map.mcap");
  auto store = std::make_unique<core::LatestStore>();
  core::SteadyClock clock;
  RecorderOptions o = fast_options(path);
  o.map.marks.push_back({MapMark::Kind::kWaypoint, "hopping 1", {35.1, 129.0, {30.0, 0.0}}});
  Recorder rec(o, store.get(), clock);
  ASSERT_TRUE(rec.start()) << rec.stats().error;
  auto snap = std::make_unique<core::Snapshot>();
  TickViz viz;
  viz.pose_valid = true;
  // 2000 ticks 20 ms apart (40 s), the boat 1.5 m further north at each: 3 km of track.
  constexpr std::uint64_t kTicks = 2000;
  for (std::uint64_t i = 0; i < kTicks; ++i) {
    viz.north_m = 1.5 * static_cast<double>(i);
    TickInput in;
    in.tick_index = i;
    in.now_ns = static_cast<core::TimeNs>(i) * 20 * core::kNsPerMs;
    in.snapshot = snap.get();
    in.viz = &viz;
    ASSERT_TRUE(wait_for([&] { return rec.record_tick(in); }));
  }
  rec.stop();
  const RecorderStats st = rec.stats();
  EXPECT_EQ(st[RecordChannel::kTick].written, kTicks);
  // At 0 s, then whenever 5 s have passed: 0, 5, ..., 35 s.
  EXPECT_EQ(st[RecordChannel::kVizMap].written, 8U);
  EXPECT_EQ(st[RecordChannel::kMapGeoJson].written, 8U);
  const auto maps = json_messages(path, "/viz/map");
  ASSERT_EQ(maps.size(), 8U);
  EXPECT_EQ(maps[0]["entities"][0]["texts"][0]["text"], "hopping 1");
  EXPECT_TRUE(maps[0]["entities"][1]["lines"].empty());  // one point: no line yet
  const auto& track = maps.back()["entities"][1]["lines"][0]["points"];
  // Bounded, yet from the start to about where the boat was at 35 s (1750 ticks).
  EXPECT_LE(track.size(), TrackLine::kMaxPoints);
  EXPECT_GE(track.size(), TrackLine::kMaxPoints / 4);
  EXPECT_DOUBLE_EQ(track.front()["y"].get<double>(), 0.0);
  EXPECT_NEAR(track.back()["y"].get<double>(), 1.5 * 1750, 16.0);
  double last_y = -1.0;
  for (const auto& p : track) {
    EXPECT_GT(p["y"].get<double>(), last_y);  // in order, no point twice
    last_y = p["y"].get<double>();
  }
  const auto geo = json_messages(path, "/map/geojson");
  ASSERT_EQ(geo.size(), 8U);
  EXPECT_NE(geo[0]["geojson"].get<std::string>().find("hopping 1"), std::string::npos);
  fs::remove(path);
}

TEST(Recorder, CameraImagesAreRecordedWithTheirDetectionsAndOversizedOnesCounted) {
  const fs::path path = temp_path("images.mcap");
  auto store = std::make_unique<core::LatestStore>();
  core::SteadyClock clock;
  Recorder rec(fast_options(path), store.get(), clock);
  ASSERT_TRUE(rec.start()) << rec.stats().error;
  const std::vector<std::uint8_t> jpeg = pattern(20'000, 7);
  msg::CameraDetections d;
  d.image_width_px = 640;
  ASSERT_TRUE(d.push(
      {msg::Colour::kBlue, msg::Shape::kCircle, 0.0F, 100.0F, 100.0F, 20.0F, 20.0F, 400.0F, 0.8F}));
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(wait_for([&] { return rec.record_image(1000 + i, jpeg, d, 1.0); }));
  }
  const std::vector<std::uint8_t> huge(Recorder::kMaxImageBytes + 1, 0);
  EXPECT_FALSE(rec.record_image(2000, huge, d, 1.0));
  rec.stop();
  const RecorderStats st = rec.stats();
  EXPECT_EQ(st[RecordChannel::kCameraImage].written, 3U);
  EXPECT_EQ(st[RecordChannel::kCameraAnnotations].written, 3U);
  EXPECT_GE(st[RecordChannel::kCameraImage].dropped, 1U);
  const auto images = json_messages(path, "/camera/image");
  ASSERT_EQ(images.size(), 3U);
  EXPECT_EQ(images[0]["format"], "jpeg");
  // Every byte, base64: 20000 bytes are 26668 characters with padding.
  EXPECT_EQ(images[0]["data"].get<std::string>().size(), 26668U);
  const auto notes = json_messages(path, "/camera/annotations");
  ASSERT_EQ(notes.size(), 3U);
  EXPECT_EQ(notes[0]["texts"][0]["text"], "blue circle 0.80");
  EXPECT_EQ(notes[0]["points"][0]["timestamp"], images[0]["timestamp"]);  // one time for both
  fs::remove(path);
}

TEST(Recorder, EveryChannelRecordedWithCountsMatchingItsStats) {
  const fs::path path = temp_path("all.mcap");
  auto store = std::make_unique<core::LatestStore>();
  core::SteadyClock clock;
  Recorder rec(fast_options(path), store.get(), clock);
  ASSERT_TRUE(rec.start()) << rec.stats().error;
  auto logger = std::make_shared<spdlog::logger>("coxswain", rec.log_sink());

  std::vector<std::uint8_t> sent_lidar, sent_gnss;
  std::thread lidar([&] {
    auto scan = std::make_unique<msg::LidarScan>();
    for (std::uint32_t i = 0; i < 20; ++i) {
      // 3000-byte reads are split over several slots; the stream must come out whole.
      const auto bytes = pattern(i % 5 == 0 ? 3000 : 100 + i, i);
      sent_lidar.insert(sent_lidar.end(), bytes.begin(), bytes.end());
      rec.on_raw(msg::DeviceId::kLidar, drivers::RawDirection::kFromDevice, i * 1000, bytes);
      scan->clear();
      for (int p = 0; p < 360; ++p) {
        (void)scan->push({static_cast<float>(p) - 179.0F, 2.0F + static_cast<float>(i), 10, p});
      }
      scan->revolution = i;
      store->lidar.publish(*scan, i * 1000);
      std::this_thread::sleep_for(2ms);
    }
  });
  std::thread gnss([&] {
    for (std::uint32_t i = 0; i < 30; ++i) {
      const auto bytes = pattern(60, 1000 + i);
      sent_gnss.insert(sent_gnss.end(), bytes.begin(), bytes.end());
      rec.on_raw(msg::DeviceId::kGnss, drivers::RawDirection::kFromDevice, i * 2000, bytes);
      rec.on_raw(msg::DeviceId::kGnss, drivers::RawDirection::kToDevice, i * 2000, bytes);
      msg::GnssFix fix;
      fix.lat_deg = 35.0 + i * 1e-5;
      fix.lon_deg = 129.0;
      fix.fix_ok = true;
      store->gnss.publish(fix, i * 2000);
      msg::DeviceHealth h;
      h.device = msg::DeviceId::kGnss;
      h.frames_ok = i;
      store->health_of(msg::DeviceId::kGnss).publish(h, i * 2000);
      std::this_thread::sleep_for(1ms);
    }
  });
  std::thread tick([&] {
    auto snap = std::make_unique<core::Snapshot>();
    TickViz viz;
    viz.pose_valid = true;
    viz.target_valid = true;
    viz.obstacle_count = 1;
    for (std::uint64_t i = 0; i < 100; ++i) {
      store->snapshot(*snap);
      viz.north_m = static_cast<double>(i);
      TickInput in;
      in.tick_index = i;
      in.now_ns = static_cast<core::TimeNs>(i) * 20 * core::kNsPerMs;
      in.snapshot = snap.get();
      in.command.pulse_us = {1500, static_cast<std::uint16_t>(1500 + i)};
      in.state_path = "ACTIVE:HOPPING";
      in.viz = i % 2 == 0 ? &viz : nullptr;
      EXPECT_TRUE(rec.record_tick(in));
      if (i == 60) {
        const NamedValue values[] = {{"heading_pid.kp_per_deg", 0.1 + 0.2},
                                     {"vision.red.h_min", 168.0}};
        EXPECT_TRUE(rec.record_parameters(61, in.now_ns, values));
      }
      if (i % 10 == 0) logger->info("tick {}", i);
      std::this_thread::sleep_for(500us);
    }
  });
  lidar.join();
  gnss.join();
  tick.join();
  msg::ImuSample imu;
  store->imu.publish(imu, 5);
  store->camera.publish(msg::CameraDetections{}, 6);
  store->arduino.publish(msg::ArduinoStatus{}, 7);
  store->operator_input.publish(msg::OperatorInput{}, 8);
  ASSERT_TRUE(wait_for([&] { return rec.stats()[RecordChannel::kOperator].written == 1; }));
  rec.stop({{"judge", {{"json", R"({"score_s":54.01})"}}}});  // known only at the end
  const RecorderStats st = rec.stats();
  EXPECT_FALSE(st.failed) << st.error;
  EXPECT_GE(st.chunks, 1U);

  const FileSummary f = summarize(path);
  EXPECT_TRUE(f.report.error.empty()) << f.report.error;
  EXPECT_TRUE(f.report.complete);
  EXPECT_TRUE(f.report.data_crc_ok);
  EXPECT_TRUE(f.report.summary_crc_ok);
  EXPECT_TRUE(f.report.index_ok);
  EXPECT_EQ(f.report.metadata.at("config").at("yaml"), "boat:\n  name: test\n");
  EXPECT_EQ(f.report.metadata.at("coxswain").at("build_version"), "0.1.0-test");
  ASSERT_TRUE(f.report.metadata.contains("judge"));
  EXPECT_EQ(f.report.metadata.at("judge").at("json"), R"({"score_s":54.01})");
  ASSERT_TRUE(f.report.statistics.has_value());
  EXPECT_EQ(f.report.statistics->metadata_count, 3U);
  EXPECT_EQ(f.report.statistics->channel_count, kRecordChannelCount);

  // Every channel's file count equals what the recorder says it wrote.
  std::uint64_t total = 0;
  for (std::size_t i = 0; i < kRecordChannelCount; ++i) {
    const auto c = static_cast<RecordChannel>(i);
    const std::string topic(channel_topic(c));
    const auto it = f.counts.find(topic);
    EXPECT_EQ(it == f.counts.end() ? 0U : it->second, st[c].written) << topic;
    total += st[c].written;
  }
  EXPECT_EQ(f.report.statistics->message_count, total);

  // Queues were deep enough for this load: nothing dropped on the raw and tick channels.
  for (auto c : {RecordChannel::kRawLidar, RecordChannel::kRawGnss, RecordChannel::kTick,
                 RecordChannel::kLog}) {
    EXPECT_EQ(st[c].dropped, 0U) << channel_topic(c);
  }
  EXPECT_EQ(f.raw_from_device.at(msg::DeviceId::kLidar), sent_lidar);
  EXPECT_EQ(f.raw_from_device.at(msg::DeviceId::kGnss), sent_gnss);
  EXPECT_EQ(st.raw_bytes, sent_lidar.size() + 2 * sent_gnss.size());
  EXPECT_EQ(st[RecordChannel::kTick].written, 100U);
  // The even ticks carry a scene, 40 ms apart; written every 200 ms: 0, 200, ..., 1800 ms.
  EXPECT_EQ(st[RecordChannel::kVizScene].written, 10U);
  EXPECT_EQ(st[RecordChannel::kVizPose].written, 10U);
  // 100 ticks 20 ms apart: the map at the first tick only (period 5 s).
  EXPECT_EQ(st[RecordChannel::kVizMap].written, 1U);
  EXPECT_EQ(st[RecordChannel::kMapGeoJson].written, 1U);
  EXPECT_EQ(st[RecordChannel::kLog].written, 10U);
  EXPECT_EQ(st[RecordChannel::kParams].written, 1U);
  ASSERT_EQ(f.parameter_sets.size(), 1U);
  EXPECT_EQ(f.parameter_sets[0].tick_index, 61U);
  ASSERT_EQ(f.parameter_sets[0].values.size(), 2U);
  EXPECT_EQ(f.parameter_sets[0].values[0].first, "heading_pid.kp_per_deg");
  EXPECT_EQ(f.parameter_sets[0].values[0].second, 0.1 + 0.2);  // every bit
  EXPECT_EQ(f.parameter_sets[0].values[1].first, "vision.red.h_min");
  EXPECT_EQ(f.schema_encoding.at("/params"), "protobuf");
  ASSERT_EQ(f.ticks.size(), 100U);
  for (std::size_t i = 0; i < f.ticks.size(); ++i) {
    EXPECT_EQ(f.ticks[i].tick_index, i);
    EXPECT_EQ(f.ticks[i].state_path, "ACTIVE:HOPPING");
    EXPECT_EQ(f.ticks[i].command.pulse_us[1], 1500 + i);
  }
  // Sampled channels: recorded + dropped (overwritten before sampling) = values published.
  EXPECT_EQ(st[RecordChannel::kLidar].written + st[RecordChannel::kLidar].dropped, 20U);
  EXPECT_EQ(st[RecordChannel::kGnss].written + st[RecordChannel::kGnss].dropped, 30U);
  // The 20 scans are 1 us apart: the scan's view once (every 200 ms at most).
  EXPECT_EQ(st[RecordChannel::kVizScan].written, 1U);
  EXPECT_EQ(st[RecordChannel::kVizFix].written, st[RecordChannel::kGnss].written);
  EXPECT_EQ(st[RecordChannel::kImu].written, 1U);
  EXPECT_EQ(st[RecordChannel::kCamera].written, 1U);
  EXPECT_EQ(st[RecordChannel::kArduino].written, 1U);
  EXPECT_EQ(f.schema_encoding.at("/viz/scene"), "jsonschema");
  EXPECT_EQ(f.schema_encoding.at("/tick"), "protobuf");
  fs::remove(path);
}

TEST(Recorder, ProducersNeverBlockOnFullQueuesAndDropsAreCounted) {
  const fs::path path = temp_path("full_queue.mcap");
  core::SteadyClock clock;
  RecorderOptions o = fast_options(path);
  o.raw_queue_slots = 8;
  o.tick_queue_slots = 4;
  o.idle_sleep_ns = 60 * core::kNsPerSec;  // the writer naps: the queues fill up
  Recorder rec(o, nullptr, clock);
  ASSERT_TRUE(rec.start());
  std::this_thread::sleep_for(20ms);  // let the writer find its queues empty and nap
  const auto bytes = pattern(100, 1);
  std::thread producer([&] {
    for (int i = 0; i < 1000; ++i) {
      rec.on_raw(msg::DeviceId::kImu, drivers::RawDirection::kFromDevice, i, bytes);
    }
  });
  auto snap = std::make_unique<core::Snapshot>();
  int accepted = 0;
  for (int i = 0; i < 50; ++i) {
    TickInput in;
    in.snapshot = snap.get();
    in.tick_index = static_cast<std::uint64_t>(i);
    accepted += rec.record_tick(in) ? 1 : 0;
  }
  producer.join();  // returns although nobody drains: on_raw never waits
  const RecorderStats during = rec.stats();
  EXPECT_GE(during[RecordChannel::kRawImu].dropped, 1000U - 8U - 256U);
  EXPECT_LE(accepted, 4 + 256);
  EXPECT_GE(during[RecordChannel::kTick].dropped, 50U - static_cast<std::uint64_t>(accepted));
  rec.stop();  // wakes the napping writer
  const RecorderStats st = rec.stats();
  EXPECT_EQ(st[RecordChannel::kRawImu].written + st[RecordChannel::kRawImu].dropped, 1000U);
  EXPECT_EQ(st[RecordChannel::kTick].written + st[RecordChannel::kTick].dropped, 50U);
  EXPECT_EQ(st[RecordChannel::kTick].written, static_cast<std::uint64_t>(accepted));
  const FileSummary f = summarize(path);
  EXPECT_EQ(f.counts.at("/raw/imu"), st[RecordChannel::kRawImu].written);
  fs::remove(path);
}

// The spdlog sink on a logger shared by several threads: each line is queued without waiting
// (a full queue drops and counts it), so written + dropped = every line logged.
TEST(Recorder, LogSinkNeverWaitsAndCountsEveryLineItCannotQueue) {
  const fs::path path = temp_path("log_flood.mcap");
  core::SteadyClock clock;
  RecorderOptions o = fast_options(path);
  o.log_queue_slots = 4;
  o.idle_sleep_ns = 20 * core::kNsPerMs;  // a slow writer: the queue fills
  Recorder rec(o, nullptr, clock);
  ASSERT_TRUE(rec.start());
  auto logger = std::make_shared<spdlog::logger>("flood", rec.log_sink());
  constexpr int kThreads = 3;
  constexpr int kLines = 2000;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      for (int i = 0; i < kLines; ++i) logger->warn("thread {} line {}", t, i);
    });
  }
  for (auto& t : threads) t.join();
  rec.stop();
  const RecorderStats st = rec.stats();
  EXPECT_EQ(st[RecordChannel::kLog].written + st[RecordChannel::kLog].dropped,
            static_cast<std::uint64_t>(kThreads * kLines));
  EXPECT_GT(st[RecordChannel::kLog].dropped, 0U);
  EXPECT_GT(st[RecordChannel::kLog].written, 0U);
  const FileSummary f = summarize(path);
  EXPECT_EQ(f.counts.at("/log"), st[RecordChannel::kLog].written);
  fs::remove(path);
}

TEST(Recorder, DiskFullAtStartIsReportedAndProducersCarryOn) {
  core::SteadyClock clock;
  RecorderOptions o = fast_options("/dev/full");
  Recorder rec(o, nullptr, clock);
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "/dev/full is not available";
  EXPECT_FALSE(rec.start());
  const RecorderStats st = rec.stats();
  EXPECT_TRUE(st.failed);
  EXPECT_FALSE(st.running);
  EXPECT_NE(st.error.find("No space left"), std::string::npos) << st.error;
  const auto bytes = pattern(10, 0);
  for (int i = 0; i < 100; ++i) {
    rec.on_raw(msg::DeviceId::kGnss, drivers::RawDirection::kFromDevice, i, bytes);
  }
  EXPECT_EQ(rec.stats()[RecordChannel::kRawGnss].dropped, 100U);
}

TEST(Recorder, WriteErrorMidRunStopsRecordingAndTheRunGoesOn) {
  // A file-size limit makes write(2) fail with EFBIG once the file reaches it, like a disk that
  // fills up in the middle of a run (SIGXFSZ ignored so the error comes back as errno).
  const fs::path path = temp_path("efbig.mcap");
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  struct sigaction old_action {};
  ASSERT_EQ(::sigaction(SIGXFSZ, &ignore, &old_action), 0);
  rlimit old_limit{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  rlimit limit = old_limit;
  limit.rlim_cur = 256 * 1024;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limit), 0);

  core::SteadyClock clock;
  RecorderOptions o = fast_options(path);
  o.chunk_period_ns = 10 * core::kNsPerMs;
  Recorder rec(o, nullptr, clock);
  ASSERT_TRUE(rec.start());
  std::mt19937 rng(7);
  std::vector<std::uint8_t> noise(512);  // incompressible, so the file grows
  std::uint64_t calls = 0;
  const bool failed = wait_for([&] {
    for (auto& b : noise) b = static_cast<std::uint8_t>(rng());
    rec.on_raw(msg::DeviceId::kLidar, drivers::RawDirection::kFromDevice,
               static_cast<core::TimeNs>(calls++), noise);
    return rec.stats().failed;
  });
  // Keep producing after the failure: nothing blocks, records are counted as dropped.
  for (int i = 0; i < 100; ++i) {
    rec.on_raw(msg::DeviceId::kLidar, drivers::RawDirection::kFromDevice, 0, noise);
  }
  rec.stop();
  ::setrlimit(RLIMIT_FSIZE, &old_limit);
  ::sigaction(SIGXFSZ, &old_action, nullptr);
  ASSERT_TRUE(failed) << "the size limit never stopped the recording";
  const RecorderStats st = rec.stats();
  EXPECT_NE(st.error.find("too large"), std::string::npos) << st.error;
  EXPECT_EQ(st[RecordChannel::kRawLidar].written + st[RecordChannel::kRawLidar].dropped,
            calls + 100);
  EXPECT_GE(st[RecordChannel::kRawLidar].dropped, 100U);
  const FileSummary f = summarize(path);
  EXPECT_FALSE(f.report.complete);
  EXPECT_EQ(f.report.chunk_crc_errors, 0U);
  EXPECT_GT(f.counts.count("/raw/lidar") != 0 ? f.counts.at("/raw/lidar") : 0U,
            0U);  // the chunks closed before the error are readable
  EXPECT_LE(fs::file_size(path), 256U * 1024U);
  fs::remove(path);
}

TEST(Recorder, SigkillLeavesAFileWithEveryClosedChunk) {
  const fs::path path = temp_path("killed.mcap");
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    // Child: record a numbered stream until a few chunks are on disk, then die mid-write.
    core::SteadyClock clock;
    RecorderOptions o = fast_options(path);
    o.chunk_period_ns = 20 * core::kNsPerMs;
    o.sync = true;
    Recorder rec(o, nullptr, clock);
    if (!rec.start()) ::_exit(2);
    std::vector<std::uint8_t> msg(64);
    for (std::uint64_t i = 0;; ++i) {
      for (std::size_t b = 0; b < 8; ++b) msg[b] = static_cast<std::uint8_t>(i >> (8 * b));
      rec.on_raw(msg::DeviceId::kImu, drivers::RawDirection::kFromDevice,
                 static_cast<core::TimeNs>(i), msg);
      if (rec.stats().chunks >= 5 && i % 97 == 0) ::kill(::getpid(), SIGKILL);
      std::this_thread::sleep_for(100us);
    }
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << "child exited with " << WEXITSTATUS(status);
  ASSERT_EQ(WTERMSIG(status), SIGKILL);

  McapReader reader;
  ASSERT_TRUE(reader.open(path));
  std::uint64_t n = 0;
  std::int64_t last = -1;
  bool ordered = true;
  const auto report = reader.read([&](const McapMessageView& m) {
    RawRecord raw;
    if (!proto::decode_raw(m.data, raw) || raw.bytes.size() != 64) return;
    std::uint64_t index = 0;
    for (std::size_t b = 0; b < 8; ++b)
      index |= static_cast<std::uint64_t>(raw.bytes[b]) << (8 * b);
    ordered = ordered && static_cast<std::int64_t>(index) > last;
    last = static_cast<std::int64_t>(index);
    ++n;
  });
  EXPECT_TRUE(report.header_ok);
  EXPECT_FALSE(report.complete);
  EXPECT_EQ(report.chunk_crc_errors, 0U);
  EXPECT_TRUE(report.error.empty()) << report.error;
  EXPECT_GE(report.chunks, 4U);  // the child saw at least 5 closed (one may hold only metadata)
  EXPECT_GT(n, 0U);
  EXPECT_TRUE(ordered);
  EXPECT_EQ(reader.channels().size(), kRecordChannelCount);
  fs::remove(path);
}

}  // namespace
}  // namespace coxswain::record
