// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/health_reporter.hpp"

#include <spdlog/spdlog.h>

namespace coxswain::app {

int HealthReporter::report_changes(const core::Snapshot& snapshot) {
  int changed = 0;
  for (std::size_t i = 0; i < snapshot.health.size(); ++i) {
    const auto& sample = snapshot.health[i];
    if (!sample.valid()) continue;
    const msg::DeviceHealth& h = sample.value;
    Last& last = last_[i];
    if (last.seen && last.state == h.state && last.detail == h.detail) continue;
    const std::string_view detail = h.detail_text();
    const auto name = msg::device_name(static_cast<msg::DeviceId>(i));
    const auto state = msg::device_state_name(h.state);
    if (h.state == msg::DeviceState::kRunning || h.state == msg::DeviceState::kDisabled) {
      spdlog::info("device {}: {} ({})", name, state, detail);
    } else {
      spdlog::warn("device {}: {} ({})", name, state, detail);
    }
    last = Last{true, h.state, h.detail};
    ++changed;
  }
  return changed;
}

void HealthReporter::report_counters(const core::Snapshot& snapshot, core::TimeNs now_ns) const {
  for (std::size_t i = 0; i < snapshot.health.size(); ++i) {
    const auto& sample = snapshot.health[i];
    if (!sample.valid() || sample.value.state == msg::DeviceState::kDisabled) continue;
    const msg::DeviceHealth& h = sample.value;
    const double age_s =
        h.last_frame_ns == core::kNeverNs ? -1.0 : core::ns_to_sec(now_ns - h.last_frame_ns);
    spdlog::info(
        "counters {}: state={} bytes={} frames={} rate={:.1f}Hz checksum_err={} framing_err={} "
        "dropped={} reopens={} last_frame_age={:.2f}s",
        msg::device_name(static_cast<msg::DeviceId>(i)), msg::device_state_name(h.state),
        h.bytes_received, h.frames_ok, h.rate_hz, h.checksum_errors, h.framing_errors,
        h.dropped_frames, h.reopen_count, age_s);
  }
}

std::string HealthReporter::summary(const core::Snapshot& snapshot) {
  std::string out;
  for (std::size_t i = 0; i < snapshot.health.size(); ++i) {
    const auto& sample = snapshot.health[i];
    if (!out.empty()) out += ' ';
    out += msg::device_name(static_cast<msg::DeviceId>(i));
    out += '=';
    out += sample.valid() ? msg::device_state_name(sample.value.state) : "unknown";
  }
  return out;
}

}  // namespace coxswain::app
