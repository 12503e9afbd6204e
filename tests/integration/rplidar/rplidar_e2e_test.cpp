// SPDX-License-Identifier: Apache-2.0
// RplidarSession end to end: the real session under the real SerialTransport, talking to the
// RPLIDAR emulator run by sim::pty::EmulatorHost over a pseudo-terminal in real time. Start-up,
// revolutions in the store, garbage, corrupted capsules (counted, never published), silence ->
// stale -> RESET restart -> recovery, unplug -> reopen -> data again, rate change.
// A pty has no modem lines: the A1's set_dtr fails there and the transport tolerates it (the
// emulator's DTR stays de-asserted, so its motor spins).
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "coxswain/core/angles.hpp"
#include "coxswain/drivers/rplidar/session.hpp"
#include "coxswain/drivers/serial/serial_transport.hpp"
#include "sim/devices/rplidar/emulator.hpp"
#include "sim/pty/emulator_host.hpp"
#include "support/temp_dir.hpp"
#include "support/wait_for.hpp"

namespace coxswain::drivers::rplidar {
namespace {

using coxswain::test::TempDir;
using coxswain::test::wait_for;

using namespace std::chrono_literals;
namespace emu = sim::devices::rplidar;

/// Sensor-frame truth: 4 m all round, a box at 1.5 m on lidar angles 40..50.
std::vector<float> truth_ranges() {
  std::vector<float> r(360, 4.0F);
  for (int i = 40; i <= 50; ++i) r[static_cast<std::size_t>(i)] = 1.5F;
  return r;
}

/// Every point must be the truth seen through a mount turned 180 deg (lidar facing astern).
::testing::AssertionResult matches_truth(const msg::LidarScan& scan) {
  if (scan.point_count < 100) {
    return ::testing::AssertionFailure() << "only " << scan.point_count << " points";
  }
  int box = 0;
  for (std::uint32_t i = 0; i < scan.point_count; ++i) {
    const msg::LidarPoint& p = scan.points[i];
    const double lidar_deg = core::wrap_deg_360(static_cast<double>(p.bearing_deg) - 180.0);
    const bool in_box = lidar_deg > 41.0 && lidar_deg < 49.0;
    const bool in_wall = lidar_deg < 38.0 || (lidar_deg > 52.0 && lidar_deg < 359.0);
    const float want = in_box ? 1.5F : 4.0F;
    if ((in_box || in_wall) && std::fabs(p.range_m - want) > 0.002F) {
      return ::testing::AssertionFailure() << "point " << i << " at lidar " << lidar_deg
                                           << " deg: " << p.range_m << " m, want " << want;
    }
    box += in_box ? 1 : 0;
  }
  for (std::uint32_t i = 0; i < scan.point_count; ++i) {
    const float prev = i == 0 ? scan.points[scan.point_count - 1].bearing_deg - 360.0F
                              : scan.points[i - 1].bearing_deg;
    if (scan.points[i].bearing_deg - prev > 2.0F) {
      return ::testing::AssertionFailure() << "gap after bearing " << prev;
    }
  }
  if (box < 3) {
    auto f = ::testing::AssertionFailure();
    f << "box missing in " << scan.point_count << " points:";
    for (std::uint32_t i = 0; i < scan.point_count; i += 8) {
      f << " " << core::wrap_deg_360(static_cast<double>(scan.points[i].bearing_deg) - 180.0);
    }
    return f;
  }
  return ::testing::AssertionSuccess();
}

/// The emulator on a pty, the session under a real transport, and the store slots.
struct Rig {
  explicit Rig(emu::Model model, std::uint32_t timeout_ms = 500)
      : emulator(make_emulator(model)),
        host(emulator, host_options(dir / "ttyLiDAR")),
        config(make_config(dir / "ttyLiDAR", timeout_ms)),
        session(config, core::MountTransform{180.0, -0.9, 0.0}, scans),
        transport(config, session, health, clock) {}
  ~Rig() {
    transport.stop();
    host.stop();
  }

  static emu::EmulatorConfig make_emulator(emu::Model model) {
    emu::EmulatorConfig c;
    c.model = model;
    return c;
  }
  static sim::pty::EmulatorHost::Options host_options(const std::filesystem::path& link) {
    sim::pty::EmulatorHost::Options o;
    o.link_path = link;
    return o;
  }
  static config::LidarDeviceConfig make_config(const std::filesystem::path& path,
                                               std::uint32_t timeout_ms) {
    config::LidarDeviceConfig c;
    c.path = path.string();
    c.baud = 115200;
    c.timeout_ms = timeout_ms;
    return c;
  }
  void start() {
    host.locked([&] { emulator.set_ranges(truth_ranges()); });
    transport.start();
  }
  msg::DeviceHealth h() const { return health.read().value; }
  /// Waits for `n` more published scans, checking each one seen against the truth.
  bool wait_scans(std::uint64_t n, std::chrono::milliseconds timeout = 15s) {
    const std::uint64_t target = scans.sequence() + n;
    std::uint64_t seen = scans.sequence();
    return wait_for(
        [&] {
          const std::uint64_t now = scans.sequence();
          if (now != seen) {
            seen = now;
            const auto s = scans.read();
            EXPECT_TRUE(matches_truth(s.value)) << "revolution " << s.value.revolution;
          }
          return now >= target;
        },
        timeout);
  }

  TempDir dir;
  emu::Emulator emulator;
  sim::pty::EmulatorHost host;
  config::LidarDeviceConfig config;
  core::LatestSlot<msg::LidarScan> scans;
  core::LatestSlot<msg::DeviceHealth> health;
  const core::SteadyClock clock;
  RplidarSession session;
  serial::SerialTransport transport;
};

TEST(RplidarEndToEnd, StartsUpAndPublishesRevolutionsInTheStore) {
  Rig rig(emu::Model::kA1);
  const core::TimeNs t0 = rig.clock.now_ns();
  rig.start();
  ASSERT_TRUE(rig.wait_scans(5)) << rig.h().detail_text();
  const auto s = rig.scans.read();
  EXPECT_GE(s.stamp_ns, t0);
  EXPECT_LE(s.stamp_ns, rig.clock.now_ns());
  EXPECT_NEAR(static_cast<double>(s.value.point_count), 400.0, 12.0);  // express, 250 us
  ASSERT_TRUE(wait_for([&] { return rig.h().rate_hz > 0.0; }));
  const msg::DeviceHealth h = rig.h();
  EXPECT_EQ(h.state, msg::DeviceState::kRunning) << h.detail_text();
  EXPECT_NEAR(h.rate_hz, 10.0, 1.5);
  EXPECT_EQ(h.checksum_errors, 0U);
  EXPECT_NE(h.detail_text().find("A1M8"), std::string_view::npos) << h.detail_text();
  EXPECT_EQ(h.reopen_count, 0U);
}

TEST(RplidarEndToEnd, GarbageAndCorruptedCapsulesAreCountedAndNeverPublished) {
  Rig rig(emu::Model::kA3);
  rig.host.set_garbage(0.05, 16);
  emu::EmulatorFaults f;
  f.corrupt_probability = 0.02;
  f.seed = 5;
  rig.host.locked([&] { rig.emulator.set_faults(f); });
  rig.start();
  ASSERT_TRUE(rig.wait_scans(10, 25s)) << rig.h().detail_text();
  ASSERT_TRUE(wait_for([&] {
    const msg::DeviceHealth h = rig.h();
    return h.checksum_errors > 0 && h.framing_errors > 0 && h.dropped_frames > 0;
  })) << rig.h().detail_text();
  EXPECT_GT(rig.host.counters().garbage_bursts, 0U);
}

TEST(RplidarEndToEnd, SilenceGoesStaleThenResetRestartsThenDataReturns) {
  Rig rig(emu::Model::kS2, 600);
  rig.start();
  ASSERT_TRUE(rig.wait_scans(3)) << rig.h().detail_text();
  const std::uint64_t resets_before = rig.host.locked([&] { return rig.emulator.stats().resets; });
  rig.host.set_silent(true);
  ASSERT_TRUE(wait_for([&] { return rig.h().state == msg::DeviceState::kStale; }))
      << rig.h().detail_text();
  ASSERT_TRUE(wait_for([&] {
    return rig.host.locked([&] { return rig.emulator.stats().resets; }) > resets_before;
  })) << rig.h().detail_text();
  rig.host.set_silent(false);
  ASSERT_TRUE(rig.wait_scans(3)) << rig.h().detail_text();
  ASSERT_TRUE(wait_for([&] { return rig.h().state == msg::DeviceState::kRunning; }));
  EXPECT_EQ(rig.transport.counters().reopen_count, 0U);
}

TEST(RplidarEndToEnd, UnplugThenReplugReopensAndDataFlowsAgain) {
  Rig rig(emu::Model::kC1);
  rig.start();
  ASSERT_TRUE(rig.wait_scans(3)) << rig.h().detail_text();
  rig.host.unplug();
  ASSERT_TRUE(wait_for([&] { return rig.h().state == msg::DeviceState::kAbsent; }))
      << rig.h().detail_text();
  std::this_thread::sleep_for(300ms);
  rig.host.replug();
  ASSERT_TRUE(rig.wait_scans(3)) << rig.h().detail_text();
  EXPECT_GE(rig.transport.counters().reopen_count, 1U);
  ASSERT_TRUE(wait_for([&] { return rig.h().state == msg::DeviceState::kRunning; }));
}

TEST(RplidarEndToEnd, RateChangeIsFollowed) {
  Rig rig(emu::Model::kA1);
  rig.start();
  ASSERT_TRUE(rig.wait_scans(5)) << rig.h().detail_text();
  rig.host.locked([&] { rig.emulator.set_revolution_hz(5.0); });
  ASSERT_TRUE(wait_for([&] {
    const msg::DeviceHealth h = rig.h();
    return std::fabs(h.rate_hz - 5.0) < 0.5 && rig.scans.read().value.point_count > 780;
  })) << rig.h().rate_hz;
  EXPECT_TRUE(matches_truth(rig.scans.read().value));
}

}  // namespace
}  // namespace coxswain::drivers::rplidar
