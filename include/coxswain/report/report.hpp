// SPDX-License-Identifier: Apache-2.0
#pragma once
// `coxswain report RUN.mcap`: the postmortem report, one self-contained HTML file (data and
// drawing script inline, no network, no external fonts or scripts). The run is replayed through
// the mission core (replay::replay, bit-exact with the recording) to recover what the tick
// record does not hold: pose, desired heading, transition reasons, obstacle segments. Plots:
// track on the course (the course geometry when the recording holds Metadata "course", else the
// lidar segments the core saw), heading vs desired heading, thrust and servo pulses, speed, the
// state-machine timeline with transition reasons, device health and rates, tick timing and GNSS
// quality. After drawing, the page's script marks each plot element (class "plot") with
// data-rendered="true" and data-points="N". Thread-safety: none; pure apart from file I/O.
#include <filesystem>
#include <ostream>
#include <string>

#include "coxswain/config/config.hpp"
#include "coxswain/replay/replay.hpp"

namespace coxswain::report {

/// The ids of the plots the page draws (each an element with class "plot").
inline constexpr const char* kPlotIds[] = {"track",  "heading", "pulses", "speed",
                                           "states", "health",  "timing", "gnss"};

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
