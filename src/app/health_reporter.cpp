// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/health_reporter.hpp"

#include <spdlog/spdlog.h>

namespace coxswain::app {

void HealthReporter::set_origin(msg::DeviceId id, std::string origin) {
  const auto i = static_cast<std::size_t>(id);
  if (i < origin_.size()) origin_[i] = std::move(origin);
}

int HealthReporter::report_changes(const core::Snapshot& snapshot) {
  int changed = 0;
  for (std::size_t i = 0; i < snapshot.health.size(); ++i) {
    const auto& sample = snapshot.health[i];
    if (!sample.valid()) continue;
    const msg::DeviceHealth& h = sample.value;
    Last& last = last_[i];
    const std::string_view detail = h.detail_text();
    if (last.seen && last.state == h.state &&
        same_words(std::string_view(last.detail.data()), detail)) {
      continue;
    }
    const auto name = msg::device_name(static_cast<msg::DeviceId>(i));
    const auto state = msg::device_state_name(h.state);
    if (h.state == msg::DeviceState::kRunning || h.state == msg::DeviceState::kDisabled) {
      spdlog::info("device {}: {} ({})", name, state, detail);
    } else if ((h.state == msg::DeviceState::kAbsent || h.state == msg::DeviceState::kError) &&
               !origin_[i].empty()) {
      // A device that cannot be opened is often a configuration problem: say where it is set.
      spdlog::warn("device {}: {} ({}) [{}]", name, state, detail, origin_[i]);
    } else {
      spdlog::warn("device {}: {} ({})", name, state, detail);
    }
    last = Last{true, h.state, h.detail};
    ++changed;
  }
  return changed;
}

bool HealthReporter::same_words(std::string_view a, std::string_view b) {
  const auto numeric = [](char c) { return (c >= '0' && c <= '9') || c == '.'; };
  std::size_t i = 0;
  std::size_t j = 0;
  while (i < a.size() && j < b.size()) {
    if (numeric(a[i]) && numeric(b[j])) {
      while (i < a.size() && numeric(a[i])) ++i;
      while (j < b.size() && numeric(b[j])) ++j;
      continue;
    }
    if (a[i] != b[j]) return false;
    ++i;
    ++j;
  }
  return i == a.size() && j == b.size();
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
