// SPDX-License-Identifier: Apache-2.0
// The batch tools' outside inputs: shard files read back by `coxswain-sim merge` (JSON lines) and
// parameter overlays (`--set-file`, flat YAML) and assignments (`--set KEY=VALUE`). Arbitrary
// bytes must give a result or an error, never a crash, and a rejected overlay changes nothing.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "coxswain/config/config.hpp"
#include "sim/batch/batch.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  {
    std::istringstream in(text);
    coxswain::sim::batch::Collected collected;
    std::string why;
    if (coxswain::sim::batch::read_lines(in, "fuzz", collected, &why, 1000)) {
      (void)coxswain::sim::batch::check_collected(collected);
      (void)coxswain::sim::batch::summarize(collected.runs, collected.kind, collected.baseline);
    }
  }
  coxswain::config::MissionConfig mission;
  const coxswain::config::MissionConfig before = mission;
  if (!coxswain::sim::batch::apply_overlay_text(mission, text, "fuzz").empty() &&
      (mission.avoidance.clearance_m != before.avoidance.clearance_m ||
       mission.heading_pid.kp_per_deg != before.heading_pid.kp_per_deg)) {
    std::abort();  // a rejected overlay must leave the mission as it was
  }
  (void)coxswain::sim::batch::set_parameter_assignment(mission, text);
  (void)coxswain::sim::batch::parse_shard(text, nullptr);
  return 0;
}
