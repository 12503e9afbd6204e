// SPDX-License-Identifier: Apache-2.0
#pragma once
// One full lidar revolution, already turned into the body frame through the mount transform.
// Fixed capacity so a scan is copied, never allocated, on the hot path.
#include <array>
#include <cstddef>
#include <cstdint>

#include "coxswain/core/time.hpp"

namespace coxswain::msg {

struct LidarPoint {
  float bearing_deg = 0.0F;  // body frame, 0 = bow, + starboard, (-180, 180]
  float range_m = 0.0F;      // 0 = no return
  std::uint8_t quality = 0;  // 0..255 (RPLIDAR standard quality is scaled x4)
  /// Time of this sample after the scan's first sample, for motion de-skew.
  std::int32_t offset_us = 0;
};

struct LidarScan {
  /// Enough for a 10 Hz revolution at 32 kSa/s (S2 dense) with headroom.
  static constexpr std::size_t kMaxPoints = 4096;

  core::TimeNs stamp_ns = core::kNeverNs;  // arrival of the first byte of the first sample
  core::TimeNs duration_ns = 0;            // first to last sample
  float max_range_m = 0.0F;                // model limit from GET_INFO / config
  float min_range_m = 0.0F;
  std::uint32_t revolution = 0;  // counts revolutions since the driver started
  std::uint32_t point_count = 0;
  /// Sorted by bearing ascending; the seam lies astern (see drivers/rplidar/scan_assembler.hpp).
  std::array<LidarPoint, kMaxPoints> points{};

  [[nodiscard]] bool push(const LidarPoint& p) {
    if (point_count >= kMaxPoints) return false;
    points[point_count++] = p;
    return true;
  }
  void clear() { point_count = 0; }
};

}  // namespace coxswain::msg
