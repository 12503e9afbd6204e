// SPDX-License-Identifier: Apache-2.0
#pragma once
// `coxswain report RUN.mcap`: the postmortem report, one self-contained HTML file (data and
// drawing script inline, no network, no external fonts or scripts). The run is replayed through
// the mission core (replay::replay, bit-exact with the recording) to recover what the tick
// record does not hold: pose, desired heading, transition reasons, obstacle segments, the
// planner's path. On top: the mission, the date, the result and the score (the simulator
// judge's, Metadata "judge", when the recording has one; else the boat's own count). Plots: the
// track over the course map (the mission's geometry, and the simulator's course when the
// recording holds Metadata "course"), with the estimate before the start calibration drawn
// apart; heading vs desired heading, thrust and servo pulses, speed, the state-machine timeline
// with transition reasons, each device's rate on its own scale, battery/e-stop/RC/mode, tick
// timing and GNSS quality. Every time plot shares one zoom and one cursor (page_text.hpp).
// After drawing, the page's script marks each plot element (class "plot") with
// data-rendered="true" and data-points="N". Thread-safety: none; pure apart from file I/O.
#include <filesystem>
#include <ostream>
#include <string>

#include "coxswain/config/config.hpp"
#include "coxswain/replay/replay.hpp"

namespace coxswain::report {

/// The ids of the plots the page draws (each an element with class "plot").
inline constexpr const char* kPlotIds[] = {"track",  "heading", "pulses", "speed", "states",
                                           "health", "power",   "timing", "gnss"};

struct ReportResult {
  bool ok = false;
  std::string error;
  std::string html;
  replay::ReplayReport replay;  // how the replay went (a report of a non-identical replay says so)
};

/// Builds the report of `recording` replayed with `config`. `title` names the run.
[[nodiscard]] ReportResult build_report(const replay::Recording& recording,
                                        const config::Configuration& config,
                                        const std::string& title);

/// `coxswain report RUN.mcap [-o OUT]`: writes OUT (default RUN with .html). `config_override`
/// null = the recorded configuration. Exit 0 written, 1 cannot write, 2 unreadable recording.
int run_report_command(const std::filesystem::path& recording, std::filesystem::path output,
                       const config::Configuration* config_override, std::ostream& out,
                       std::ostream& err);

}  // namespace coxswain::report
