// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "coxswain/core/time.hpp"

namespace coxswain::msg {

enum class DeviceId : std::uint8_t { kLidar = 0, kImu, kGnss, kArduino, kCamera };
inline constexpr std::size_t kDeviceCount = 5;

[[nodiscard]] constexpr std::string_view device_name(DeviceId id) {
  switch (id) {
    case DeviceId::kLidar:
      return "lidar";
    case DeviceId::kImu:
      return "imu";
    case DeviceId::kGnss:
      return "gnss";
    case DeviceId::kArduino:
      return "arduino";
    case DeviceId::kCamera:
      return "camera";
  }
  return "unknown";
}

enum class DeviceState : std::uint8_t {
  kDisabled = 0,  // not configured
  kAbsent,        // path does not exist / cannot be opened
  kPresent,       // device node exists, no driver has opened it yet
  kOpening,
  kConfiguring,
  kRunning,  // frames arriving
  kStale,    // open but silent for longer than its timeout
  kError,
};

[[nodiscard]] constexpr std::string_view device_state_name(DeviceState s) {
  switch (s) {
    case DeviceState::kDisabled:
      return "disabled";
    case DeviceState::kAbsent:
      return "absent";
    case DeviceState::kPresent:
      return "present";
    case DeviceState::kOpening:
      return "opening";
    case DeviceState::kConfiguring:
      return "configuring";
    case DeviceState::kRunning:
      return "running";
    case DeviceState::kStale:
      return "stale";
    case DeviceState::kError:
      return "error";
  }
  return "unknown";
}

/// Counters and state one driver keeps about its device. Trivially copyable (fixed-size text).
struct DeviceHealth {
  core::TimeNs stamp_ns = core::kNeverNs;  // when this health record was written
  DeviceId device = DeviceId::kLidar;
  DeviceState state = DeviceState::kDisabled;
  std::uint64_t bytes_received = 0;
  std::uint64_t frames_ok = 0;
  std::uint64_t checksum_errors = 0;
  std::uint64_t framing_errors = 0;  // garbage skipped, bad lengths, bad sync
  std::uint64_t dropped_frames = 0;
  std::uint32_t reopen_count = 0;
  core::TimeNs last_frame_ns = core::kNeverNs;
  double rate_hz = 0.0;            // decoded messages per second, recent window
  std::array<char, 192> detail{};  // last notable event, NUL-terminated

  void set_detail(std::string_view text) {
    const std::size_t n = text.size() < detail.size() - 1 ? text.size() : detail.size() - 1;
    for (std::size_t i = 0; i < n; ++i) detail[i] = text[i];
    detail[n] = '\0';
  }
  [[nodiscard]] std::string_view detail_text() const { return std::string_view(detail.data()); }
};

}  // namespace coxswain::msg
