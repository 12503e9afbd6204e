// SPDX-License-Identifier: Apache-2.0
#pragma once
// myAHRS+ request encoder and start-up plan. Protocol: docs/protocols.md section 2.2
// (framing, checksum) and 2.3 (commands, suggested start-up).
//
// A request is `@name[,arg...]*CC\r\n` with CC = XOR of every byte from '@' up to '*', as two
// upper-case hex digits. The device answers `~name,OK,...` or `~name,ERROR`.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "coxswain/drivers/myahrs/codec.hpp"

namespace coxswain::drivers::myahrs {

inline constexpr std::size_t kMaxCommandBytes = 96;
/// Highest output rate; actual rate = kMaxRateHz / divider (docs/protocols.md 2.1).
inline constexpr double kMaxRateHz = 100.0;
inline constexpr int kMaxDivider = 1000;

/// One encoded request, ready to write. Plain value, fixed capacity.
struct EncodedCommand {
  std::array<char, kMaxCommandBytes> bytes{};
  std::size_t size = 0;

  [[nodiscard]] std::string_view text() const { return {bytes.data(), size}; }
  [[nodiscard]] std::span<const std::uint8_t> data() const {
    return {reinterpret_cast<const std::uint8_t*>(bytes.data()), size};
  }
  /// The command name without '@' (what the `~` response echoes).
  [[nodiscard]] std::string_view name() const;
};

/// `@name[,args]*CC\r\n`. `args` is appended after one comma as given (it may itself hold commas,
/// e.g. "EULER, IMU"). nullopt when the name is empty or holds anything but [a-z0-9_], when a
/// byte is outside printable ASCII or is one of `$ ~ @ *`, or when the result does not fit.
[[nodiscard]] std::optional<EncodedCommand> encode_request(std::string_view name,
                                                           std::string_view args = {});

enum class OutputForm : std::uint8_t { kAscii, kBinary };
enum class Content : std::uint8_t { kRpyImu, kQuatImu };

/// `@mode,<letters>`: letters from {A, B, C, T}, 1 or 2 of them (e.g. "T", "AC", "BC").
[[nodiscard]] std::optional<EncodedCommand> mode_command(std::string_view letters);
/// `@mode,AC` / `@mode,BC`: continuous output in the given form.
[[nodiscard]] EncodedCommand continuous_mode_command(OutputForm form);
/// `@asc_out,RPYIMU` / `@asc_out,QUATIMU`.
[[nodiscard]] EncodedCommand asc_out_command(Content content);
/// `@bin_out,EULER, IMU` / `@bin_out,QUATERNION, IMU` (spelled as the ROS driver sends it).
[[nodiscard]] EncodedCommand bin_out_command(Content content);
/// `@divider,N`, N in [1, kMaxDivider]; nullopt outside.
[[nodiscard]] std::optional<EncodedCommand> divider_command(int divider);
[[nodiscard]] EncodedCommand version_command();
/// `@trig`: one data message in trigger mode (the device answers with data, not `~trig`).
[[nodiscard]] EncodedCommand trig_command();

/// Divider for a wanted rate: round(kMaxRateHz / rate_hz) clamped to [1, kMaxDivider].
/// Non-finite or non-positive rates give 1.
[[nodiscard]] int divider_for_rate(double rate_hz);

/// What to ask the sensor for at start-up. Volatile settings, so sent at every connect.
struct StartupParams {
  OutputForm form = OutputForm::kAscii;  // ASCII is easier to debug on a terminal
  double rate_hz = 100.0;                // (0, 100]; rounded to 100 / integer divider
  Content content = Content::kRpyImu;    // RPYIMU: yaw directly, no quaternion conversion

  /// Empty when valid, else the problem.
  [[nodiscard]] std::optional<std::string> validate() const;
};

/// One start-up step: send `command`, then wait (the SDK waits up to 500 ms) for the `~`
/// response whose name is `awaits` and whose status is OK.
struct StartupStep {
  EncodedCommand command;
  std::string_view awaits;  // e.g. "mode" for `~mode,OK,...`
};

/// The ordered start-up exchange. Fixed capacity; plain value.
struct StartupPlan {
  static constexpr std::size_t kMaxSteps = 8;
  std::array<StartupStep, kMaxSteps> steps{};
  std::size_t count = 0;

  [[nodiscard]] std::span<const StartupStep> view() const { return {steps.data(), count}; }
};

/// Quiet the stream first (`@mode,T`, as the SDK's resync does, so responses do not interleave
/// with 100 Hz data), read `@version` for the log, set `@divider`, the output format
/// (`@asc_out` or `@bin_out`), then start continuous output in the chosen form (`@mode,AC|BC`).
/// Params must be valid (see validate()); invalid rates are clamped like divider_for_rate().
[[nodiscard]] StartupPlan make_startup_plan(const StartupParams& params);

/// True when `response` is the OK answer the step waits for. An ERROR answer with the same
/// name is a failed step; anything else (data, other responses) is not the answer yet.
[[nodiscard]] bool is_awaited_ok(const StartupStep& step, const CommandResponse& response);

}  // namespace coxswain::drivers::myahrs
