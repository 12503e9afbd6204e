// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/systemd_notify.hpp"

#include <systemd/sd-daemon.h>

#include <cstdint>
#include <cstdlib>
#include <string>

namespace coxswain::app {

SystemdNotifier::SystemdNotifier() {
  const char* socket = std::getenv("NOTIFY_SOCKET");
  enabled_ = socket != nullptr && socket[0] != '\0';
  std::uint64_t usec = 0;
  if (sd_watchdog_enabled(0, &usec) > 0) watchdog_ns_ = static_cast<core::TimeNs>(usec) * 1000;
}

bool SystemdNotifier::send(std::string_view state) const {
  if (!enabled_) return false;
  const std::string text(state);
  return sd_notify(0, text.c_str()) > 0;
}

bool SystemdNotifier::ready() const { return send("READY=1"); }
bool SystemdNotifier::status(std::string_view text) const {
  std::string line = "STATUS=";
  for (char c : text) line += (c == '\n') ? ' ' : c;  // one line per STATUS
  return send(line);
}
bool SystemdNotifier::watchdog() const { return send("WATCHDOG=1"); }
bool SystemdNotifier::stopping() const { return send("STOPPING=1"); }

}  // namespace coxswain::app
