// SPDX-License-Identifier: Apache-2.0
#pragma once
// systemd Type=notify support through libsystemd's sd_notify: READY, STATUS, WATCHDOG, STOPPING.
// When not started by systemd (no NOTIFY_SOCKET) every call is a cheap no-op.
#include <string_view>

#include "coxswain/core/time.hpp"

namespace coxswain::app {

/// Thread-safe (sd_notify opens a fresh datagram per call).
class SystemdNotifier {
 public:
  SystemdNotifier();
  [[nodiscard]] bool enabled() const { return enabled_; }
  /// Watchdog interval systemd expects (WatchdogSec), 0 when the watchdog is off.
  [[nodiscard]] core::TimeNs watchdog_interval_ns() const { return watchdog_ns_; }
  bool ready() const;
  bool status(std::string_view text) const;
  bool watchdog() const;
  bool stopping() const;

 private:
  bool send(std::string_view state) const;
  bool enabled_ = false;
  core::TimeNs watchdog_ns_ = 0;
};

}  // namespace coxswain::app
