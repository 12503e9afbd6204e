// SPDX-License-Identifier: Apache-2.0
#pragma once
// The operator's command language, shared by the control socket (`coxswain ctl`), the status
// page's buttons and the daemon's --target option: parsing, turning commands into the store's
// OperatorInput and the `status` answer (the tunable parameters' table is in
// mission/tunable_parameters.hpp). Pure functions and plain values; thread-safe as values
// (OperatorState has one owner: the control thread).
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "coxswain/core/latest_store.hpp"
#include "coxswain/mission/mission_core.hpp"
#include "coxswain/msg/camera_detections.hpp"
#include "coxswain/msg/operator_input.hpp"

namespace coxswain::live {

/// kParams asks for the parameters in force (the answer `coxswain ctl save-params` writes out).
enum class CommandKind : std::uint8_t { kStart, kHold, kResume, kTarget, kStatus, kParams };

struct ControlCommand {
  CommandKind kind = CommandKind::kStatus;
  msg::Colour colour = msg::Colour::kUnknown;  // kTarget only
  msg::Shape shape = msg::Shape::kUnknown;     // kTarget only
};

/// "red" -> kRed; empty when unknown ("unknown" itself is refused: a target names something).
[[nodiscard]] std::optional<msg::Colour> parse_colour(std::string_view name);
[[nodiscard]] std::optional<msg::Shape> parse_shape(std::string_view name);

/// One line: `start`, `hold`, `resume`, `target <colour> <shape>`, `status` or `params`
/// (case-sensitive,
/// blanks around words ignored). Empty with `error` set when the line is not a command.
[[nodiscard]] std::optional<ControlCommand> parse_command(std::string_view line,
                                                          std::string& error);

/// The operator's requests so far. Each start/hold/resume bumps its counter so the core acts on
/// every press exactly once. Not thread-safe: the control thread owns it.
class OperatorState {
 public:
  /// Applies a command other than kStatus; returns the value to publish.
  const msg::OperatorInput& apply(const ControlCommand& command, core::TimeNs now_ns);
  [[nodiscard]] const msg::OperatorInput& current() const { return input_; }

 private:
  msg::OperatorInput input_;
};

/// What the tick thread hands to the live server each tick (trivially copyable: it crosses
/// threads through a core::LatestSlot).
struct TickSummary {
  std::uint64_t tick_index = 0;
  mission::MissionStatus status;
};

/// The `status` answer, one JSON object on one line (no newline): state path, holding and its
/// reason, what the start waits for, the operator's requests, and each device's health with an
/// overall `devices_ok` (every enabled device running). `tick` may be invalid (before the first
/// tick: state_path "starting").
[[nodiscard]] std::string status_json(const core::Sample<TickSummary>& tick,
                                      const msg::OperatorInput& operator_input,
                                      const core::Snapshot& devices, core::TimeNs now_ns);

/// Constant-time comparison of a presented token with the configured one (length leaks only).
/// An empty configured token never matches.
[[nodiscard]] bool token_matches(std::string_view configured, std::string_view presented);

}  // namespace coxswain::live
