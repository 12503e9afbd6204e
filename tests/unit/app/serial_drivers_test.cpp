// SPDX-License-Identifier: Apache-2.0
// The daemon's serial wiring: SerialDrivers starts a transport only for enabled devices with a
// session, DeviceProbe leaves their health alone, and capture mode's RawCaptureSink writes what
// each device sent to DIR/<device>.raw without ever blocking, counting what it had to drop.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "coxswain/app/decode_capture.hpp"
#include "coxswain/app/device_probe.hpp"
#include "coxswain/app/device_sessions.hpp"
#include "coxswain/app/health_reporter.hpp"
#include "coxswain/app/raw_capture_sink.hpp"
#include "coxswain/app/serial_drivers.hpp"
#include "coxswain/drivers/myahrs/codec.hpp"
#include "integration/serial/line_protocol.hpp"
#include "sim/pty/emulator_host.hpp"
#include "support/run_command.hpp"
#include "support/temp_dir.hpp"
#include "support/wait_for.hpp"

namespace coxswain::app {
namespace {

using coxswain::test::slurp;

using coxswain::test::TempDir;
using coxswain::test::wait_for;

using namespace std::chrono_literals;
namespace fs = std::filesystem;

std::span<const std::uint8_t> as_bytes(const std::string& s) {
  return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

// A myAHRS+ in ASCII RPY mode at 100 Hz, written for this test: checksummed `$RPY` sentences, so
// the capture it leaves can be run through `coxswain decode --device myahrs`.
class RpyDevice final : public sim::devices::DeviceEmulator {
 public:
  void receive(std::span<const std::uint8_t> /*host_bytes*/, core::TimeNs /*now_ns*/) override {}
  std::span<const std::uint8_t> poll(core::TimeNs now_ns) override {
    out_.clear();
    if (next_ns_ == core::kNeverNs) next_ns_ = now_ns;
    while (now_ns >= next_ns_) {
      const std::string body = "$RPY," + std::to_string(seq_ % 100) + ",1.50,-2.25," +
                               std::to_string(seq_ % 360) + ".00";
      char tail[8];
      std::snprintf(tail, sizeof tail, "*%02X\r\n",
                    static_cast<unsigned>(drivers::myahrs::xor_checksum(std::string_view(body))));
      out_ += body + tail;
      ++seq_;
      next_ns_ += 10 * core::kNsPerMs;
    }
    return as_bytes(out_);
  }

 private:
  std::string out_;
  core::TimeNs next_ns_ = core::kNeverNs;
  unsigned seq_ = 0;
};

config::DevicesConfig devices_with(const fs::path& dir) {
  config::DevicesConfig d;
  d.lidar.path = (dir / "ttyLiDAR").string();
  d.imu.path = (dir / "ttyIMU").string();
  d.gnss.path = (dir / "ttyGPS").string();
  d.arduino.path = (dir / "ttyARDUINO").string();
  d.arduino.enabled = false;
  d.camera.source = (dir / "videoCAM").string();
  return d;
}

TEST(DeviceSessions, SerialConfigsAndNoDriverYet) {
  const config::Configuration config;
  EXPECT_EQ(serial_device_config(msg::DeviceId::kGnss, config.devices), &config.devices.gnss);
  EXPECT_EQ(serial_device_config(msg::DeviceId::kLidar, config.devices), &config.devices.lidar);
  EXPECT_EQ(serial_device_config(msg::DeviceId::kCamera, config.devices), nullptr);
  auto store = std::make_unique<core::LatestStore>();
  for (const msg::DeviceId id : kSerialDevices) {
    const auto session = make_device_session(id, config, *store);
    if (session) {
      EXPECT_EQ(session->device(), id);
    }
  }
}

TEST(SerialDrivers, DrivesEnabledDevicesWithASessionAndCapturesTheirBytes) {
  TempDir dir;
  RpyDevice imu_device;
  test::LineDevice gnss_device;
  sim::pty::EmulatorHost::Options imu_opts;
  imu_opts.link_path = dir.path() / "ttyIMU";
  sim::pty::EmulatorHost imu_host(imu_device, imu_opts);
  sim::pty::EmulatorHost::Options gnss_opts;
  gnss_opts.link_path = dir.path() / "ttyGPS";
  sim::pty::EmulatorHost gnss_host(gnss_device, gnss_opts);

  const config::DevicesConfig devices = devices_with(dir.path());
  auto store = std::make_unique<core::LatestStore>();
  const core::SteadyClock clock;
  RawCaptureSink capture(dir.path() / "capture");
  std::vector<test::LineSession*> sessions;
  std::vector<msg::DeviceId> asked;
  SerialDrivers drivers(
      devices,
      [&](msg::DeviceId id) -> std::unique_ptr<drivers::DeviceSession> {
        asked.push_back(id);
        if (id != msg::DeviceId::kImu && id != msg::DeviceId::kGnss) return nullptr;
        test::LineSessionOptions o;
        o.device = id;
        auto s = std::make_unique<test::LineSession>(o);
        sessions.push_back(s.get());
        return s;
      },
      *store, clock, &capture);
  // Asked for every enabled serial device (the Arduino is disabled), never for the camera.
  EXPECT_EQ(asked, (std::vector<msg::DeviceId>{msg::DeviceId::kLidar, msg::DeviceId::kImu,
                                               msg::DeviceId::kGnss}));
  EXPECT_TRUE(drivers.drives(msg::DeviceId::kImu));
  EXPECT_TRUE(drivers.drives(msg::DeviceId::kGnss));
  EXPECT_FALSE(drivers.drives(msg::DeviceId::kLidar));
  EXPECT_FALSE(drivers.drives(msg::DeviceId::kArduino));
  EXPECT_FALSE(drivers.drives(msg::DeviceId::kCamera));

  // The probe owns the others' health only.
  DeviceProbe probe(devices, *store, drivers.driven());
  drivers.start();
  ASSERT_TRUE(wait_for([&] { return sessions[1]->frame_count() >= 20; }));
  ASSERT_TRUE(
      wait_for([&] { return drivers.counters(msg::DeviceId::kImu).bytes_received > 2000; }));
  ASSERT_TRUE(wait_for([&] {
    return store->health_of(msg::DeviceId::kGnss).read().value.state == msg::DeviceState::kRunning;
  }));
  const std::uint64_t gnss_health_seq = store->health_of(msg::DeviceId::kGnss).sequence();
  probe.probe_once(clock.now_ns());
  EXPECT_EQ(store->health_of(msg::DeviceId::kLidar).read().value.state, msg::DeviceState::kAbsent);
  EXPECT_EQ(store->health_of(msg::DeviceId::kArduino).read().value.state,
            msg::DeviceState::kDisabled);
  // The probe did not write the GNSS slot (its transport may have, meanwhile: still running).
  EXPECT_NE(store->health_of(msg::DeviceId::kGnss).read().value.state, msg::DeviceState::kPresent);
  EXPECT_GE(store->health_of(msg::DeviceId::kGnss).sequence(), gnss_health_seq);

  drivers.stop();
  capture.stop();
  // Every byte each transport read is in its capture file, unchanged.
  const std::string imu_raw =
      slurp(RawCaptureSink::file_for(dir.path() / "capture", msg::DeviceId::kImu));
  const std::string gnss_raw =
      slurp(RawCaptureSink::file_for(dir.path() / "capture", msg::DeviceId::kGnss));
  EXPECT_EQ(imu_raw.size(), drivers.counters(msg::DeviceId::kImu).bytes_received);
  EXPECT_EQ(gnss_raw.size(), drivers.counters(msg::DeviceId::kGnss).bytes_received);
  EXPECT_EQ(capture.counters(msg::DeviceId::kImu).bytes_dropped, 0U);
  EXPECT_EQ(capture.counters(msg::DeviceId::kImu).bytes_written, imu_raw.size());
  EXPECT_NE(gnss_raw.find("$T,"), std::string::npos);
  EXPECT_FALSE(fs::exists(RawCaptureSink::file_for(dir.path() / "capture", msg::DeviceId::kLidar)));

  // ... and `coxswain decode` reads the IMU's capture back into samples, with no errors beyond a
  // sentence cut by the port's opening.
  CaptureDecoder decoder(CaptureFormat::kMyahrs);
  std::vector<nlohmann::json> samples;
  decoder.feed(as_bytes(imu_raw), [&](const nlohmann::json& j) { samples.push_back(j); });
  const nlohmann::json summary = decoder.summary();
  EXPECT_GE(samples.size(), 20U);
  EXPECT_EQ(summary["codec"]["ascii_checksum_errors"], 0);
  EXPECT_EQ(samples.front()["type"], "sample");
  EXPECT_DOUBLE_EQ(samples.front()["roll_deg"].get<double>(), 1.5);
}

// A driven device that is absent is reported once, however often its transport retries.
TEST(SerialDrivers, AnAbsentDeviceIsReportedOnce) {
  TempDir dir;
  config::DevicesConfig devices = devices_with(dir.path());
  devices.lidar.enabled = false;
  devices.imu.enabled = false;
  auto store = std::make_unique<core::LatestStore>();
  auto snapshot = std::make_unique<core::Snapshot>();
  const core::SteadyClock clock;
  drivers::serial::TransportOptions fast;
  fast.backoff_initial_ns = 5 * core::kNsPerMs;  // many retries in a short test
  fast.backoff_max_ns = 10 * core::kNsPerMs;
  SerialDrivers drivers(
      devices,
      [](msg::DeviceId id) -> std::unique_ptr<drivers::DeviceSession> {
        test::LineSessionOptions o;
        o.device = id;
        return std::make_unique<test::LineSession>(o);
      },
      *store, clock, nullptr, fast);
  drivers.start();
  HealthReporter reporter;
  int reports = 0;
  const auto end = std::chrono::steady_clock::now() + 500ms;
  while (std::chrono::steady_clock::now() < end) {  // a 1 kHz "tick" watching the health
    store->snapshot(*snapshot);
    if (snapshot->health[static_cast<std::size_t>(msg::DeviceId::kGnss)].valid()) {
      reports += reporter.report_changes(*snapshot);
    }
    std::this_thread::sleep_for(1ms);
  }
  const auto failures = drivers.counters(msg::DeviceId::kGnss).open_failures;
  drivers.stop();
  EXPECT_GE(failures, 10U);
  const msg::DeviceHealth h = store->health_of(msg::DeviceId::kGnss).read().value;
  EXPECT_EQ(h.state, msg::DeviceState::kAbsent);
  EXPECT_NE(h.detail_text().find("ttyGPS: No such file or directory"), std::string_view::npos)
      << h.detail_text();
  EXPECT_EQ(reports, 1);  // "gnss: absent"; the slots nobody wrote are not reported
  store->snapshot(*snapshot);
  EXPECT_EQ(reporter.report_changes(*snapshot), 0);
}

TEST(RawCaptureSink, ConcurrentProducersLoseNothingWhenTheRingKeepsUp) {
  TempDir dir;
  RawCaptureSink sink(dir.path(), 1 << 16, core::kNsPerMs);
  const auto produce = [&](msg::DeviceId id, char tag) {
    std::string expected;
    for (int i = 0; i < 2000; ++i) {
      const std::string chunk = std::string(1, tag) + std::to_string(i) + ";";
      sink.on_raw(id, drivers::RawDirection::kFromDevice, 0, as_bytes(chunk));
      sink.on_raw(id, drivers::RawDirection::kToDevice, 0, as_bytes("not captured"));
      expected += chunk;
      if (i % 100 == 0) std::this_thread::sleep_for(1ms);  // let the writer keep up
    }
    return expected;
  };
  std::string lidar_expected;
  std::string gnss_expected;
  std::thread a([&] { lidar_expected = produce(msg::DeviceId::kLidar, 'L'); });
  std::thread b([&] { gnss_expected = produce(msg::DeviceId::kGnss, 'G'); });
  a.join();
  b.join();
  sink.stop();
  const auto lidar = sink.counters(msg::DeviceId::kLidar);
  const auto gnss = sink.counters(msg::DeviceId::kGnss);
  // Whatever was dropped is counted; with a 64 KiB ring for ~13 KiB nothing should be.
  EXPECT_EQ(lidar.bytes_dropped, 0U);
  EXPECT_EQ(gnss.bytes_dropped, 0U);
  EXPECT_EQ(slurp(RawCaptureSink::file_for(dir.path(), msg::DeviceId::kLidar)), lidar_expected);
  EXPECT_EQ(slurp(RawCaptureSink::file_for(dir.path(), msg::DeviceId::kGnss)), gnss_expected);
  EXPECT_EQ(lidar.bytes_written, lidar_expected.size());
}

TEST(RawCaptureSink, AFullRingDropsWholeChunksAndCountsThem) {
  TempDir dir;
  // A writer that never runs during the burst (1 h period): the 100-byte ring fills up.
  RawCaptureSink sink(dir.path(), 100, 3600 * core::kNsPerSec);
  const std::string chunk(30, 'x');
  for (int i = 0; i < 5; ++i) {
    sink.on_raw(msg::DeviceId::kImu, drivers::RawDirection::kFromDevice, 0, as_bytes(chunk));
  }
  sink.stop();
  const auto c = sink.counters(msg::DeviceId::kImu);
  EXPECT_EQ(c.bytes_written, 90U);  // three chunks fit
  EXPECT_EQ(c.bytes_dropped, 60U);
  EXPECT_EQ(slurp(RawCaptureSink::file_for(dir.path(), msg::DeviceId::kImu)), std::string(90, 'x'));
  // After stop() nothing is accepted, and that is counted too.
  sink.on_raw(msg::DeviceId::kImu, drivers::RawDirection::kFromDevice, 0, as_bytes(chunk));
  EXPECT_EQ(sink.counters(msg::DeviceId::kImu).bytes_dropped, 90U);
}

TEST(RawCaptureSink, UnwritableDirectoryIsAnError) {
  TempDir dir;
  const fs::path file = dir.path() / "plain_file";
  std::ofstream(file) << "x";
  EXPECT_THROW(RawCaptureSink(file / "sub"), fs::filesystem_error);
}

}  // namespace
}  // namespace coxswain::app
