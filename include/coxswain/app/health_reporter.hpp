// SPDX-License-Identifier: Apache-2.0
#pragma once
// Turns the per-device health in a Snapshot into log lines: one line when a device's state or
// the words of its detail change (never one per tick, nor one per telemetry frame whose detail
// differs only in its numbers: a supply voltage, a sequence number), and a periodic counters
// line for every device. A device that cannot be opened (absent, error) is logged with where
// its path or source came from (the key and the file), once per outage.
#include <array>
#include <string>
#include <string_view>

#include "coxswain/core/latest_store.hpp"

namespace coxswain::app {

/// Not thread-safe: called from the tick thread only. Logging goes through spdlog's async logger.
class HealthReporter {
 public:
  /// Where device `id`'s path or source is set ("devices.gnss.path in /etc/coxswain/devices.yaml"),
  /// named in its absent and error lines. Call before the first report_changes().
  void set_origin(msg::DeviceId id, std::string origin);
  /// Logs changes since the previous call. Returns how many devices changed.
  int report_changes(const core::Snapshot& snapshot);
  /// Logs one counters line per enabled device.
  void report_counters(const core::Snapshot& snapshot, core::TimeNs now_ns) const;
  /// True when `a` and `b` differ at most in their numbers (runs of digits and '.'), so a
  /// detail that only re-measures is not a new line in the log. Allocates nothing.
  [[nodiscard]] static bool same_words(std::string_view a, std::string_view b);
  /// A one-line summary for systemd STATUS and the status page.
  [[nodiscard]] static std::string summary(const core::Snapshot& snapshot);

 private:
  struct Last {
    bool seen = false;
    msg::DeviceState state = msg::DeviceState::kDisabled;
    decltype(msg::DeviceHealth::detail) detail{};  // fixed size: no allocation per tick
  };
  std::array<Last, msg::kDeviceCount> last_{};
  std::array<std::string, msg::kDeviceCount> origin_{};
};

}  // namespace coxswain::app
