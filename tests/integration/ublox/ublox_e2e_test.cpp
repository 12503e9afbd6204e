// SPDX-License-Identifier: Apache-2.0
// UbloxSession end to end: the real SerialTransport opens a pseudo-terminal on which
// sim::pty::EmulatorHost runs the u-blox receiver emulator core in real time. Covers the
// configuration exchange, fixes in the store, garbage, corrupted checksums, silence and
// recovery, unplug and reopen, a run-time rate change, and RTCM forwarding from a file.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "coxswain/core/clock.hpp"
#include "coxswain/drivers/serial/serial_transport.hpp"
#include "coxswain/drivers/ublox/codec.hpp"
#include "coxswain/drivers/ublox/rtcm_source.hpp"
#include "coxswain/drivers/ublox/session.hpp"
#include "sim/devices/ublox/emulator.hpp"
#include "sim/pty/emulator_host.hpp"
#include "support/temp_dir.hpp"
#include "support/wait_for.hpp"

namespace coxswain::drivers::ublox {
namespace {

using coxswain::test::TempDir;
using coxswain::test::wait_for;

using namespace std::chrono_literals;
namespace emu = sim::devices::ublox;

msg::GnssFix truth_fix() {
  msg::GnssFix t;
  t.fix_type = msg::FixType::k3D;
  t.fix_ok = true;
  t.diff_soln = true;
  t.rtk = msg::RtkSolution::kFixed;
  t.lat_deg = 37.5665123;
  t.lon_deg = 126.9780456;
  t.height_msl_m = 21.5;
  t.h_acc_m = 0.014;
  t.v_acc_m = 0.02;
  t.satellites = 28;
  t.vel_north_mps = 0.8;
  t.vel_east_mps = 1.1;
  t.ground_speed_mps = std::hypot(0.8, 1.1);
  t.course_deg = 53.97;
  t.utc_ns = (unix_days_from_civil(2026, 11, 23) * 86400 + 16 * 3600) * core::kNsPerSec;
  return t;
}

/// The whole rig: emulator on a pty, transport + session on the other side.
struct Rig {
  TempDir dir;
  emu::Emulator device;
  sim::pty::EmulatorHost host;
  core::LatestSlot<msg::GnssFix> fixes;
  core::LatestSlot<msg::DeviceHealth> health;
  const core::SteadyClock clock;
  config::GnssDeviceConfig cfg;
  UbloxSession session;
  serial::SerialTransport transport;

  static emu::EmulatorConfig emu_config() {
    emu::EmulatorConfig c;
    c.model = emu::Model::kF9;
    return c;
  }
  static sim::pty::EmulatorHost::Options host_options(const std::filesystem::path& link) {
    sim::pty::EmulatorHost::Options o;
    o.link_path = link;
    return o;
  }
  static config::GnssDeviceConfig gnss_config(const std::filesystem::path& link) {
    config::GnssDeviceConfig c;
    c.path = link.string();
    c.receiver = config::GnssReceiver::kF9;
    c.port = config::GnssPort::kUsb;
    c.rate_hz = 10.0;
    c.timeout_ms = 400;
    return c;
  }
  static SessionTiming timing() {
    SessionTiming t;
    t.reopen_after_ns = 30 * core::kNsPerSec;  // silence tests must see kStale, not a reopen
    return t;
  }

  explicit Rig(RtcmQueue* rtcm = nullptr)
      : device(emu_config()),
        host(device, host_options(dir / "ttyGPS")),
        cfg(gnss_config(dir / "ttyGPS")),
        session(cfg, fixes, timing()),
        transport(cfg, session, health, clock) {
    host.locked([&] { device.set_truth(truth_fix()); });
    session.set_rtcm_queue(rtcm);  // before the device thread starts
    transport.start();
  }
  ~Rig() { transport.stop(); }

  [[nodiscard]] msg::DeviceHealth h() const { return health.read().value; }
};

void expect_truth(const msg::GnssFix& f) {
  const msg::GnssFix t = truth_fix();
  EXPECT_EQ(f.source, msg::GnssSource::kUbxNavPvt);
  EXPECT_EQ(f.fix_type, t.fix_type);
  EXPECT_TRUE(f.fix_ok);
  EXPECT_EQ(f.rtk, t.rtk);
  EXPECT_NEAR(f.lat_deg, t.lat_deg, 1e-7);
  EXPECT_NEAR(f.lon_deg, t.lon_deg, 1e-7);
  EXPECT_NEAR(f.height_msl_m, t.height_msl_m, 1e-3);
  EXPECT_NEAR(f.h_acc_m, t.h_acc_m, 1e-3);
  EXPECT_EQ(f.satellites, t.satellites);
  EXPECT_NEAR(f.ground_speed_mps, t.ground_speed_mps, 1e-3);
  EXPECT_NEAR(f.course_deg, t.course_deg, 1e-4);
  EXPECT_EQ(f.utc_ns, t.utc_ns);
}

TEST(UbloxE2E, ConfiguresWithAcksAndPublishesTheTruth) {
  Rig rig;
  const core::TimeNs t0 = rig.clock.now_ns();
  ASSERT_TRUE(wait_for([&] { return rig.h().detail_text() == "configured"; }))
      << rig.h().detail_text();
  ASSERT_TRUE(wait_for([&] { return rig.fixes.sequence() >= 20; }));
  const auto s = rig.fixes.read();
  expect_truth(s.value);
  EXPECT_GE(s.stamp_ns, t0);
  EXPECT_LE(s.stamp_ns, rig.clock.now_ns());
  const auto st = rig.host.locked([&] { return rig.device.stats(); });
  EXPECT_EQ(st.acks, 4U);
  EXPECT_EQ(st.naks, 0U);
  EXPECT_EQ(rig.host.locked([&] { return rig.device.meas_period_ms(); }), 100);
  ASSERT_TRUE(wait_for([&] { return std::abs(rig.h().rate_hz - 10.0) < 1.0; })) << rig.h().rate_hz;
  EXPECT_EQ(rig.h().state, msg::DeviceState::kRunning);
  EXPECT_EQ(rig.h().checksum_errors, 0U);
}

TEST(UbloxE2E, GarbageAndCorruptedChecksumsAreCountedAndNoBadFixIsPublished) {
  Rig rig;
  ASSERT_TRUE(wait_for([&] { return rig.fixes.sequence() >= 5; }));
  emu::EmulatorFaults f;
  f.corrupt_checksum_probability = 0.3;
  f.garbage_probability = 0.5;
  rig.host.locked([&] { rig.device.set_faults(f); });
  rig.host.set_garbage(0.2, 16);
  // Sample the store while faults run: every fix read must still be the truth.
  const std::uint64_t start = rig.fixes.sequence();
  std::uint64_t checked = 0;
  std::uint64_t last_seq = 0;
  ASSERT_TRUE(wait_for(
      [&] {
        const auto s = rig.fixes.read();
        if (s.sequence != last_seq) {
          last_seq = s.sequence;
          ++checked;
          EXPECT_NEAR(s.value.lat_deg, truth_fix().lat_deg, 1e-7);
          EXPECT_NEAR(s.value.lon_deg, truth_fix().lon_deg, 1e-7);
          EXPECT_EQ(s.value.satellites, truth_fix().satellites);
        }
        return s.sequence >= start + 20 && rig.h().checksum_errors >= 3;
      },
      20s))
      << rig.h().checksum_errors;
  EXPECT_GE(checked, 10U);
  const auto st = rig.host.locked([&] { return rig.device.stats(); });
  EXPECT_GT(st.corrupted_messages, 0U);
  EXPECT_GT(rig.h().framing_errors + rig.h().checksum_errors, 3U);
  expect_truth(rig.fixes.read().value);
}

TEST(UbloxE2E, SilenceGoesStaleAndRecovers) {
  Rig rig;
  ASSERT_TRUE(wait_for([&] { return rig.h().state == msg::DeviceState::kRunning; }));
  rig.host.set_silent(true);
  ASSERT_TRUE(wait_for([&] { return rig.h().state == msg::DeviceState::kStale; }));
  const std::uint64_t seq = rig.fixes.sequence();
  rig.host.set_silent(false);
  ASSERT_TRUE(wait_for([&] { return rig.h().state == msg::DeviceState::kRunning; }));
  ASSERT_TRUE(wait_for([&] { return rig.fixes.sequence() > seq + 5; }));
  expect_truth(rig.fixes.read().value);
}

TEST(UbloxE2E, UnplugReopenReconfiguresAndDataFlowsAgain) {
  Rig rig;
  ASSERT_TRUE(wait_for([&] { return rig.h().detail_text() == "configured"; }));
  ASSERT_TRUE(wait_for([&] { return rig.fixes.sequence() >= 5; }));
  rig.host.unplug();
  ASSERT_TRUE(wait_for([&] { return rig.h().state != msg::DeviceState::kRunning; }));
  const std::uint64_t seq = rig.fixes.sequence();
  std::this_thread::sleep_for(200ms);
  rig.host.replug();
  ASSERT_TRUE(wait_for([&] { return rig.h().reopen_count >= 1; }));
  ASSERT_TRUE(wait_for([&] { return rig.fixes.sequence() > seq + 5; }));
  // The configuration ran again on the fresh port.
  ASSERT_TRUE(
      wait_for([&] { return rig.host.locked([&] { return rig.device.stats().acks; }) >= 8; }));
  ASSERT_TRUE(wait_for([&] { return rig.h().state == msg::DeviceState::kRunning; }));
  expect_truth(rig.fixes.read().value);
}

TEST(UbloxE2E, RateChangeAtRunTimeShowsInHealth) {
  Rig rig;
  ASSERT_TRUE(wait_for([&] { return std::abs(rig.h().rate_hz - 10.0) < 1.0; })) << rig.h().rate_hz;
  rig.host.locked([&] { rig.device.set_rate_hz(4.0); });
  ASSERT_TRUE(wait_for([&] { return std::abs(rig.h().rate_hz - 4.0) < 0.4; })) << rig.h().rate_hz;
}

std::vector<std::uint8_t> rtcm_frame(std::uint16_t type, std::size_t payload_len) {
  std::vector<std::uint8_t> f{kRtcm3Preamble, static_cast<std::uint8_t>(payload_len >> 8),
                              static_cast<std::uint8_t>(payload_len & 0xFF)};
  for (std::size_t i = 0; i < payload_len; ++i) f.push_back(static_cast<std::uint8_t>(i * 31));
  f[3] = static_cast<std::uint8_t>(type >> 4);
  f[4] = static_cast<std::uint8_t>(((type & 0x0F) << 4) | (f[4] & 0x0F));
  const std::uint32_t crc = crc24q(f);
  f.push_back(static_cast<std::uint8_t>(crc >> 16));
  f.push_back(static_cast<std::uint8_t>(crc >> 8));
  f.push_back(static_cast<std::uint8_t>(crc));
  return f;
}

TEST(UbloxE2E, RtcmFromAFileReachesTheReceiver) {
  TempDir dir;
  const auto path = dir / "corrections.rtcm3";
  constexpr int kFrames = 30;
  {
    std::ofstream out(path, std::ios::binary);
    for (int i = 0; i < kFrames; ++i) {
      const auto f = rtcm_frame(i % 2 == 0 ? 1077 : 1005, static_cast<std::size_t>(20 + 10 * i));
      out.write(reinterpret_cast<const char*>(f.data()), static_cast<std::streamsize>(f.size()));
    }
  }
  RtcmQueue queue;
  RtcmSource source(path.string(), queue);
  Rig rig(&queue);
  source.start();
  ASSERT_TRUE(wait_for(
      [&] { return rig.host.locked([&] { return rig.device.stats().rtcm_frames; }) >= kFrames; }));
  source.stop();
  EXPECT_EQ(rig.host.locked([&] { return rig.device.stats().rtcm_frames; }),
            static_cast<std::uint64_t>(kFrames));
  EXPECT_EQ(source.stats().frames_queued, static_cast<std::uint64_t>(kFrames));
  ASSERT_TRUE(wait_for([&] { return rig.fixes.sequence() >= 5; }));
}

}  // namespace
}  // namespace coxswain::drivers::ublox
