// SPDX-License-Identifier: Apache-2.0
#pragma once
// Subcommand groups of coxswain-sim. Each adds its subcommands to `app`; a subcommand's callback
// stores the process exit code in `exit_code` (0 = success).
#include <CLI/CLI.hpp>

namespace coxswain::sim::app {

/// `course check FILE...`, `course generate --kind K --seed N -o FILE`, `course svg FILE -o OUT`,
/// `course drive FILE --servo-us S --thrust-us T --seconds N [--json OUT] [--svg OUT]`.
void add_course_commands(CLI::App& app, int& exit_code);

/// `run --course FILE --mission FILE [--seed N] [--sensors FILE] [--out DIR]` and
/// `batch --kind K --runs N [--seed0 S] [--jobs J] [--baseline]`.
void add_run_commands(CLI::App& app, int& exit_code);

/// `devices --course FILE [--mission FILE] [--boat FILE] [--seed N] [--run-dir DIR]
/// [--daemon PATH] [--time-limit S] [--quiet]`: the unmodified daemon against the device
/// emulators in real time (sim/devices_mode), scored.
void add_devices_command(CLI::App& app, int& exit_code);

/// `camera render --venue V --count N --seed S --out DIR`: labelled frames for `vision eval`.
void add_camera_commands(CLI::App& app, int& exit_code);

}  // namespace coxswain::sim::app
