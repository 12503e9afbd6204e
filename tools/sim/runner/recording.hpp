// SPDX-License-Identifier: Apache-2.0
#pragma once
// The simulator's flight recording (`coxswain-sim run ... --record FILE.mcap`): the same
// record::Recorder, channels and effective-config metadata the daemon writes, plus Metadata
// "course" (the course geometry as JSON, for `coxswain report`) and, at the end, "judge" (the
// score). In lockstep the virtual clock
// runs far faster than any polling thread, so the runner calls sample() after every step (no
// sampler thread) and each tick waits (real time, bounded) until the tick queue has
// room: every input replay needs is in the file, and the trajectory stays bit-identical (the wait
// never touches the simulation). Runner thread only.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "coxswain/config/config.hpp"
#include "coxswain/core/clock.hpp"
#include "coxswain/core/latest_store.hpp"
#include "coxswain/mission/mission_core.hpp"
#include "coxswain/record/recorder.hpp"
#include "sim/world/world.hpp"

namespace coxswain::sim::runner {

/// The course geometry as the JSON of Metadata "course" (FORMAT.md): navigation frame metres.
[[nodiscard]] std::string course_json(const world::World& world);

class RunRecorder {
 public:
  /// `store` and `clock` are the runner's (LockstepRunner::store()/clock()); they must outlive
  /// this. `course_json` may be empty.
  RunRecorder(std::filesystem::path path, const config::Configuration& config,
              const core::LatestStore& store, const core::Clock& clock,
              const std::string& course_json, const std::string& build_version);
  ~RunRecorder();
  RunRecorder(const RunRecorder&) = delete;
  RunRecorder& operator=(const RunRecorder&) = delete;

  /// Creates the file; false (with error()) when it cannot.
  bool start();
  /// Records one tick exactly as the daemon does (command, state path, viz).
  void record_tick(const core::Snapshot& snapshot, core::TimeNs now_ns,
                   const mission::CoreOutput& out);
  /// Records a parameter set applied before the next record_tick() (the daemon's /params).
  void record_parameters(const mission::TunableParameters& params, core::TimeNs now_ns);
  /// Takes every new store value into the recording (the recorder runs no sampler thread here:
  /// virtual time would outrun it and lose IMU samples). Call after every LockstepRunner step
  /// (LockstepRunner::set_step_observer); waits (real time, bounded) for queue room first.
  void sample();
  /// Finishes the file; a non-empty `judge_json` (the judge's verdict on the run, known only at
  /// its end) becomes Metadata "judge" (key "json") after the last message. Returns the
  /// recorder's final statistics.
  record::RecorderStats stop(const std::string& judge_json = {});
  [[nodiscard]] std::string error() const;

 private:
  void wait_for_sampler(const core::Snapshot& snapshot);

  config::BoatConfig boat_;
  std::unique_ptr<record::Recorder> recorder_;
  std::unique_ptr<record::TickViz> viz_;
  std::uint64_t tick_index_ = 0;
  bool started_ = false;
};

}  // namespace coxswain::sim::runner
