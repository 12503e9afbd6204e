// SPDX-License-Identifier: Apache-2.0
#pragma once
// Run directories named YYMMDD-HHMMSS-<mission>-NN as the source team did: NN counts the runs of
// that mission on that day (01, 02, ...), so a day's attempts sort and number themselves.
#include <ctime>
#include <filesystem>
#include <string>

namespace coxswain::app {

/// Creates and returns a new run directory under `base` for `mission` at local time `when`.
/// Throws std::filesystem::filesystem_error when `base` cannot be created.
std::filesystem::path create_run_dir(const std::filesystem::path& base, const std::string& mission,
                                     std::time_t when);

}  // namespace coxswain::app
