// SPDX-License-Identifier: Apache-2.0
#include "sim/devices_mode/faults.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace coxswain::sim::devices_mode {
namespace {

constexpr std::array<FaultKind, 5> kKinds{FaultKind::kUnplug, FaultKind::kReset,
                                          FaultKind::kGarbage, FaultKind::kSilence,
                                          FaultKind::kBaud};

double parse_seconds(std::string_view text, std::string_view what, std::string_view spec) {
  double v = 0.0;
  const auto* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, v);
  if (text.empty() || ec != std::errc() || ptr != end || !std::isfinite(v) || v < 0.0) {
    throw std::invalid_argument("fault '" + std::string(spec) + "': " + std::string(what) + " '" +
                                std::string(text) + "' is not a number of seconds (0 or more)");
  }
  return v;
}

std::string device_list() {
  std::string s;
  for (msg::DeviceId id : kSerialDevices) {
    if (!s.empty()) s += ", ";
    s += msg::device_name(id);
  }
  return s;
}

std::string kind_list() {
  std::string s;
  for (FaultKind k : kKinds) {
    if (!s.empty()) s += ", ";
    s += fault_kind_name(k);
  }
  return s;
}

bool contains(const std::string& s, std::string_view what) {
  return s.find(what) != std::string::npos;
}

std::string format_s(double s) {
  char buf[32];
  (void)std::snprintf(buf, sizeof buf, "%.3g", s);
  return buf;
}

}  // namespace

std::string_view fault_kind_name(FaultKind kind) {
  switch (kind) {
    case FaultKind::kUnplug:
      return "unplug";
    case FaultKind::kReset:
      return "reset";
    case FaultKind::kGarbage:
      return "garbage";
    case FaultKind::kSilence:
      return "silence";
    case FaultKind::kBaud:
      return "baud";
  }
  return "?";
}

double default_fault_duration_s(FaultKind kind) {
  // A USB reset takes the device away for a moment; the others last long enough for every
  // device's staleness timeout (the GNSS's is 1.5 s) to fire.
  return kind == FaultKind::kReset ? 0.5 : 3.0;
}

FaultSpec parse_fault_spec(std::string_view spec) {
  const auto colon = spec.find(':');
  const auto at = spec.find('@');
  if (colon == std::string_view::npos || at == std::string_view::npos || at < colon) {
    throw std::invalid_argument("fault '" + std::string(spec) +
                                "': expected DEVICE:KIND@T[+DURATION], e.g. gnss:unplug@40+3");
  }
  FaultSpec f;
  const std::string_view device = spec.substr(0, colon);
  bool found = false;
  for (msg::DeviceId id : kSerialDevices) {
    if (device == msg::device_name(id)) {
      f.device = id;
      found = true;
    }
  }
  if (!found) {
    throw std::invalid_argument("fault '" + std::string(spec) + "': unknown device '" +
                                std::string(device) + "' (one of " + device_list() + ")");
  }
  const std::string_view kind = spec.substr(colon + 1, at - colon - 1);
  found = false;
  for (FaultKind k : kKinds) {
    if (kind == fault_kind_name(k)) {
      f.kind = k;
      found = true;
    }
  }
  if (!found) {
    throw std::invalid_argument("fault '" + std::string(spec) + "': unknown kind '" +
                                std::string(kind) + "' (one of " + kind_list() + ")");
  }
  std::string_view times = spec.substr(at + 1);
  const auto plus = times.find('+');
  f.at_s = parse_seconds(times.substr(0, plus), "time", spec);
  if (plus == std::string_view::npos) {
    f.duration_s = default_fault_duration_s(f.kind);
  } else {
    f.duration_s = parse_seconds(times.substr(plus + 1), "duration", spec);
    if (f.duration_s <= 0.0) {
      throw std::invalid_argument("fault '" + std::string(spec) +
                                  "': the duration must be more than 0 s");
    }
  }
  return f;
}

std::string fault_spec_text(const FaultSpec& spec) {
  return std::string(msg::device_name(spec.device)) + ":" +
         std::string(fault_kind_name(spec.kind)) + "@" + format_s(spec.at_s) + "+" +
         format_s(spec.duration_s);
}

void observe_fault(const std::vector<LogLine>& lines, FaultRecord& r, core::TimeNs until_ns) {
  if (!r.began_s) return;
  const std::string device = "device " + std::string(msg::device_name(r.spec.device)) + ": ";
  const core::TimeNs end_ns = r.ended_s ? r.ended_ns : r.began_ns;
  // Holds that begin after the fault's end plus a staleness timeout are not this fault's.
  const core::TimeNs hold_window_end_ns = end_ns + 3 * core::kNsPerSec;
  std::optional<std::size_t> hold_index;
  bool device_down = false;
  std::optional<core::TimeNs> back_ns;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const LogLine& l = lines[i];
    if (l.stamp_ns < r.began_ns) continue;
    if (l.stamp_ns >= until_ns) break;
    if (!hold_index && l.stamp_ns <= hold_window_end_ns && contains(l.text, "mission: ") &&
        contains(l.text, "-> hold/")) {
      hold_index = i;
      r.held_after_ms = static_cast<double>(l.stamp_ns - r.began_ns) * 1e-6;
    } else if (hold_index && !r.resumed_after_s && contains(l.text, "mission: ") &&
               contains(l.text, "resume: ")) {
      r.resumed_after_s = static_cast<double>(l.stamp_ns - end_ns) * 1e-9;
    }
    if (contains(l.text, device)) {
      if (contains(l.text, device + "running")) {
        if (device_down && !back_ns && (!r.ended_s || l.stamp_ns >= end_ns)) back_ns = l.stamp_ns;
      } else if (!back_ns) {
        device_down = true;
      }
    }
  }
  if (!r.ended_s) return;
  if (!device_down) {
    r.device_back_s = 0.0;  // it never left "running": ridden through
  } else if (back_ns) {
    r.device_back_s = static_cast<double>(*back_ns - end_ns) * 1e-9;
  }
}

std::string fault_summary_line(const FaultRecord& r) {
  std::string s = fault_spec_text(r.spec) + ": ";
  if (!r.began_s) return s + "not applied (the run ended first)";
  char buf[96];
  if (r.held_after_ms) {
    (void)std::snprintf(buf, sizeof buf, "held after %.0f ms", *r.held_after_ms);
    s += buf;
  } else {
    // The mission holds only for a device its task in progress needs (the circling of course 2
    // steers by the camera, not the lidar), so a fault may be ridden through.
    s += r.sailing_at_start ? "ridden through (no hold)" : "not sailing (no hold expected)";
  }
  if (!r.ended_s) return s + ", still on when the run ended";
  if (r.device_back_s) {
    (void)std::snprintf(buf, sizeof buf, ", device running %.1f s after the end", *r.device_back_s);
    s += buf;
  } else {
    s += ", device NOT back";
  }
  if (r.resumed_after_s) {
    (void)std::snprintf(buf, sizeof buf, ", resumed %.1f s after the end", *r.resumed_after_s);
    s += buf;
  } else if (r.held_after_ms) {
    s += ", NOT resumed";
  }
  return s;
}

bool fault_recovered(const FaultRecord& r) {
  if (!r.began_s || !r.ended_s || !r.device_back_s) return false;
  return !r.held_after_ms || r.resumed_after_s.has_value();
}

}  // namespace coxswain::sim::devices_mode
