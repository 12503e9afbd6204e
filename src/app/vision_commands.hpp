// SPDX-License-Identifier: Apache-2.0
#pragma once
// `coxswain vision eval DIR` and `coxswain vision calibrate DIR`: the tools to check and tune
// the camera detectors at the venue (see coxswain/app/vision_eval.hpp for the labels format).
#include <CLI/CLI.hpp>

namespace coxswain::app {

/// Adds the `vision` subcommand group to `app`; a subcommand's callback stores the process exit
/// code in `exit_code` (0 = success). Returns the group, so main can tell that it ran.
CLI::App* add_vision_commands(CLI::App& app, int& exit_code);

}  // namespace coxswain::app
