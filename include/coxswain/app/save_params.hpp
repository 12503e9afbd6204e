// SPDX-License-Identifier: Apache-2.0
#pragma once
// `coxswain ctl save-params`: the daemon's parameters in force (its `params` answer on the
// control socket) written back as config files, so a venue's live tuning survives a restart.
// Both files are read back with their loaders before the command says it saved them.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace coxswain::app {

/// `mission_yaml` (a mission file's text) with each named live parameter ("heading_pid.kp_per_deg",
/// "avoidance.score.goal_weight": tunable_specs() names) set to its value, written as the file
/// writes it (booleans true/false, enumerations by name). Names that are not mission
/// parameters (vision.*) are left out. Empty with `error` set when the text is not a mission map.
[[nodiscard]] std::string mission_with_values(
    const std::string& mission_yaml, const std::vector<std::pair<std::string, double>>& values,
    std::string& error);

/// Writes the `params` answer `answer`: `vision_out` gets the vision file; `mission_out`, when
/// not empty, the daemon's mission file with the live values in place. Each file is loaded back
/// before returning. Empty when both were written and load, else why not.
[[nodiscard]] std::string save_params(const std::string& answer,
                                      const std::filesystem::path& vision_out,
                                      const std::filesystem::path& mission_out);

}  // namespace coxswain::app
