// SPDX-License-Identifier: Apache-2.0
// Writes a recording with every channel the way a run does: device threads tee their protocol
// bytes and publish decoded messages into a LatestStore, a tick thread records Snapshots,
// commands, state paths and viz data at 50 Hz (and one live parameter set), log lines go through
// the recorder's spdlog sink.
// Then writes expected.json: the per-channel counts the recorder says it wrote, for
// read_mcap.mjs to compare with what @mcap/core reads. Exit 1 when the run's own counters and the
// recorder disagree (recorded + dropped must equal what was produced).
// Usage: record_sample_writer OUT.mcap EXPECTED.json
#include <spdlog/logger.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <thread>
#include <vector>

#include "coxswain/record/recorder.hpp"
#include "device_streams.hpp"

using namespace coxswain;
using namespace std::chrono_literals;

namespace {

void tee(record::Recorder& rec, msg::DeviceId device, const core::Clock& clock,
         const std::vector<std::uint8_t>& bytes, std::size_t piece) {
  for (std::size_t at = 0; at < bytes.size(); at += piece) {
    const std::size_t n = std::min(piece, bytes.size() - at);
    rec.on_raw(device, drivers::RawDirection::kFromDevice, clock.now_ns(),
               std::span<const std::uint8_t>(bytes).subspan(at, n));
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s OUT.mcap EXPECTED.json\n", argv[0]);
    return 2;
  }
  core::SteadyClock clock;
  auto store = std::make_unique<core::LatestStore>();
  record::RecorderOptions options;
  options.path = argv[1];
  options.chunk_period_ns = 100 * core::kNsPerMs;
  options.config_yaml = "boat:\n  name: sample\nmission:\n  name: hopping\n";
  options.build_version = "integration-test";
  record::Recorder rec(options, store.get(), clock);
  if (!rec.start()) {
    std::fprintf(stderr, "cannot start the recorder: %s\n", rec.stats().error.c_str());
    return 1;
  }
  auto logger = std::make_shared<spdlog::logger>("coxswain", rec.log_sink());
  logger->info("sample run starting");

  constexpr int kTicks = 150;
  std::vector<std::thread> threads;
  threads.emplace_back([&] {  // lidar: bytes and a scan per revolution
    auto scan = std::make_unique<msg::LidarScan>();
    const auto bytes = record::test::lidar_stream(1, 360);
    for (std::uint32_t r = 0; r < 15; ++r) {
      tee(rec, msg::DeviceId::kLidar, clock, bytes, 256);
      scan->clear();
      for (int i = 0; i < 360; ++i) {
        (void)scan->push({static_cast<float>(i) - 179.5F, 3.0F + static_cast<float>(i % 40) * 0.1F,
                          60, i * 278});
      }
      scan->revolution = r;
      scan->max_range_m = 12.0F;
      store->lidar.publish(*scan, clock.now_ns());
      std::this_thread::sleep_for(20ms);
    }
  });
  threads.emplace_back([&] {  // GNSS, IMU, Arduino, camera, health
    const auto gga = record::test::gnss_stream(1);
    const auto rpy = record::test::imu_stream(1);
    const auto tel = record::test::arduino_stream(1);
    for (int i = 0; i < 60; ++i) {
      const core::TimeNs now = clock.now_ns();
      tee(rec, msg::DeviceId::kImu, clock, rpy, 64);
      msg::ImuSample imu;
      imu.heading_deg = -170.0 + i;
      store->imu.publish(imu, now);
      if (i % 4 == 0) {
        tee(rec, msg::DeviceId::kGnss, clock, gga, 64);
        msg::GnssFix fix;
        fix.fix_ok = true;
        fix.fix_type = msg::FixType::k3D;
        fix.lat_deg = 35.1187 + i * 1e-6;
        fix.lon_deg = 129.0091;
        fix.h_acc_m = 0.02;
        fix.v_acc_m = 0.04;
        store->gnss.publish(fix, now);
        tee(rec, msg::DeviceId::kArduino, clock, tel, 64);
        store->arduino.publish(msg::ArduinoStatus{}, now);
        msg::CameraDetections cam;
        (void)cam.push(
            {msg::Colour::kRed, msg::Shape::kBuoy, -10.0F, 300, 240, 40, 60, 2000, 0.8F});
        store->camera.publish(cam, now);
        for (std::size_t d = 0; d < msg::kDeviceCount; ++d) {
          msg::DeviceHealth h;
          h.device = static_cast<msg::DeviceId>(d);
          h.state = msg::DeviceState::kRunning;
          h.set_detail("ok");
          store->health[d].publish(h, now);
        }
      }
      std::this_thread::sleep_for(5ms);
    }
  });
  threads.emplace_back([&] {  // the tick at 50 Hz
    auto snap = std::make_unique<core::Snapshot>();
    record::TickViz viz;
    viz.pose_valid = true;
    viz.target_valid = true;
    viz.danger_valid = true;
    viz.danger_start_deg = -20.0;
    viz.danger_end_deg = 25.0;
    viz.danger_range_m = 5.0;
    viz.obstacle_count = 2;
    viz.obstacles[0] = {4.0F, 1.0F, 0.4F};
    viz.obstacles[1] = {6.0F, -2.0F, 0.4F};
    for (int i = 0; i < kTicks; ++i) {
      store->snapshot(*snap);
      viz.north_m = 0.1 * i;
      viz.east_m = 0.05 * i;
      viz.heading_deg = 30.0;
      viz.target_bearing_deg = 10.0 - 0.1 * i;
      record::TickInput in;
      in.tick_index = static_cast<std::uint64_t>(i);
      in.now_ns = clock.now_ns();
      in.snapshot = snap.get();
      in.command.pulse_us = {1550, 1600};
      in.command.active = true;
      in.state_path = i < 50 ? "WAITING" : "ACTIVE:HOPPING:TRACKING";
      in.viz = &viz;
      (void)rec.record_tick(in);
      if (i == 75) {  // an operator's live retuning, first in force at the next tick
        const record::NamedValue values[] = {{"heading_pid.kp_per_deg", 0.03},
                                             {"avoidance.clearance_m", 0.4}};
        (void)rec.record_parameters(76, in.now_ns, values);
      }
      if (i % 25 == 0) logger->warn("tick {} state {}", i, in.state_path);
      std::this_thread::sleep_for(20ms);
    }
  });
  for (auto& t : threads) t.join();
  store->operator_input.publish(msg::OperatorInput{}, clock.now_ns());
  logger->info("sample run finished");
  // Let the writer sample the last store values before stopping (stop() samples once more too).
  std::this_thread::sleep_for(50ms);
  rec.stop();

  const record::RecorderStats st = rec.stats();
  if (st.failed) {
    std::fprintf(stderr, "recording failed: %s\n", st.error.c_str());
    return 1;
  }
  nlohmann::json expected;
  expected["written"] = nlohmann::json::object();
  expected["dropped"] = nlohmann::json::object();
  for (std::size_t i = 0; i < record::kRecordChannelCount; ++i) {
    const auto c = static_cast<record::RecordChannel>(i);
    expected["written"][std::string(record::channel_topic(c))] = st[c].written;
    expected["dropped"][std::string(record::channel_topic(c))] = st[c].dropped;
  }
  // Channels this run feeds; /raw/camera stays empty (a camera has no byte stream).
  expected["must_have"] = {"/raw/lidar", "/raw/imu", "/raw/gnss", "/raw/arduino", "/tick",
                           "/gnss",      "/imu",     "/lidar",    "/camera",      "/arduino",
                           "/operator",  "/health",  "/viz/fix",  "/viz/scan",    "/tf",
                           "/viz/scene", "/log",     "/params"};
  std::ofstream(argv[2]) << expected.dump(2) << "\n";

  // The run's own counters: every value published is recorded or counted as dropped.
  bool ok = true;
  auto check = [&](record::RecordChannel c, std::uint64_t produced) {
    if (st[c].written + st[c].dropped != produced) {
      std::fprintf(stderr, "%s: written %llu + dropped %llu != produced %llu\n",
                   std::string(record::channel_topic(c)).c_str(),
                   static_cast<unsigned long long>(st[c].written),
                   static_cast<unsigned long long>(st[c].dropped),
                   static_cast<unsigned long long>(produced));
      ok = false;
    }
  };
  check(record::RecordChannel::kLidar, store->lidar.sequence());
  check(record::RecordChannel::kImu, store->imu.sequence());
  check(record::RecordChannel::kGnss, store->gnss.sequence());
  check(record::RecordChannel::kArduino, store->arduino.sequence());
  check(record::RecordChannel::kCamera, store->camera.sequence());
  check(record::RecordChannel::kTick, kTicks);
  check(record::RecordChannel::kParams, 1);
  std::uint64_t health = 0;
  for (const auto& h : store->health) health += h.sequence();
  check(record::RecordChannel::kHealth, health);
  std::printf("wrote %s: %llu chunks, %llu bytes, %llu raw bytes, %llu dropped\n", argv[1],
              static_cast<unsigned long long>(st.chunks),
              static_cast<unsigned long long>(st.file_bytes),
              static_cast<unsigned long long>(st.raw_bytes),
              static_cast<unsigned long long>(st.total_dropped()));
  return ok ? 0 : 1;
}
