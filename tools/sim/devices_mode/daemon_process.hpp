// SPDX-License-Identifier: Apache-2.0
#pragma once
// The unmodified coxswain daemon as a child process of the simulator, and what it says: every
// line of its log output (stderr) is stamped on arrival with the steady clock, kept, copied to a
// file, and the lines the simulator acts on are parsed (device health changes, mission
// transitions, "mission finished", per-device counters, tick overruns). An arrival stamp is never
// earlier than the daemon's own: latencies measured with it are upper bounds.
#include <sys/types.h>

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "coxswain/core/time.hpp"

namespace coxswain::sim::devices_mode {

/// One log line of the daemon with its arrival time (core::SteadyClock ns).
struct LogLine {
  core::TimeNs stamp_ns = 0;
  std::string text;
};

/// A parsed "mission: FROM -> TO: reason" line.
struct MissionTransition {
  core::TimeNs stamp_ns = 0;
  std::string from;
  std::string to;
  std::string reason;
};

/// What the daemon reported so far (parsed from its log).
struct DaemonReport {
  std::map<std::string, std::string> device_state;  // device -> last health state logged
  std::map<std::string, double> device_rate_hz;     // device -> rate of its last counters line
  std::vector<MissionTransition> transitions;
  bool finished = false;  // "mission finished after ..."
  bool started = false;  // "coxswain ... starting": its stop signals are handled in order from here
  std::uint64_t window_overruns = 0;         // sum of the periodic "tick: ... overruns N" windows
  double worst_tick_p99_ms = 0.0;            // largest p99 tick duration of a window
  double worst_tick_max_ms = 0.0;            // largest tick duration of a window
  std::optional<std::uint64_t> total_ticks;  // from the final "stopping" line
  std::optional<std::uint64_t> total_overruns;  // from the final "stopping" line
};

/// Parses one daemon log line into `report` (stamped `stamp_ns`). Exposed for tests.
void parse_daemon_line(const std::string& line, core::TimeNs stamp_ns, DaemonReport& report);

/// Starts `argv` (argv[0] = the program path) with stderr and stdout piped to a reader thread.
/// The child gets SIGTERM when the simulator dies (PR_SET_PDEATHSIG), so no daemon is left
/// behind. Thread-safety: every public method may be called from any thread.
class DaemonProcess {
 public:
  /// Throws std::system_error when the pipe or the process cannot be made. Lines are appended
  /// to `log_copy` (when not empty) and echoed to stderr when `echo`.
  DaemonProcess(const std::vector<std::string>& argv, const std::filesystem::path& log_copy,
                bool echo);
  /// Stops the daemon (stop()) and the reader.
  ~DaemonProcess();
  DaemonProcess(const DaemonProcess&) = delete;
  DaemonProcess& operator=(const DaemonProcess&) = delete;

  /// Waits (within `grace`) until the daemon has said it is starting, so its stop is an orderly
  /// one, then SIGTERM, and waits up to the rest of `grace` for the exit (SIGKILL after). Returns
  /// the exit status (as from waitpid's WEXITSTATUS, 128+signal when killed). Idempotent.
  int stop(std::chrono::milliseconds grace = std::chrono::milliseconds(8000));
  /// True once the daemon's output ended (it exited or closed stderr).
  [[nodiscard]] bool output_closed() const;
  [[nodiscard]] pid_t pid() const { return pid_; }

  [[nodiscard]] DaemonReport report() const;
  [[nodiscard]] std::size_t line_count() const;
  [[nodiscard]] std::vector<LogLine> lines() const;
  /// Waits until a line at index >= `from` satisfies `pred` (or `timeout` passes, or the output
  /// ends); returns it and its index.
  std::optional<std::pair<std::size_t, LogLine>> wait_for(
      std::size_t from, const std::function<bool(const std::string&)>& pred,
      std::chrono::milliseconds timeout) const;

 private:
  void read_loop(int fd);

  pid_t pid_ = -1;
  bool echo_;
  std::ofstream log_copy_;
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  std::vector<LogLine> lines_;
  DaemonReport report_;
  bool closed_ = false;
  bool reaped_ = false;
  int exit_status_ = 0;
  std::thread reader_;
};

}  // namespace coxswain::sim::devices_mode
