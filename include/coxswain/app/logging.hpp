// SPDX-License-Identifier: Apache-2.0
#pragma once
// Asynchronous spdlog set-up: console plus a size-capped rotating file in the run directory, and
// a tap that more sinks can join while the logger runs (the flight recorder's /log). The queue
// drops the oldest line rather than block, so logging can never stall the tick or a driver.
// Warnings and errors that repeat (the same words, numbers aside) are rate-limited in front of
// every sink, the tap included, so the console, the file and /log read the same: the first line
// passes, repeats within the window are counted, and when the window ends one line says
// "... N similar suppressed". Device state changes and mission transitions are never limited.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

namespace spdlog::sinks {
class sink;
}

namespace coxswain::app {

/// The decision logic of the repeat limiter (no I/O; times are the lines' own stamps).
/// Not thread-safe: the logging thread owns it.
class RepeatLimiter {
 public:
  using Clock = std::chrono::system_clock;
  /// `window`: how long after a line passes its repeats are counted instead of written.
  /// `max_keys`: distinct lines tracked at once; past it, new lines pass unlimited.
  explicit RepeatLimiter(std::chrono::nanoseconds window = std::chrono::seconds(10),
                         std::size_t max_keys = 512);
  /// Whether a line with this level and text is written now (true) or counted (false). A state
  /// change ("device ...", "mission: ...") is always written: each one is a line of the log.
  bool admit(int level, std::string_view text, Clock::time_point at);
  /// For every key whose window has ended with lines counted: calls `report(level, count,
  /// last_text)` and forgets the key (its next line passes and opens a new window).
  void expire(Clock::time_point now,
              const std::function<void(int, std::uint64_t, const std::string&)>& report);
  /// The same for every key, ended or not (at shutdown).
  void expire_all(const std::function<void(int, std::uint64_t, const std::string&)>& report);
  /// The text with every run of digits (and '.') replaced by '#': lines differing in their
  /// numbers only are "similar".
  [[nodiscard]] static std::string key_of(std::string_view text);

 private:
  struct Entry {
    Clock::time_point opened;
    std::uint64_t suppressed = 0;
    std::string last_text;
  };
  std::chrono::nanoseconds window_;
  std::size_t max_keys_;
  std::map<std::pair<int, std::string>, Entry> entries_;
};

/// The log file's size cap: `max_bytes` per file, `files` rotated copies kept (coxswain.1.log,
/// coxswain.2.log, ...), so a run's log never takes more than max_bytes * (files + 1).
struct LogFileLimits {
  std::size_t max_bytes = std::size_t{16} << 20U;
  std::size_t files = 4;
};

/// The lowest level the repeat limiter applies to (spdlog's warn).
inline constexpr int kRepeatLimitLevel = 3;

/// Parses "trace|debug|info|warn|error|critical|off"; nullopt for anything else.
std::optional<int> parse_log_level(const std::string& text);

/// Installs the default logger. `log_file` empty = console only. Call once, before threads start.
void setup_logging(const std::optional<std::filesystem::path>& log_file, int level,
                   const LogFileLimits& limits = {},
                   std::chrono::nanoseconds repeat_window = std::chrono::seconds(10));
/// Adds `sink` to the default logger's tap (thread-safe, any time after setup_logging): it then
/// gets every line at `level` or above, on the logging thread. False when the default logger has
/// no tap (setup_logging was not called).
bool attach_log_sink(const std::shared_ptr<spdlog::sinks::sink>& sink, int level);
/// Removes it again (thread-safe; lines already handed to it are not recalled).
void detach_log_sink(const std::shared_ptr<spdlog::sinks::sink>& sink);
/// Flushes and stops the logging thread.
void shutdown_logging();

}  // namespace coxswain::app
