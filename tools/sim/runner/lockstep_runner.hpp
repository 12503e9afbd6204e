// SPDX-License-Identifier: Apache-2.0
#pragma once
// The simulator in lockstep: one thread moves a ManualClock in fixed dynamics steps and, at each
// step, in this order: runs the pilot when a tick falls due (snapshot of the store in, command
// out), hands the latest command to the emulated Arduino when a command falls due (the shared
// drivers::arduino::FirmwareLogic with its failsafe, so a pilot that stops commanding gets
// neutral outputs after failsafe_ms exactly as on the boat), applies the firmware's outputs to the
// boat, integrates the dynamics, lets the sensor suite publish, and scores the new state. Nothing
// reads a real clock, so the same course, boat, options and seed give a bit-identical trajectory
// (trajectory_hash() folds every state of every step). Not thread-safe: one runner per thread;
// the World is shared read-only.
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "coxswain/config/config.hpp"
#include "coxswain/core/clock.hpp"
#include "coxswain/core/latest_store.hpp"
#include "coxswain/drivers/arduino/firmware_logic.hpp"
#include "sim/dynamics/boat_model.hpp"
#include "sim/runner/pilot.hpp"
#include "sim/runner/sensor_suite.hpp"
#include "sim/scoring/scorer.hpp"
#include "sim/world/collision.hpp"
#include "sim/world/course.hpp"

namespace coxswain::sim::runner {

struct RunnerOptions {
  std::uint64_t seed = 1;  // disturbances (sensors take their own)
  core::TimeNs dynamics_step_ns = 10 * core::kNsPerMs;
  double tick_rate_hz = 50.0;       // pilot (mission tick_rate_hz)
  double max_time_s = 900.0;        // hard stop when scoring never ends the run
  std::uint16_t failsafe_ms = 300;  // devices.yaml arduino.failsafe_ms
  bool boot_hold = false;           // emulate the firmware's 3 s ESC arming hold
  bool start_switch = true;         // state of the Arduino's start switch input
  core::TimeNs trace_period_ns = 100 * core::kNsPerMs;   // path decimation for pictures
  core::TimeNs status_period_ns = 100 * core::kNsPerMs;  // Arduino telemetry rate
  /// The hull stops at walls, docks and buoys (world::CollisionResponse) instead of passing
  /// through them; off only to reproduce runs of simulators before it.
  bool collision_response = true;
};

struct RunOutcome {
  scoring::ScoreResult score;
  core::TimeNs end_ns = 0;
  std::uint64_t steps = 0;
  std::uint64_t trajectory_hash = 0;
};

class LockstepRunner {
 public:
  /// `sensors` and `pilot` may be null (no sensing / neutral commands); they must outlive the
  /// runner. The course's environment and dynamics overrides apply.
  LockstepRunner(const world::Course& course, const config::BoatConfig& boat, RunnerOptions options,
                 SensorSuite* sensors, Pilot* pilot);
  ~LockstepRunner();
  LockstepRunner(const LockstepRunner&) = delete;
  LockstepRunner& operator=(const LockstepRunner&) = delete;

  /// One dynamics step. Returns false once the run is over (scored done or max_time_s).
  bool step();
  /// Steps until the run is over.
  RunOutcome run();
  /// Ends the run now (the boat stopped sailing): the judge settles the score at this time.
  void stop();

  /// Cuts (false) or restores (true) the serial link to the Arduino: while cut, commands do not
  /// reach the firmware, whose failsafe then neutralises the outputs after failsafe_ms.
  void set_command_link(bool up) { link_up_ = up; }
  /// Called at the end of every step(), after the sensors published (the flight recorder takes
  /// each new store value there). Empty = none.
  void set_step_observer(std::function<void()> observer) { step_observer_ = std::move(observer); }

  [[nodiscard]] const world::Course& course() const { return *course_; }
  [[nodiscard]] const config::BoatConfig& boat_config() const { return boat_; }
  [[nodiscard]] core::TimeNs now_ns() const { return clock_.now_ns(); }
  [[nodiscard]] const core::ManualClock& clock() const { return clock_; }
  [[nodiscard]] core::LatestStore& store() { return *store_; }
  [[nodiscard]] const dynamics::BoatModel& boat() const { return model_; }
  [[nodiscard]] dynamics::TruthState truth() const { return model_.truth(); }
  [[nodiscard]] const scoring::Scorer& scorer() const { return scorer_; }
  [[nodiscard]] const std::vector<core::NavPose>& path() const { return path_; }
  [[nodiscard]] std::uint64_t trajectory_hash() const { return hash_; }
  [[nodiscard]] const drivers::arduino::LogicOutputs& arduino_outputs() const { return outputs_; }

 private:
  const world::Course* course_;
  config::BoatConfig boat_;
  RunnerOptions options_;
  SensorSuite* sensors_;
  Pilot* pilot_;
  core::ManualClock clock_;
  std::unique_ptr<core::LatestStore> store_;
  std::unique_ptr<core::Snapshot> snapshot_;
  dynamics::BoatModel model_;
  scoring::Scorer scorer_;
  world::CollisionResponse collisions_;
  drivers::arduino::FirmwareLogic firmware_;
  drivers::arduino::LogicOutputs outputs_{};
  msg::ActuatorCommand command_;
  std::uint16_t command_seq_ = 0;
  core::TimeNs tick_period_ns_;
  core::TimeNs command_period_ns_;
  core::TimeNs next_tick_ns_ = 0;
  core::TimeNs next_command_ns_ = 0;
  core::TimeNs next_status_ns_ = 0;
  core::TimeNs next_trace_ns_ = 0;
  std::uint64_t steps_ = 0;
  std::function<void()> step_observer_;
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
  bool over_ = false;
  bool link_up_ = true;
  std::vector<core::NavPose> path_;
};

}  // namespace coxswain::sim::runner
