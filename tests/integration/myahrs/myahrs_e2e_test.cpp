// SPDX-License-Identifier: Apache-2.0
// MyahrsSession end to end: the real SerialTransport opens a pseudo-terminal on which
// sim::pty::EmulatorHost runs the myAHRS+ emulator core in real time. Covers the start-up
// exchange, samples with the true heading in the store, garbage, corrupted checksums, silence and
// recovery, unplug and reopen, and a run-time rate change.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <string>
#include <thread>

#include "coxswain/core/clock.hpp"
#include "coxswain/drivers/myahrs/session.hpp"
#include "coxswain/drivers/serial/serial_transport.hpp"
#include "sim/devices/myahrs/emulator.hpp"
#include "sim/pty/emulator_host.hpp"
#include "support/temp_dir.hpp"
#include "support/wait_for.hpp"

namespace coxswain::drivers::myahrs {
namespace {

using coxswain::test::TempDir;
using coxswain::test::wait_for;

using namespace std::chrono_literals;
namespace emu = sim::devices::myahrs;

constexpr double kHeadingDeg = -135.5;
constexpr double kMountYawDeg = 12.0;
constexpr double kDeclinationDeg = -9.0;

msg::ImuSample truth() {
  msg::ImuSample t;
  t.roll_deg = -4.0;
  t.pitch_deg = 1.5;
  t.yaw_magnetic_deg = emu::Emulator::sensor_yaw_for_heading(
      kHeadingDeg, HeadingConfig{kMountYawDeg, kDeclinationDeg});
  t.accel_g = {0.0, 0.01, -1.0};
  t.gyro_dps = {0.1, 0.2, -5.0};
  t.mag_ut = {20.0, -30.0, 40.0};
  t.temperature_c = 35.0;
  return t;
}

struct Rig {
  TempDir dir;
  emu::Emulator device;
  sim::pty::EmulatorHost host;
  core::LatestSlot<msg::ImuSample> samples;
  core::LatestSlot<msg::DeviceHealth> health;
  const core::SteadyClock clock;
  config::ImuDeviceConfig cfg;
  MyahrsSession session;
  serial::SerialTransport transport;

  static sim::pty::EmulatorHost::Options host_options(const std::filesystem::path& link) {
    sim::pty::EmulatorHost::Options o;
    o.link_path = link;
    return o;
  }
  static config::ImuDeviceConfig imu_config(const std::filesystem::path& link,
                                            config::ImuOutput output) {
    config::ImuDeviceConfig c;
    c.path = link.string();
    c.output = output;
    c.rate_hz = 50.0;
    c.declination_deg = kDeclinationDeg;
    c.timeout_ms = 300;
    return c;
  }
  static core::MountTransform mount() {
    core::MountTransform m;
    m.yaw_deg = kMountYawDeg;
    return m;
  }
  static SessionTiming timing() {
    SessionTiming t;
    t.reopen_after_ns = 30 * core::kNsPerSec;  // silence tests must see kStale, not a reopen
    return t;
  }

  explicit Rig(config::ImuOutput output = config::ImuOutput::kAscii)
      : host(device, host_options(dir / "ttyIMU")),
        cfg(imu_config(dir / "ttyIMU", output)),
        session(cfg, mount(), samples, timing()),
        transport(cfg, session, health, clock) {
    host.locked([&] { device.set_truth(truth()); });
    transport.start();
  }
  ~Rig() { transport.stop(); }

  [[nodiscard]] msg::DeviceHealth h() const { return health.read().value; }
};

void expect_truth(const msg::ImuSample& s) {
  EXPECT_NEAR(s.heading_deg, kHeadingDeg, 0.02);
  EXPECT_NEAR(s.roll_deg, -4.0, 0.02);
  EXPECT_NEAR(s.pitch_deg, 1.5, 0.02);
  EXPECT_TRUE(s.has_inertial);
  EXPECT_NEAR(s.gyro_dps[2], -5.0, 0.1);
}

TEST(MyahrsE2E, StartsUpAndPublishesTheTrueHeadingInBothForms) {
  for (const auto output : {config::ImuOutput::kAscii, config::ImuOutput::kBinary}) {
    Rig rig(output);
    const core::TimeNs t0 = rig.clock.now_ns();
    ASSERT_TRUE(wait_for([&] { return rig.h().detail_text() == "started"; }))
        << rig.h().detail_text();
    ASSERT_TRUE(wait_for([&] { return rig.samples.sequence() >= 50; }));
    const auto s = rig.samples.read();
    expect_truth(s.value);
    EXPECT_GE(s.stamp_ns, t0);
    EXPECT_EQ(rig.host.locked([&] { return rig.device.divider(); }), 2);
    EXPECT_EQ(rig.host.locked([&] { return rig.device.binary(); }),
              output == config::ImuOutput::kBinary);
    ASSERT_TRUE(wait_for([&] { return std::abs(rig.h().rate_hz - 50.0) < 5.0; }))
        << rig.h().rate_hz;
    EXPECT_EQ(rig.h().state, msg::DeviceState::kRunning);
    EXPECT_EQ(rig.h().checksum_errors, 0U);
  }
}

TEST(MyahrsE2E, GarbageAndCorruptedChecksumsAreCountedAndNoBadSampleIsPublished) {
  Rig rig;
  ASSERT_TRUE(wait_for([&] { return rig.samples.sequence() >= 10; }));
  emu::EmulatorFaults f;
  f.corrupt_checksum_probability = 0.2;
  f.garbage_probability = 0.2;
  rig.host.locked([&] { rig.device.set_faults(f); });
  rig.host.set_garbage(0.1, 16);
  const std::uint64_t start = rig.samples.sequence();
  std::uint64_t last_seq = 0;
  std::uint64_t checked = 0;
  ASSERT_TRUE(wait_for(
      [&] {
        const auto s = rig.samples.read();
        if (s.sequence != last_seq) {
          last_seq = s.sequence;
          ++checked;
          EXPECT_NEAR(s.value.heading_deg, kHeadingDeg, 0.02);
          EXPECT_NEAR(s.value.roll_deg, -4.0, 0.02);
        }
        return s.sequence >= start + 100 && rig.h().checksum_errors >= 5;
      },
      20s))
      << rig.h().checksum_errors;
  EXPECT_GE(checked, 20U);
  EXPECT_GT(rig.host.locked([&] { return rig.device.stats().corrupted_messages; }), 0U);
}

TEST(MyahrsE2E, SilenceGoesStaleAndRecovers) {
  Rig rig;
  ASSERT_TRUE(wait_for([&] { return rig.h().state == msg::DeviceState::kRunning; }));
  rig.host.set_silent(true);
  ASSERT_TRUE(wait_for([&] { return rig.h().state == msg::DeviceState::kStale; }));
  const std::uint64_t seq = rig.samples.sequence();
  rig.host.set_silent(false);
  ASSERT_TRUE(wait_for([&] { return rig.h().state == msg::DeviceState::kRunning; }));
  ASSERT_TRUE(wait_for([&] { return rig.samples.sequence() > seq + 10; }));
  expect_truth(rig.samples.read().value);
}

TEST(MyahrsE2E, UnplugReopenRestartsAndDataFlowsAgain) {
  Rig rig;
  ASSERT_TRUE(wait_for([&] { return rig.h().detail_text() == "started"; }));
  const auto ok_before = rig.host.locked([&] { return rig.device.stats().requests_ok; });
  rig.host.unplug();
  ASSERT_TRUE(wait_for([&] { return rig.h().state != msg::DeviceState::kRunning; }));
  const std::uint64_t seq = rig.samples.sequence();
  std::this_thread::sleep_for(200ms);
  rig.host.replug();
  ASSERT_TRUE(wait_for([&] { return rig.h().reopen_count >= 1; }));
  ASSERT_TRUE(wait_for([&] { return rig.samples.sequence() > seq + 10; }));
  ASSERT_TRUE(wait_for([&] {
    return rig.host.locked([&] { return rig.device.stats().requests_ok; }) >= ok_before + 5;
  }));
  ASSERT_TRUE(wait_for([&] { return rig.h().state == msg::DeviceState::kRunning; }));
  expect_truth(rig.samples.read().value);
}

TEST(MyahrsE2E, RateChangeAtRunTimeShowsInHealth) {
  Rig rig;
  ASSERT_TRUE(wait_for([&] { return std::abs(rig.h().rate_hz - 50.0) < 5.0; })) << rig.h().rate_hz;
  rig.host.locked([&] { rig.device.set_divider(10); });  // 10 Hz
  ASSERT_TRUE(wait_for([&] { return std::abs(rig.h().rate_hz - 10.0) < 1.0; })) << rig.h().rate_hz;
}

}  // namespace
}  // namespace coxswain::drivers::myahrs
