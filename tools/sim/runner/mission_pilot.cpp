// SPDX-License-Identifier: Apache-2.0
#include "sim/runner/mission_pilot.hpp"

#include "sim/runner/recording.hpp"

namespace coxswain::sim::runner {

MissionPilot::MissionPilot(const config::Configuration& config)
    : mission_(config.mission),
      core_(std::make_unique<mission::MissionCore>(config.boat, config.mission,
                                                   config::magnetometer_of(config.devices.imu))),
      out_(std::make_unique<mission::CoreOutput>()) {}

void MissionPilot::step(const core::Snapshot& snapshot, core::TimeNs now_ns,
                        msg::ActuatorCommand& out) {
  if (requested_) {
    parameters_error_ = core_->apply_parameters(*requested_);
    requested_.reset();
    if (parameters_error_.empty() && recorder_ != nullptr) {
      recorder_->record_parameters(core_->parameters(), now_ns);
    }
  }
  core_->step(snapshot, now_ns, *out_);
  if (recorder_ != nullptr) recorder_->record_tick(snapshot, now_ns, *out_);
  out = out_->command;
  const auto& log = out_->transitions;
  for (std::uint32_t i = 0; i < log.count && i < mission::TransitionLog::kCapacity; ++i) {
    const auto& e = log.entries[i];
    transitions_.push_back({core::ns_to_sec(e.stamp_ns), std::string(e.from.view()),
                            std::string(e.to.view()), std::string(e.reason.view())});
  }
  if (out_->status.holding && !was_holding_) hold_entries_.push_back(now_ns);
  was_holding_ = out_->status.holding;
  core_->finish_tick();  // as the daemon does once the command is out
}

bool MissionPilot::camera_wanted() const {
  const auto& s = out_->status;
  if (!s.started || s.finished || s.task_index >= mission_.tasks.size()) return false;
  switch (mission_.tasks[s.task_index].type) {
    case config::TaskType::kCourse1:
    case config::TaskType::kCourse2:
    case config::TaskType::kDocking:
      return true;
    case config::TaskType::kHopping:
    case config::TaskType::kObstacleCourse:
      return false;
  }
  return false;
}

core::TimeNs MissionPilot::first_hold_after(core::TimeNs since_ns) const {
  for (core::TimeNs t : hold_entries_) {
    if (t >= since_ns) return t;
  }
  return core::kNeverNs;
}

}  // namespace coxswain::sim::runner
