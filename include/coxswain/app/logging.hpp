// SPDX-License-Identifier: Apache-2.0
#pragma once
// Asynchronous spdlog set-up: console plus a file in the run directory, and a tap that more sinks
// can join while the logger runs (the flight recorder's /log). The queue drops the oldest line
// rather than block, so logging can never stall the tick or a driver.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

namespace spdlog::sinks {
class sink;
}

namespace coxswain::app {

/// Parses "trace|debug|info|warn|error|critical|off"; nullopt for anything else.
std::optional<int> parse_log_level(const std::string& text);

/// Installs the default logger. `log_file` empty = console only. Call once, before threads start.
void setup_logging(const std::optional<std::filesystem::path>& log_file, int level);
/// Adds `sink` to the default logger's tap (thread-safe, any time after setup_logging): it then
/// gets every line at `level` or above, on the logging thread. False when the default logger has
/// no tap (setup_logging was not called).
bool attach_log_sink(const std::shared_ptr<spdlog::sinks::sink>& sink, int level);
/// Removes it again (thread-safe; lines already handed to it are not recalled).
void detach_log_sink(const std::shared_ptr<spdlog::sinks::sink>& sink);
/// Flushes and stops the logging thread.
void shutdown_logging();

}  // namespace coxswain::app
