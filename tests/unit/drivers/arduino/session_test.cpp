// SPDX-License-Identifier: Apache-2.0
// ArduinoSession in virtual time against the Arduino emulator core, which runs the firmware's own
// FirmwareLogic: boot wait after the reset on open, SetOutputs at the command rate with
// increasing sequence numbers, telemetry into ArduinoStatus, neutral on stale/inactive
// commands, the board's failsafe when commands stop, sequence-lag warning, stale and reopen.
#include "coxswain/drivers/arduino/session.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "sim/devices/arduino/emulator.hpp"

namespace coxswain::drivers::arduino {
namespace {

namespace emu = sim::devices::arduino;
constexpr core::TimeNs kMs = core::kNsPerMs;
constexpr core::TimeNs kT0 = 10'000 * kMs;

class CapturingLink final : public DeviceLink {
 public:
  explicit CapturingLink(emu::Emulator& e) : emu_(e) {}
  bool write(std::span<const std::uint8_t> bytes) override {
    if (drop_writes) return true;  // a cable that eats the host's bytes
    FrameDecoder& d = decoder;
    for (const std::uint8_t b : bytes) {
      if (d.push(b)) frames.push_back({now_ns, d.frame().type, d.frame().seq, parse_set(d)});
    }
    emu_.receive(bytes, now_ns);
    return true;
  }
  void set_dtr(bool /*asserted*/) override {}
  void flush_input() override {}

  struct Sent {
    core::TimeNs at_ns;
    std::uint8_t type;
    std::uint16_t seq;
    SetOutputs set;
  };
  static SetOutputs parse_set(const FrameDecoder& d) {
    SetOutputs s{};
    (void)parse(d.frame(), &s);
    return s;
  }
  [[nodiscard]] std::vector<Sent> set_outputs() const {
    std::vector<Sent> v;
    for (const Sent& s : frames) {
      if (s.type == static_cast<std::uint8_t>(MsgType::kSetOutputs)) v.push_back(s);
    }
    return v;
  }

  core::TimeNs now_ns = 0;
  bool drop_writes = false;
  FrameDecoder decoder;
  std::vector<Sent> frames;

 private:
  emu::Emulator& emu_;
};

struct Rig {
  explicit Rig(const emu::EmulatorConfig& ec = {}, config::ArduinoDeviceConfig dc = {},
               config::ActuatorsConfig ac = {})
      : emulator(ec), link(emulator), session(dc, ac, command, status) {}

  void open() {
    now = now == 0 ? kT0 : now;
    link.now_ns = now;
    emulator.reset(now);  // opening the port toggles DTR: the board resets
    session.on_open(link, now);
  }

  /// The tick publishing `cmd` every 50 ms while `publishing`.
  template <class Pred>
  bool run_until(core::TimeNs until, Pred pred) {
    while (now < until) {
      now += 5 * kMs;
      link.now_ns = now;
      if (publishing && (now - kT0) % (50 * kMs) == 0) command.publish(cmd, now);
      const auto bytes = emulator.poll(now);
      session.on_bytes(bytes, now, link);
      if (session.on_poll(link, now) == SessionVerdict::kReopen) ++reopen_verdicts;
      if (pred()) return true;
    }
    return pred();
  }
  void run_for(core::TimeNs d) {
    run_until(now + d, [] { return false; });
  }
  msg::DeviceHealth health() const {
    msg::DeviceHealth h;
    session.fill_health(h, now);
    return h;
  }

  emu::Emulator emulator;
  CapturingLink link;
  core::LatestSlot<msg::ActuatorCommand> command;
  core::LatestSlot<msg::ArduinoStatus> status;
  ArduinoSession session;
  core::TimeNs now = 0;
  bool publishing = true;
  msg::ActuatorCommand cmd{core::kNeverNs, {1600, 1400}, msg::LedColour::kGreen, true};
  int reopen_verdicts = 0;
};

TEST(ArduinoSession, WaitsSilentlyForTheBoardAfterTheResetOnOpen) {
  Rig rig;
  rig.open();
  rig.run_for(1'400 * kMs);
  EXPECT_TRUE(rig.link.frames.empty()) << "nothing sent while the bootloader runs";
  EXPECT_EQ(rig.session.step(), ArduinoStep::kBooting);
  msg::DeviceHealth h = rig.health();
  EXPECT_EQ(h.state, msg::DeviceState::kConfiguring);
  EXPECT_EQ(h.checksum_errors + h.framing_errors, 0U);
  EXPECT_NE(h.detail_text().find("bootloader"), std::string_view::npos) << h.detail_text();
  ASSERT_TRUE(rig.run_until(kT0 + 2'000 * kMs,
                            [&] { return rig.session.step() == ArduinoStep::kRunning; }));
  EXPECT_EQ(rig.session.board_resets_seen(), 1U);
  EXPECT_EQ(rig.session.last_ready().failsafe_ms, 300);
  EXPECT_EQ(rig.emulator.stats().bytes_lost_in_bootloader, 0U);
}

TEST(ArduinoSession, SendsCommandsAtTheConfiguredRateWithIncreasingSequence) {
  config::ActuatorsConfig ac;
  ac.command_rate_hz = 25.0;
  Rig rig({}, {}, ac);
  rig.open();
  ASSERT_TRUE(rig.run_until(kT0 + 2'000 * kMs,
                            [&] { return rig.session.step() == ArduinoStep::kRunning; }));
  const core::TimeNs from = rig.now;
  rig.run_for(2'000 * kMs);
  std::vector<CapturingLink::Sent> sent;
  for (const auto& s : rig.link.set_outputs()) {
    if (s.at_ns > from) sent.push_back(s);
  }
  EXPECT_NEAR(static_cast<double>(sent.size()), 50.0, 1.0);
  for (std::size_t i = 1; i < sent.size(); ++i) {
    EXPECT_EQ(static_cast<std::uint16_t>(sent[i - 1].seq + 1), sent[i].seq);
    EXPECT_NEAR(static_cast<double>(sent[i].at_ns - sent[i - 1].at_ns), 40.0 * kMs, 5.0 * kMs);
    EXPECT_EQ(sent[i].set.pulse_us[0], 1600);
    EXPECT_EQ(sent[i].set.pulse_us[1], 1400);
    EXPECT_EQ(sent[i].set.flags, kFlagArm);
    EXPECT_EQ(sent[i].set.led, static_cast<std::uint8_t>(msg::LedColour::kGreen));
  }
  EXPECT_EQ(rig.session.command_period_ns(), 40 * kMs);
}

TEST(ArduinoSession, TelemetryBecomesStatusAndTheBoardAppliesTheCommandAfterBootHold) {
  Rig rig;
  rig.open();
  ASSERT_TRUE(rig.run_until(kT0 + 6'000 * kMs, [&] {
    const auto s = rig.status.read();
    return s.valid() && s.value.applied_pulse_us[0] == 1600;
  })) << rig.session.detail();
  const auto s = rig.status.read();
  EXPECT_EQ(s.value.applied_pulse_us[1], 1400);
  EXPECT_EQ(s.value.mode, msg::ControlMode::kAutonomous);
  EXPECT_TRUE(s.value.rc_present);
  EXPECT_FALSE(s.value.failsafe);
  EXPECT_FALSE(s.value.estop);
  EXPECT_EQ(s.value.led, msg::LedColour::kGreen);
  EXPECT_NEAR(s.value.supply_v, 12.0, 1e-9);
  EXPECT_EQ(s.stamp_ns, s.value.stamp_ns);
  EXPECT_LE(static_cast<std::uint16_t>(rig.session.last_sent_seq() - s.value.last_sequence_seen),
            1);
  // Boot hold lasted 3 s after the bootloader.
  EXPECT_GE(rig.now - kT0, 1'500 * kMs + 3'000 * kMs);
  const msg::DeviceHealth h = rig.health();
  EXPECT_EQ(h.state, msg::DeviceState::kRunning);
  EXPECT_NEAR(h.rate_hz, 20.0, 1.0);
  EXPECT_FALSE(rig.session.sequence_lag_warning());
}

TEST(ArduinoSession, StaleOrInactiveCommandIsSentAsDisarmedNeutral) {
  Rig rig;
  rig.open();
  ASSERT_TRUE(rig.run_until(kT0 + 6'000 * kMs,
                            [&] { return rig.status.read().value.applied_pulse_us[0] == 1600; }));
  rig.publishing = false;  // the tick died
  rig.run_for(250 * kMs);
  EXPECT_EQ(rig.link.set_outputs().back().set.flags, kFlagArm) << "still fresh within 300 ms";
  rig.run_for(200 * kMs);
  const auto last = rig.link.set_outputs().back();
  EXPECT_EQ(last.set.flags, 0) << "disarmed";
  EXPECT_EQ(last.set.pulse_us[0], 1500);
  EXPECT_EQ(last.set.pulse_us[1], 1500);
  rig.run_for(100 * kMs);
  const auto st = rig.status.read().value;
  EXPECT_EQ(st.applied_pulse_us[0], 1500);
  EXPECT_FALSE(st.failsafe) << "commands keep flowing: the board is disarmed, not in failsafe";
  EXPECT_EQ(rig.emulator.outputs().source, OutputSource::kDisarmed);
  // Inactive command: neutral as well.
  rig.publishing = true;
  rig.cmd.active = false;
  rig.run_for(200 * kMs);
  EXPECT_EQ(rig.link.set_outputs().back().set.flags, 0);
  EXPECT_GT(rig.session.neutral_commands_sent(), 0U);
}

TEST(ArduinoSession, BoardFailsafeShowsInTelemetryWhenCommandsStopArriving) {
  Rig rig;
  rig.open();
  ASSERT_TRUE(rig.run_until(kT0 + 6'000 * kMs,
                            [&] { return rig.status.read().value.applied_pulse_us[0] == 1600; }));
  rig.link.drop_writes = true;  // the host's bytes no longer reach the board
  rig.run_for(250 * kMs);
  EXPECT_FALSE(rig.status.read().value.failsafe);
  rig.run_for(500 * kMs);  // 15 commands lost: the lag warning threshold is 10
  const auto st = rig.status.read().value;
  EXPECT_TRUE(st.failsafe);
  EXPECT_EQ(st.applied_pulse_us[0], 1500);
  EXPECT_EQ(st.applied_pulse_us[1], 1500);
  EXPECT_EQ(rig.emulator.outputs().source, OutputSource::kFailsafe);
  EXPECT_EQ(rig.emulator.logic().counters().failsafe_events, 1);
  EXPECT_TRUE(rig.session.sequence_lag_warning());
  EXPECT_NE(rig.health().detail_text().find("lags ours"), std::string_view::npos)
      << rig.health().detail_text();
  // Link restored: the board accepts the next sequence and leaves failsafe.
  rig.link.drop_writes = false;
  rig.run_for(200 * kMs);
  EXPECT_FALSE(rig.status.read().value.failsafe);
  EXPECT_EQ(rig.status.read().value.applied_pulse_us[0], 1600);
  EXPECT_FALSE(rig.session.sequence_lag_warning());
  EXPECT_GT(rig.emulator.logic().counters().seq_gaps, 0);
}

TEST(ArduinoSession, RcAbsentEstopAndManualAreReported) {
  Rig rig;
  rig.open();
  ASSERT_TRUE(rig.run_until(kT0 + 6'000 * kMs,
                            [&] { return rig.status.read().value.applied_pulse_us[0] == 1600; }));
  emu::BoardInputs in = rig.emulator.inputs();
  in.rc_present = false;
  rig.emulator.set_inputs(in);
  rig.run_for(300 * kMs);
  auto st = rig.status.read().value;
  EXPECT_FALSE(st.rc_present);
  EXPECT_EQ(st.mode, msg::ControlMode::kManual);
  EXPECT_EQ(st.applied_pulse_us[0], 1500);
  in.rc_present = true;
  in.estop = true;
  in.supply_mv = 11100;
  rig.emulator.set_inputs(in);
  rig.run_for(300 * kMs);
  st = rig.status.read().value;
  EXPECT_TRUE(st.estop);
  EXPECT_EQ(st.applied_pulse_us[1], 1500);
  EXPECT_NEAR(st.supply_v, 11.1, 1e-9);
  in.estop = false;
  in.mode_auto = false;
  in.rc_steering_us = 1700;
  rig.emulator.set_inputs(in);
  rig.run_for(300 * kMs);
  st = rig.status.read().value;
  EXPECT_EQ(st.mode, msg::ControlMode::kManual);
  EXPECT_EQ(st.applied_pulse_us[0], 1700) << "RC passed through in manual";
}

TEST(ArduinoSession, SilenceIsStaleThenReopen) {
  Rig rig;
  rig.open();
  ASSERT_TRUE(rig.run_until(kT0 + 3'000 * kMs,
                            [&] { return rig.session.step() == ArduinoStep::kRunning; }));
  rig.emulator.set_faults({0.0, 0.0, true, 1});
  const core::TimeNs from = rig.now;
  rig.run_for(400 * kMs);
  EXPECT_EQ(rig.health().state, msg::DeviceState::kRunning);
  rig.run_for(200 * kMs);
  EXPECT_EQ(rig.health().state, msg::DeviceState::kStale) << rig.health().detail_text();
  ASSERT_TRUE(rig.run_until(from + 3'000 * kMs, [&] { return rig.reopen_verdicts > 0; }));
  EXPECT_GE(rig.now - from, 2'000 * kMs);
  EXPECT_NE(rig.session.detail().find("reopening"), std::string_view::npos);
  // The transport reopens: the board resets again and the session recovers.
  rig.session.on_close(rig.now);
  rig.emulator.set_faults({});
  rig.open();
  ASSERT_TRUE(rig.run_until(rig.now + 3'000 * kMs,
                            [&] { return rig.session.step() == ArduinoStep::kRunning; }));
  EXPECT_EQ(rig.session.board_resets_seen(), 2U);
}

TEST(ArduinoSession, SilentBoardGetsHellosThenReopen) {
  emu::EmulatorConfig ec;
  ec.faults.silent = true;
  Rig rig(ec);
  rig.open();
  ASSERT_TRUE(rig.run_until(kT0 + 8'000 * kMs, [&] { return rig.reopen_verdicts > 0; }));
  EXPECT_EQ(rig.emulator.stats().hellos, static_cast<std::uint64_t>(ArduinoSession::kMaxHellos));
  EXPECT_NEAR(static_cast<double>(rig.now - kT0),
              static_cast<double>((ArduinoSession::kBootGraceMs +
                                   ArduinoSession::kMaxHellos * ArduinoSession::kHelloPeriodMs) *
                                  kMs),
              10.0 * kMs);
  EXPECT_TRUE(rig.link.set_outputs().empty());
}

TEST(ArduinoSession, BoardThatDidNotResetGetsHelloAndCommands) {
  Rig rig;
  rig.emulator.reset(kT0 - 10'000 * kMs);      // powered long ago; this open does not reset it
  (void)rig.emulator.poll(kT0 - 1'000 * kMs);  // its Ready went to nobody
  rig.now = kT0;
  rig.link.now_ns = kT0;
  rig.session.on_open(rig.link, kT0);
  ASSERT_TRUE(
      rig.run_until(kT0 + 500 * kMs, [&] { return rig.session.step() == ArduinoStep::kRunning; }));
  rig.run_for(200 * kMs);
  EXPECT_EQ(rig.emulator.stats().hellos, 1U);
  EXPECT_GE(rig.session.board_resets_seen(), 1U) << "Hello answered with Ready";
  EXPECT_FALSE(rig.link.set_outputs().empty());
}

TEST(ArduinoSession, CorruptTelemetryIsCountedAndGoodTelemetryStillFlows) {
  emu::EmulatorConfig ec;
  ec.faults.corrupt_probability = 0.1;
  ec.faults.garbage_probability = 0.1;
  ec.faults.seed = 5;
  Rig rig(ec);
  rig.open();
  rig.run_for(6'000 * kMs);
  const msg::DeviceHealth h = rig.health();
  EXPECT_GT(h.checksum_errors, 0U);
  EXPECT_GT(h.frames_ok, 50U);
  EXPECT_EQ(h.state, msg::DeviceState::kRunning);
  EXPECT_EQ(rig.status.read().value.applied_pulse_us[0], 1600);
  EXPECT_EQ(rig.reopen_verdicts, 0);
}

TEST(ArduinoSession, TwinLayoutNeutralUsesTheThrusterNeutral) {
  config::ActuatorsConfig ac;
  ac.layout = msg::ActuatorLayout::kTwinThrusters;
  ac.thruster.neutral_us = 1490;
  Rig rig({}, {}, ac);
  rig.publishing = false;
  rig.open();
  ASSERT_TRUE(rig.run_until(kT0 + 3'000 * kMs, [&] { return !rig.link.set_outputs().empty(); }));
  const auto s = rig.link.set_outputs().back();
  EXPECT_EQ(s.set.pulse_us[0], 1490);
  EXPECT_EQ(s.set.pulse_us[1], 1490);
  EXPECT_EQ(s.set.flags, 0);
  EXPECT_EQ(s.set.led, 0);
}

}  // namespace
}  // namespace coxswain::drivers::arduino
