// SPDX-License-Identifier: Apache-2.0
#pragma once
// Test helper: records a lockstep simulator run of a shipped course with the mission core as
// pilot (ideal IMU and GNSS, the simulated RPLIDAR), the way `coxswain-sim run --record` does.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "coxswain/config/config.hpp"
#include "coxswain/mission/mission_core.hpp"

namespace coxswain::test {

/// The shipped boat, devices and `mission` (a name under config/missions/).
config::Configuration shipped_config(const std::string& mission);

struct SimRecordingResult {
  bool ok = false;
  std::string error;
  std::uint64_t ticks = 0;
  std::uint64_t dropped = 0;     // messages the recorder dropped (all channels)
  std::string parameters_error;  // a requested parameter change the core refused
};

/// A parameter change during the run, applied between two steps as a live request would be.
struct ParameterChange {
  double at_s = 0.0;
  std::function<void(mission::TunableParameters&)> edit;
};

/// Sails `course` (a file under config/courses/) for `seconds` of virtual time with `config`,
/// recording to `mcap`; `change` (optional) retunes the core once during the run.
SimRecordingResult record_sim_run(const std::filesystem::path& mcap,
                                  const config::Configuration& config, const std::string& course,
                                  double seconds,
                                  const std::optional<ParameterChange>& change = std::nullopt);

}  // namespace coxswain::test
