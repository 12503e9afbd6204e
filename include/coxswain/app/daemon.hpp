// SPDX-License-Identifier: Apache-2.0
#pragma once
// The daemon's run: wires the store, the device threads, the tick loop, signals and systemd.
#include <filesystem>
#include <string>

#include "coxswain/config/config.hpp"
#include "coxswain/msg/camera_detections.hpp"

namespace coxswain::app {

struct RunOptions {
  std::filesystem::path run_dir;      // already created; the log file and recordings go here
  double run_for_s = 0.0;             // > 0: stop by itself after this long (tests, demos)
  std::filesystem::path capture_dir;  // not empty: raw device bytes to <capture_dir>/<device>.raw
  bool record = true;                 // flight recording to <run_dir>/run.mcap
  std::string build_version;          // written into the recording
  bool stop_when_finished = false;    // end the run once the mission reports finished
  msg::Colour target_colour = msg::Colour::kUnknown;  // --target: the docking target from the
  msg::Shape target_shape = msg::Shape::kUnknown;     // command line (as `coxswain ctl target`)
};

/// Blocks SIGINT/SIGTERM in the calling thread and so in every thread started after it (the
/// logging thread included): run_daemon then waits for them on a thread of its own. Call first
/// thing in main, before any thread exists.
void block_stop_signals();

/// Runs until SIGINT/SIGTERM (or run_for_s). Returns the process exit status.
/// block_stop_signals() must have been called before any thread was started.
int run_daemon(const config::Configuration& config, const RunOptions& options);

}  // namespace coxswain::app
