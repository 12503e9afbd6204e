// SPDX-License-Identifier: Apache-2.0
#pragma once
// What lidar perception hands to guidance: obstacles as line segments in the body frame, and the
// closest range per bearing bin. Fixed capacity, plain data.
#include <array>
#include <cstddef>
#include <cstdint>

#include "coxswain/core/frames.hpp"
#include "coxswain/core/time.hpp"

namespace coxswain::perception {

enum class ObstacleKind : std::uint8_t { kBuoy = 0, kWall = 1 };

/// A straight piece of an obstacle in the body frame (x forward, y starboard, metres).
struct ObstacleSegment {
  core::BodyPoint begin;
  core::BodyPoint end;
  ObstacleKind kind = ObstacleKind::kBuoy;
  float closest_range_m =
      0.0F;  // distance from the body origin to the nearest point of the segment
  std::uint16_t point_count = 0;  // lidar returns behind this segment
};

struct ObstacleList {
  static constexpr std::size_t kMaxSegments = 256;
  core::TimeNs stamp_ns = core::kNeverNs;  // the scan's stamp
  std::uint32_t count = 0;
  std::array<ObstacleSegment, kMaxSegments> segments{};

  [[nodiscard]] bool push(const ObstacleSegment& s) {
    if (count >= kMaxSegments) return false;
    segments[count++] = s;
    return true;
  }
  void clear() { count = 0; }
};

/// Closest return per bearing bin over the full circle, body frame. Bin i covers
/// [-180 + i * bin_width_deg, -180 + (i + 1) * bin_width_deg). Empty bins hold `kNoReturn`.
struct RangeProfile {
  static constexpr std::size_t kMaxBins = 720;
  static constexpr float kNoReturn = 1.0e9F;
  core::TimeNs stamp_ns = core::kNeverNs;
  float bin_width_deg = 1.0F;
  std::uint32_t bin_count = 360;
  std::array<float, kMaxBins> closest_range_m{};
};

}  // namespace coxswain::perception
