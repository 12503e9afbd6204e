// SPDX-License-Identifier: Apache-2.0
#pragma once
// One time type for the whole project: signed 64-bit nanoseconds of the steady clock.
// Wall time appears only in log lines and file names, never in decisions.
#include <cstdint>

namespace coxswain::core {

/// Nanoseconds on the steady (monotonic) clock. Every stamp in every message uses it.
using TimeNs = std::int64_t;

inline constexpr TimeNs kNsPerUs = 1'000;
inline constexpr TimeNs kNsPerMs = 1'000'000;
inline constexpr TimeNs kNsPerSec = 1'000'000'000;
/// Marks "never happened" (a slot that was never written, a device never seen).
inline constexpr TimeNs kNeverNs = INT64_MIN;

[[nodiscard]] constexpr double ns_to_sec(TimeNs t_ns) {
  return static_cast<double>(t_ns) / static_cast<double>(kNsPerSec);
}
[[nodiscard]] constexpr TimeNs sec_to_ns(double t_s) {
  return static_cast<TimeNs>(t_s * static_cast<double>(kNsPerSec));
}
[[nodiscard]] constexpr TimeNs ms_to_ns(std::int64_t t_ms) { return t_ms * kNsPerMs; }

}  // namespace coxswain::core
