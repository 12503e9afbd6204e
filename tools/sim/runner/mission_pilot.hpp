// SPDX-License-Identifier: Apache-2.0
#pragma once
// The daemon's tick in the simulator: runner::Pilot backed by the real mission::MissionCore (the
// same core, configuration and snapshot path the daemon's tick thread uses). Keeps the last
// CoreOutput and every state transition (for result.json). Deterministic; runner thread only.
// The transition log grows with the run (a host-side record, not the pure core).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "coxswain/config/config.hpp"
#include "coxswain/mission/mission_core.hpp"
#include "sim/runner/pilot.hpp"

namespace coxswain::sim::runner {

class RunRecorder;  // sim/runner/recording.hpp

/// One logged state transition, as text.
struct TransitionRecord {
  double t_s = 0.0;
  std::string from;
  std::string to;
  std::string reason;
};

class MissionPilot final : public Pilot {
 public:
  /// Throws std::invalid_argument when the mission core rejects `config`.
  explicit MissionPilot(const config::Configuration& config);
  void step(const core::Snapshot& snapshot, core::TimeNs now_ns,
            msg::ActuatorCommand& out) override;

  /// Records every tick into `recorder` (null = no recording); it must outlive the run.
  void set_recorder(RunRecorder* recorder) { recorder_ = recorder; }
  /// A parameter set to apply before the next step, as the daemon applies a live request
  /// (MissionCore::apply_parameters between two steps); an applied set is recorded (/params).
  void request_parameters(const mission::TunableParameters& params) { requested_ = params; }
  /// What the last request came to: empty when applied, else why the core refused it.
  [[nodiscard]] const std::string& parameters_error() const { return parameters_error_; }
  [[nodiscard]] mission::TunableParameters parameters() const { return core_->parameters(); }
  [[nodiscard]] const mission::CoreOutput& output() const { return *out_; }
  [[nodiscard]] const mission::MissionCore& core() const { return *core_; }
  [[nodiscard]] const mission::MissionStatus& status() const { return out_->status; }
  [[nodiscard]] const std::vector<TransitionRecord>& transitions() const { return transitions_; }
  /// True while the current task looks through the camera (course 1, course 2, docking).
  [[nodiscard]] bool camera_wanted() const;
  /// Time of the first tick the status reported `holding` after `since_ns` (kNeverNs = none).
  [[nodiscard]] core::TimeNs first_hold_after(core::TimeNs since_ns) const;

 private:
  config::MissionConfig mission_;
  std::unique_ptr<mission::MissionCore> core_;
  std::unique_ptr<mission::CoreOutput> out_;
  std::vector<TransitionRecord> transitions_;
  std::vector<core::TimeNs> hold_entries_;
  bool was_holding_ = false;
  RunRecorder* recorder_ = nullptr;
  std::optional<mission::TunableParameters> requested_;
  std::string parameters_error_;
};

}  // namespace coxswain::sim::runner
