// SPDX-License-Identifier: Apache-2.0
// MyahrsSession in virtual time: the start-up exchange (waits, retries, ERROR answers), the
// heading with declination and mount yaw, stamping, split-anywhere equivalence, error counting,
// silence and rate, against hand-built lines and the pure emulator (tools/sim/devices/myahrs).
#include "coxswain/drivers/myahrs/session.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "coxswain/core/angles.hpp"
#include "sim/devices/myahrs/emulator.hpp"

namespace coxswain::drivers::myahrs {
namespace {

constexpr core::TimeNs kMs = core::kNsPerMs;
constexpr core::TimeNs kT0 = 5'000 * kMs;

struct CaptureLink final : DeviceLink {
  std::vector<std::string> writes;
  bool write(std::span<const std::uint8_t> bytes) override {
    writes.emplace_back(bytes.begin(), bytes.end());
    return true;
  }
  void set_dtr(bool /*asserted*/) override {}
  void flush_input() override {}
};

std::vector<std::uint8_t> line(std::string_view body) {
  char tail[8];
  std::snprintf(tail, sizeof tail, "*%02X\r\n", static_cast<unsigned>(xor_checksum(body)));
  std::string s = std::string(body) + tail;
  return {s.begin(), s.end()};
}

config::ImuDeviceConfig imu_config() {
  config::ImuDeviceConfig c;
  c.output = config::ImuOutput::kAscii;
  c.rate_hz = 50.0;
  c.declination_deg = -9.0;
  c.timeout_ms = 200;
  return c;
}

msg::DeviceHealth health_of(const MyahrsSession& s, core::TimeNs now) {
  msg::DeviceHealth h;
  s.fill_health(h, now);
  return h;
}

const std::vector<std::uint8_t> kRpyImu = line(
    "$RPYIMU,15,-1.55,-1.25,97.31,-0.0142,-0.0010,-0.9224,-0.9756,-0.3659,-0.8537,-8.4000,"
    "-46.8000,5.4000,38.3");

TEST(MyahrsSession, StartupSendsEachRequestAfterTheOkOfThePrevious) {
  core::LatestSlot<msg::ImuSample> slot;
  MyahrsSession s(imu_config(), core::MountTransform{}, slot);
  CaptureLink link;
  s.on_open(link, kT0);
  ASSERT_EQ(link.writes.size(), 1U);
  EXPECT_EQ(link.writes[0].substr(0, 8), "@mode,T*");
  EXPECT_EQ(health_of(s, kT0).state, msg::DeviceState::kConfiguring);
  // Data and unrelated answers do not advance the plan.
  s.on_bytes(kRpyImu, kT0 + kMs, link);
  s.on_bytes(line("~divider,OK,divider=2,max rate=100"), kT0 + kMs, link);
  EXPECT_EQ(link.writes.size(), 1U);
  s.on_bytes(line("~mode,OK,mode=T"), kT0 + 2 * kMs, link);
  ASSERT_EQ(link.writes.size(), 2U);
  EXPECT_EQ(link.writes[1], "@version*3A\r\n");  // docs/protocols.md 2.2 example
  s.on_bytes(line("~version,OK,product=myAHRS+,platform=myAHRS+m3,sn=123,ver=1.6,build=x"),
             kT0 + 3 * kMs, link);
  ASSERT_EQ(link.writes.size(), 3U);
  EXPECT_EQ(s.firmware_version(), "1.6");
  EXPECT_EQ(link.writes[2].substr(0, 11), "@divider,2*");  // 100 / 50 Hz
  s.on_bytes(line("~divider,OK,divider=2,max rate=100"), kT0 + 4 * kMs, link);
  EXPECT_EQ(link.writes[3].substr(0, 16), "@asc_out,RPYIMU*");
  s.on_bytes(line("~asc_out,OK,fmt=RPYIMU"), kT0 + 5 * kMs, link);
  EXPECT_EQ(link.writes[4].substr(0, 9), "@mode,AC*");
  s.on_bytes(line("~mode,OK,mode=AC"), kT0 + 6 * kMs, link);
  EXPECT_FALSE(s.configuring());
  EXPECT_EQ(s.startup_failures(), 0U);
  EXPECT_EQ(health_of(s, kT0 + 7 * kMs).detail_text(), "started");
  EXPECT_EQ(health_of(s, kT0 + 7 * kMs).state, msg::DeviceState::kRunning);
  EXPECT_EQ(s.samples_published(), 1U);
}

TEST(MyahrsSession, TimeoutsRetryThenMoveOnAndErrorsAreReported) {
  core::LatestSlot<msg::ImuSample> slot;
  SessionTiming timing;
  timing.response_timeout_ns = 500 * kMs;
  timing.max_attempts = 3;
  config::ImuDeviceConfig cfg = imu_config();
  cfg.timeout_ms = 10'000;
  MyahrsSession s(cfg, core::MountTransform{}, slot, timing);
  CaptureLink link;
  s.on_open(link, kT0);
  core::TimeNs t = kT0;
  // No answer to @mode,T: sent three times, 500 ms apart, then @version.
  while (link.writes.size() < 4) {
    t += 10 * kMs;
    ASSERT_EQ(s.on_poll(link, t), SessionVerdict::kContinue);
    ASSERT_LT(t, kT0 + 5'000 * kMs);
  }
  EXPECT_EQ(link.writes[0], link.writes[1]);
  EXPECT_EQ(link.writes[1], link.writes[2]);
  EXPECT_EQ(link.writes[3], "@version*3A\r\n");
  EXPECT_NEAR(static_cast<double>(t - kT0), 1'500.0 * kMs, 10.0 * kMs);
  EXPECT_EQ(s.startup_failures(), 1U);
  // An ERROR answer fails the step at once.
  s.on_bytes(line("~version,ERROR"), t + kMs, link);
  EXPECT_EQ(link.writes.size(), 5U);
  EXPECT_EQ(s.startup_failures(), 2U);
  EXPECT_EQ(health_of(s, t + 2 * kMs).detail_text(), "no answer to @mode");
}

TEST(MyahrsSession, HeadingAppliesDeclinationAndMountYaw) {
  core::LatestSlot<msg::ImuSample> slot;
  core::MountTransform mount;
  mount.yaw_deg = 90.0;  // board arrow to starboard
  MyahrsSession s(imu_config(), mount, slot);
  CaptureLink link;
  s.on_open(link, kT0);
  s.on_bytes(kRpyImu, kT0 + kMs, link);
  const auto got = slot.read();
  ASSERT_TRUE(got.valid());
  EXPECT_DOUBLE_EQ(got.value.yaw_magnetic_deg, 97.31);
  // true heading = wrap(97.31 - 90 + (-9)) = -1.69
  EXPECT_NEAR(got.value.heading_deg, -1.69, 1e-9);
  EXPECT_EQ(got.stamp_ns, kT0 + kMs);
  EXPECT_EQ(got.value.sequence, 15U);
  EXPECT_TRUE(got.value.has_inertial);
}

TEST(MyahrsSession, StampIsTheChunkHoldingTheFirstByte) {
  core::LatestSlot<msg::ImuSample> slot;
  MyahrsSession s(imu_config(), core::MountTransform{}, slot);
  CaptureLink link;
  s.on_open(link, kT0);
  // Tail bytes of nothing (garbage without a start byte), then the line split in three.
  std::vector<std::uint8_t> a{'1', '2', '\r', '\n'};
  a.insert(a.end(), kRpyImu.begin(), kRpyImu.begin() + 10);
  s.on_bytes(a, kT0 + 1 * kMs, link);
  s.on_bytes(std::span(kRpyImu).subspan(10, 40), kT0 + 2 * kMs, link);
  s.on_bytes(std::span(kRpyImu).subspan(50), kT0 + 3 * kMs, link);
  ASSERT_EQ(slot.sequence(), 1U);
  EXPECT_EQ(slot.read().stamp_ns, kT0 + 1 * kMs);
  // Back to back: the next line starts in the chunk that ends the previous one.
  std::vector<std::uint8_t> b(kRpyImu.begin() + 40, kRpyImu.end());
  std::vector<std::uint8_t> two = kRpyImu;
  two.insert(two.end(), kRpyImu.begin(), kRpyImu.begin() + 40);
  s.on_bytes(two, kT0 + 10 * kMs, link);
  s.on_bytes(b, kT0 + 11 * kMs, link);
  EXPECT_EQ(slot.sequence(), 3U);
  EXPECT_EQ(slot.read().stamp_ns, kT0 + 10 * kMs);
}

TEST(MyahrsSession, BadChecksumsAndGarbageAreCountedNotPublished) {
  core::LatestSlot<msg::ImuSample> slot;
  MyahrsSession s(imu_config(), core::MountTransform{}, slot);
  CaptureLink link;
  s.on_open(link, kT0);
  auto bad = kRpyImu;
  bad[bad.size() - 3] = bad[bad.size() - 3] == '0' ? '1' : '0';
  std::vector<std::uint8_t> stream{0xFF, 0x00, 0x7F};
  stream.insert(stream.end(), bad.begin(), bad.end());
  s.on_bytes(stream, kT0 + kMs, link);
  EXPECT_EQ(slot.sequence(), 0U);
  const auto h = health_of(s, kT0 + 2 * kMs);
  EXPECT_EQ(h.checksum_errors, 1U);
  EXPECT_EQ(h.frames_ok, 0U);
  s.on_bytes(kRpyImu, kT0 + 3 * kMs, link);
  EXPECT_EQ(slot.sequence(), 1U);
}

// ---- Against the pure emulator, in virtual time ----

struct Loop {
  core::LatestSlot<msg::ImuSample> slot;
  sim::devices::myahrs::Emulator emu;
  MyahrsSession session;
  struct EmuLink final : DeviceLink {
    sim::devices::myahrs::Emulator* emu = nullptr;
    core::TimeNs now = 0;
    bool write(std::span<const std::uint8_t> bytes) override {
      emu->receive(bytes, now);
      return true;
    }
    void set_dtr(bool /*asserted*/) override {}
    void flush_input() override {}
  } link;
  core::TimeNs now = kT0;
  std::size_t chunk = 0;  // 0: whole poll output at once

  Loop(const config::ImuDeviceConfig& cfg, const core::MountTransform& mount,
       const SessionTiming& timing = {})
      : session(cfg, mount, slot, timing) {
    link.emu = &emu;
    link.now = now;
    session.on_open(link, now);
  }
  SessionVerdict run_for(core::TimeNs dt) {
    const core::TimeNs end = now + dt;
    SessionVerdict v = SessionVerdict::kContinue;
    while (now < end && v == SessionVerdict::kContinue) {
      now += 5 * kMs;
      link.now = now;
      const auto out = emu.poll(now);
      const std::size_t step = chunk == 0 ? out.size() : chunk;
      for (std::size_t o = 0; o < out.size(); o += step) {
        session.on_bytes(out.subspan(o, std::min(step, out.size() - o)), now, link);
      }
      v = session.on_poll(link, now);
    }
    return v;
  }
};

msg::ImuSample truth(double heading_deg, const HeadingConfig& hc) {
  msg::ImuSample t;
  t.roll_deg = 3.5;
  t.pitch_deg = -2.25;
  t.yaw_magnetic_deg = sim::devices::myahrs::Emulator::sensor_yaw_for_heading(heading_deg, hc);
  t.accel_g = {0.01, -0.02, -0.99};
  t.gyro_dps = {0.5, -0.25, 3.0};
  t.mag_ut = {10.0, -40.0, 5.0};
  t.temperature_c = 31.0;
  return t;
}

TEST(MyahrsSession, AsciiAndBinaryAgainstTheEmulatorGiveTheTrueHeadingAtTheConfiguredRate) {
  for (const auto output : {config::ImuOutput::kAscii, config::ImuOutput::kBinary}) {
    config::ImuDeviceConfig cfg = imu_config();
    cfg.output = output;
    cfg.rate_hz = 50.0;
    core::MountTransform mount;
    mount.yaw_deg = -30.0;
    Loop loop(cfg, mount);
    const HeadingConfig hc{mount.yaw_deg, cfg.declination_deg};
    loop.emu.set_truth(truth(123.4, hc));
    loop.run_for(3'000 * kMs);
    EXPECT_EQ(loop.session.startup_failures(), 0U);
    EXPECT_EQ(loop.emu.divider(), 2);
    EXPECT_EQ(loop.emu.binary(), output == config::ImuOutput::kBinary);
    const auto got = loop.slot.read();
    ASSERT_TRUE(got.valid());
    EXPECT_NEAR(got.value.heading_deg, 123.4, 0.02);  // binary: 180/32767 deg resolution
    EXPECT_NEAR(got.value.roll_deg, 3.5, 0.02);
    EXPECT_NEAR(got.value.pitch_deg, -2.25, 0.02);
    const auto h = health_of(loop.session, loop.now);
    EXPECT_EQ(h.state, msg::DeviceState::kRunning);
    EXPECT_NEAR(h.rate_hz, 50.0, 1.0);
    EXPECT_EQ(h.checksum_errors, 0U);
  }
}

TEST(MyahrsSession, SplitAnywhereGivesTheSameSamples) {
  const auto run = [](std::size_t chunk) {
    Loop loop(imu_config(), core::MountTransform{});
    loop.chunk = chunk;
    loop.emu.set_truth(truth(10.0, HeadingConfig{0.0, -9.0}));
    std::vector<double> headings;
    std::uint64_t seen = 0;
    for (int i = 0; i < 200; ++i) {
      loop.run_for(5 * kMs);
      if (loop.slot.sequence() != seen) {
        seen = loop.slot.sequence();
        headings.push_back(loop.slot.read().value.heading_deg);
      }
    }
    return std::make_pair(headings, loop.session.samples_published());
  };
  const auto whole = run(0);
  ASSERT_GT(whole.second, 40U);
  for (const std::size_t chunk : {1U, 3U, 7U, 64U}) {
    const auto split = run(chunk);
    EXPECT_EQ(split.second, whole.second) << chunk;
    EXPECT_EQ(split.first, whole.first) << chunk;
  }
}

TEST(MyahrsSession, SilenceStaleReopenAndRateChange) {
  SessionTiming timing;
  timing.reopen_after_ns = 2'000 * kMs;
  config::ImuDeviceConfig cfg = imu_config();
  cfg.rate_hz = 100.0;
  Loop loop(cfg, core::MountTransform{}, timing);
  loop.emu.set_truth(truth(0.0, HeadingConfig{}));
  ASSERT_EQ(loop.run_for(3'000 * kMs), SessionVerdict::kContinue);
  EXPECT_NEAR(health_of(loop.session, loop.now).rate_hz, 100.0, 2.0);
  // Rate change behind our back: 100 Hz -> 20 Hz.
  loop.emu.set_divider(5);
  ASSERT_EQ(loop.run_for(3'000 * kMs), SessionVerdict::kContinue);
  EXPECT_NEAR(health_of(loop.session, loop.now).rate_hz, 20.0, 0.5);
  // Silence: stale after timeout_ms, reopen verdict after reopen_after_ns.
  sim::devices::myahrs::EmulatorFaults quiet;
  quiet.silent = true;
  loop.emu.set_faults(quiet);
  const core::TimeNs silent_from = loop.now;
  ASSERT_EQ(loop.run_for(150 * kMs), SessionVerdict::kContinue);
  EXPECT_EQ(health_of(loop.session, loop.now).state, msg::DeviceState::kRunning);
  ASSERT_EQ(loop.run_for(200 * kMs), SessionVerdict::kContinue);
  EXPECT_EQ(health_of(loop.session, loop.now).state, msg::DeviceState::kStale);
  EXPECT_EQ(loop.run_for(5'000 * kMs), SessionVerdict::kReopen);
  EXPECT_NEAR(static_cast<double>(loop.now - silent_from), 2'000.0 * kMs, 60.0 * kMs);
  // Reopen: the start-up runs again and data resumes.
  loop.session.on_close(loop.now);
  loop.emu.set_faults({});
  loop.session.on_open(loop.link, loop.now);
  ASSERT_EQ(loop.run_for(2'000 * kMs), SessionVerdict::kContinue);
  EXPECT_FALSE(loop.session.configuring());
  EXPECT_EQ(health_of(loop.session, loop.now).state, msg::DeviceState::kRunning);
  EXPECT_NEAR(health_of(loop.session, loop.now).rate_hz, 100.0, 2.0);
}

}  // namespace
}  // namespace coxswain::drivers::myahrs
