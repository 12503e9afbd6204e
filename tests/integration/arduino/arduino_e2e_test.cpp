// SPDX-License-Identifier: Apache-2.0
// ArduinoSession end to end: the real session under the real SerialTransport, talking to the
// Arduino emulator (the firmware's own FirmwareLogic) run by sim::pty::EmulatorHost over a
// pseudo-terminal in real time: start-up, commands applied and telemetry in the store, garbage
// and corruption counted, silence -> stale -> reopen -> data again, unplug -> reopen, and the
// board's failsafe when the daemon stops sending.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "coxswain/drivers/arduino/session.hpp"
#include "coxswain/drivers/serial/serial_transport.hpp"
#include "sim/devices/arduino/emulator.hpp"
#include "sim/pty/emulator_host.hpp"
#include "support/temp_dir.hpp"
#include "support/wait_for.hpp"

namespace coxswain::drivers::arduino {
namespace {

using coxswain::test::TempDir;

using namespace std::chrono_literals;
namespace emu = sim::devices::arduino;

struct Rig {
  Rig()
      : emulator(make_emulator()),
        host(emulator, host_options(dir / "ttyARDUINO")),
        config(make_config(dir / "ttyARDUINO")),
        session(config, config::ActuatorsConfig{}, command, status),
        transport(config, session, health, clock) {}
  ~Rig() {
    transport.stop();
    host.stop();
  }
  static emu::EmulatorConfig make_emulator() {
    emu::EmulatorConfig c;
    c.bootloader_ms = 300;  // short boot so the tests stay quick (the session waits for it)
    c.logic.boot_neutral_ms = 500;
    return c;
  }
  static sim::pty::EmulatorHost::Options host_options(const std::filesystem::path& link) {
    sim::pty::EmulatorHost::Options o;
    o.link_path = link;
    return o;
  }
  static config::ArduinoDeviceConfig make_config(const std::filesystem::path& path) {
    config::ArduinoDeviceConfig c;
    c.path = path.string();
    c.baud = 115200;
    c.timeout_ms = 500;
    return c;
  }
  /// Plays the tick: publishes `cmd` every 20 ms while `publishing` (this thread is the command
  /// slot's single writer), until `condition` holds or `timeout`.
  template <class F>
  bool tick_until(F&& condition, std::chrono::milliseconds timeout = 15s) {
    const auto end = std::chrono::steady_clock::now() + timeout;
    while (!condition()) {
      if (std::chrono::steady_clock::now() > end) return false;
      if (publishing) command.publish(cmd, clock.now_ns());
      std::this_thread::sleep_for(20ms);
    }
    return true;
  }
  msg::DeviceHealth h() const { return health.read().value; }
  msg::ArduinoStatus st() const { return status.read().value; }

  TempDir dir;
  emu::Emulator emulator;
  sim::pty::EmulatorHost host;
  config::ArduinoDeviceConfig config;
  core::LatestSlot<msg::ActuatorCommand> command;
  core::LatestSlot<msg::ArduinoStatus> status;
  core::LatestSlot<msg::DeviceHealth> health;
  const core::SteadyClock clock;
  ArduinoSession session;
  serial::SerialTransport transport;
  bool publishing = true;
  msg::ActuatorCommand cmd{0, {1620, 1380}, msg::LedColour::kYellow, true};
};

TEST(ArduinoEndToEnd, CommandsAreAppliedAndTelemetryReachesTheStore) {
  Rig rig;
  rig.transport.start();
  ASSERT_TRUE(rig.tick_until([&] {
    const auto s = rig.status.read();
    return s.valid() && s.value.applied_pulse_us[0] == 1620;
  })) << rig.h().detail_text();
  const msg::ArduinoStatus s = rig.st();
  EXPECT_EQ(s.applied_pulse_us[1], 1380);
  EXPECT_EQ(s.mode, msg::ControlMode::kAutonomous);
  EXPECT_EQ(s.led, msg::LedColour::kYellow);
  EXPECT_FALSE(s.failsafe);
  EXPECT_TRUE(s.rc_present);
  ASSERT_TRUE(rig.tick_until([&] { return rig.h().rate_hz > 0.0; }));
  const msg::DeviceHealth h = rig.h();
  EXPECT_EQ(h.state, msg::DeviceState::kRunning) << h.detail_text();
  EXPECT_NEAR(h.rate_hz, 20.0, 3.0);
  EXPECT_EQ(h.checksum_errors, 0U);
  // Every SetOutputs reached the board in order: no sequence gaps.
  ASSERT_TRUE(rig.tick_until(
      [&] { return rig.host.locked([&] { return rig.emulator.logic().last_seq(); }) > 30; }));
  EXPECT_EQ(rig.host.locked([&] { return rig.emulator.logic().counters().seq_gaps; }), 0);
}

TEST(ArduinoEndToEnd, BoardFailsafeWhenTheDaemonStopsSending) {
  Rig rig;
  rig.transport.start();
  ASSERT_TRUE(rig.tick_until([&] { return rig.st().applied_pulse_us[0] == 1620; }));
  rig.transport.stop();  // the daemon's Arduino thread is gone
  ASSERT_TRUE(rig.tick_until([&] {
    return rig.host.locked([&] { return rig.emulator.outputs().source; }) ==
           OutputSource::kFailsafe;
  }));
  const auto out = rig.host.locked([&] { return rig.emulator.outputs(); });
  EXPECT_EQ(out.pulse_us[0], 1500);
  EXPECT_EQ(out.pulse_us[1], 1500);
  EXPECT_TRUE(out.failsafe);
}

TEST(ArduinoEndToEnd, StaleCommandsBecomeDisarmedNeutral) {
  Rig rig;
  rig.transport.start();
  ASSERT_TRUE(rig.tick_until([&] { return rig.st().applied_pulse_us[0] == 1620; }));
  rig.publishing = false;  // the tick stops; the session keeps the link alive with neutral
  ASSERT_TRUE(rig.tick_until([&] { return rig.st().applied_pulse_us[0] == 1500; }));
  EXPECT_FALSE(rig.st().failsafe);
  EXPECT_EQ(rig.host.locked([&] { return rig.emulator.outputs().source; }),
            OutputSource::kDisarmed);
}

TEST(ArduinoEndToEnd, GarbageAndCorruptionAreCountedAndTelemetryKeepsFlowing) {
  Rig rig;
  rig.host.set_garbage(0.2, 16);
  rig.host.set_corruption(0.002);
  rig.transport.start();
  ASSERT_TRUE(rig.tick_until([&] {
    const msg::DeviceHealth h = rig.h();
    return h.frames_ok > 60 && h.checksum_errors > 0 && rig.st().applied_pulse_us[0] == 1620;
  })) << rig.h().detail_text();
  EXPECT_EQ(rig.transport.counters().reopen_count, 0U);
}

TEST(ArduinoEndToEnd, SilenceGoesStaleThenReopensAndRecovers) {
  Rig rig;
  rig.transport.start();
  ASSERT_TRUE(rig.tick_until([&] { return rig.st().applied_pulse_us[0] == 1620; }));
  rig.host.set_silent(true);
  ASSERT_TRUE(rig.tick_until([&] { return rig.h().state == msg::DeviceState::kStale; }));
  ASSERT_TRUE(rig.tick_until([&] { return rig.transport.counters().reopen_count >= 1; }));
  rig.host.set_silent(false);
  const std::uint64_t before = rig.status.sequence();
  ASSERT_TRUE(rig.tick_until([&] {
    return rig.status.sequence() > before + 10 && rig.h().state == msg::DeviceState::kRunning;
  })) << rig.h().detail_text();
  EXPECT_EQ(rig.st().applied_pulse_us[0], 1620);
}

TEST(ArduinoEndToEnd, UnplugThenReplugReopensAndTelemetryReturns) {
  Rig rig;
  rig.transport.start();
  ASSERT_TRUE(rig.tick_until([&] { return rig.st().applied_pulse_us[0] == 1620; }));
  rig.host.unplug();
  ASSERT_TRUE(rig.tick_until([&] { return rig.h().state == msg::DeviceState::kAbsent; }));
  rig.host.replug();
  const std::uint64_t before = rig.status.sequence();
  ASSERT_TRUE(rig.tick_until([&] {
    return rig.status.sequence() > before + 10 && rig.h().state == msg::DeviceState::kRunning;
  })) << rig.h().detail_text();
  EXPECT_GE(rig.transport.counters().reopen_count, 1U);
}

}  // namespace
}  // namespace coxswain::drivers::arduino
