// SPDX-License-Identifier: Apache-2.0
#pragma once
// Asynchronous spdlog set-up: console plus a file in the run directory. The queue drops the oldest
// line rather than block, so logging can never stall the tick or a driver.
#include <filesystem>
#include <optional>
#include <string>

namespace coxswain::app {

/// Parses "trace|debug|info|warn|error|critical|off"; nullopt for anything else.
std::optional<int> parse_log_level(const std::string& text);

/// Installs the default logger. `log_file` empty = console only. Call once, before threads start.
void setup_logging(const std::optional<std::filesystem::path>& log_file, int level);
/// Flushes and stops the logging thread.
void shutdown_logging();

}  // namespace coxswain::app
