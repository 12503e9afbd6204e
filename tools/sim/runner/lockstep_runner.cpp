// SPDX-License-Identifier: Apache-2.0
#include "sim/runner/lockstep_runner.hpp"

#include <cstring>

#include "coxswain/drivers/arduino/codec.hpp"

namespace coxswain::sim::runner {
namespace {

namespace ard = drivers::arduino;

ard::LogicConfig logic_config(const config::BoatConfig& boat, const RunnerOptions& options) {
  ard::LogicConfig c;
  const auto& a = boat.actuators;
  if (a.layout == msg::ActuatorLayout::kServoThruster) {
    c.neutral_us[0] = a.servo.center_us;
    c.min_us[0] = a.servo.min_us;
    c.max_us[0] = a.servo.max_us;
  } else {
    c.neutral_us[0] = a.thruster.neutral_us;
    c.min_us[0] = a.thruster.min_us;
    c.max_us[0] = a.thruster.max_us;
  }
  c.neutral_us[1] = a.thruster.neutral_us;
  c.min_us[1] = a.thruster.min_us;
  c.max_us[1] = a.thruster.max_us;
  c.failsafe_ms = options.failsafe_ms;
  c.boot_neutral_ms = options.boot_hold ? 3000 : 0;
  return c;
}

// FNV-1a over the bytes of each value: any bit that differs changes the hash.
void fold(std::uint64_t& h, double v) {
  unsigned char bytes[sizeof(double)];
  std::memcpy(bytes, &v, sizeof v);
  for (unsigned char b : bytes) {
    h ^= b;
    h *= 0x100000001b3ULL;
  }
}

std::uint32_t millis(core::TimeNs t_ns) {
  return static_cast<std::uint32_t>(static_cast<std::uint64_t>(t_ns / core::kNsPerMs));
}

}  // namespace

LockstepRunner::LockstepRunner(const world::Course& course, const config::BoatConfig& boat,
                               RunnerOptions options, SensorSuite* sensors, Pilot* pilot)
    : course_(&course),
      boat_(boat),
      options_(options),
      sensors_(sensors),
      pilot_(pilot),
      clock_(0),
      store_(std::make_unique<core::LatestStore>()),
      snapshot_(std::make_unique<core::Snapshot>()),
      model_(boat, dynamics::make_params(boat, course.dynamics), course.environment, options.seed,
             core::ns_to_sec(options.dynamics_step_ns)),
      scorer_(course.world, boat.hull),
      collisions_(course.world, boat.hull),
      firmware_(logic_config(boat, options)),
      tick_period_ns_(core::sec_to_ns(1.0 / options.tick_rate_hz)),
      command_period_ns_(core::sec_to_ns(1.0 / boat.actuators.command_rate_hz)) {
  model_.reset(course.world.start);
  firmware_.reset(0);
  path_.push_back(model_.truth().pose);
  const dynamics::TruthState t0 = model_.truth();
  if (sensors_ != nullptr) sensors_->step(t0, 0, *store_);
}

LockstepRunner::~LockstepRunner() = default;

bool LockstepRunner::step() {
  if (over_) return false;
  const core::TimeNs now = clock_.now_ns();
  const std::uint32_t now_ms = millis(now);
  // 1. The pilot's tick.
  if (now >= next_tick_ns_) {
    next_tick_ns_ += tick_period_ns_;
    if (pilot_ != nullptr) {
      store_->refresh(*snapshot_);  // the scan is copied only when a new one came
      msg::ActuatorCommand cmd = command_;
      pilot_->step(*snapshot_, now, cmd);
      cmd.stamp_ns = now;
      command_ = cmd;
      store_->command.publish(cmd, now);
    }
  }
  // 2. The Arduino driver sends the latest command at the command rate.
  if (now >= next_command_ns_) {
    next_command_ns_ += command_period_ns_;
    if (link_up_ && command_.stamp_ns != core::kNeverNs) {
      (void)firmware_.on_set_outputs(now_ms, command_seq_++, ard::to_set_outputs(command_));
    }
  }
  // 3. The firmware decides the outputs; the RC transmitter is on with its switch at autonomous.
  for (std::uint8_t ch = 0; ch < ard::kRcChannels; ++ch) {
    firmware_.on_rc_pulse(now_ms, ch, ch == 2 ? 2000 : 1500);
  }
  outputs_ = firmware_.step(now_ms, {false, options_.start_switch});
  model_.set_pulses({outputs_.pulse_us[0], outputs_.pulse_us[1]});
  if (now >= next_status_ns_) {
    next_status_ns_ += options_.status_period_ns;
    ard::Telemetry tel{};
    firmware_.fill_telemetry(now_ms, outputs_, ard::DecoderStats{}, 12000, &tel);
    store_->arduino.publish(ard::to_status(tel, now), now);
  }
  // 4. Dynamics, then the clock.
  model_.step();
  if (options_.collision_response) (void)collisions_.resolve(model_);
  ++steps_;
  const core::TimeNs t = model_.time_ns();
  clock_.set_ns(t);
  const dynamics::TruthState truth = model_.truth();
  const dynamics::BoatState& s = model_.state();
  for (double v : {s.north_m, s.east_m, s.psi_rad, s.u_r_mps, s.v_r_mps, s.r_radps}) fold(hash_, v);
  // 5. Sensors and scoring see the new state.
  if (sensors_ != nullptr) sensors_->step(truth, t, *store_);
  scorer_.update(truth, static_cast<msg::LedColour>(outputs_.led));
  if (t >= next_trace_ns_) {
    next_trace_ns_ += options_.trace_period_ns;
    path_.push_back(truth.pose);
  }
  if (scorer_.done() || core::ns_to_sec(t) >= options_.max_time_s) {
    over_ = true;
    path_.push_back(truth.pose);
  }
  if (step_observer_) step_observer_();
  return !over_;
}

void LockstepRunner::stop() {
  if (over_) return;
  scorer_.finish(core::ns_to_sec(clock_.now_ns()));
  over_ = true;
  path_.push_back(model_.truth().pose);
}

RunOutcome LockstepRunner::run() {
  while (step()) {
  }
  RunOutcome out;
  out.score = scorer_.result();
  out.end_ns = clock_.now_ns();
  out.steps = steps_;
  out.trajectory_hash = hash_;
  return out;
}

}  // namespace coxswain::sim::runner
