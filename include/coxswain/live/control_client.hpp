// SPDX-License-Identifier: Apache-2.0
#pragma once
// The client side of the control socket, for `coxswain ctl`: finding the socket, sending one
// command line and reading its one-line answer. Blocking; any thread.
#include <filesystem>
#include <optional>
#include <string>

namespace coxswain::live {

/// Sends `line` (without newline) to the socket and returns the answer line (without newline),
/// or empty with `error` set (no socket, refused, no answer within timeout_s).
[[nodiscard]] std::optional<std::string> send_control_command(const std::filesystem::path& socket,
                                                              const std::string& line,
                                                              std::string& error,
                                                              double timeout_s = 5.0);

/// The control socket of the newest run under `log_dir` (<log_dir>/<run>/control.sock), the
/// default when neither --socket nor the configuration names one. Empty when there is none.
[[nodiscard]] std::filesystem::path newest_run_socket(const std::filesystem::path& log_dir);

/// Whether an answer line reports success (`"ok": true`, or a status object).
[[nodiscard]] bool answer_ok(const std::string& answer);

}  // namespace coxswain::live
