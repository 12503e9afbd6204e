// SPDX-License-Identifier: Apache-2.0
#pragma once
// GPS offset calibration at the start point (docs/missions.md; the KABOAT 2022 report 5.1.2): the
// organisers' points are taken as exact, the boat sits on the known start point, and the mean
// offset of its fixes from that point is subtracted from every later fix. The receiver was seen
// biased 5-10 m, all points shifted one way.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "coxswain/core/frames.hpp"

namespace coxswain::guidance {

struct GpsCalibrationParams {
  std::size_t min_fixes = 20;  // fewer: refuse (at 5 Hz, 4 s on the start point)
  std::size_t window = 50;     // the last `window` fixes are used, <= kMaxFixes
  double max_spread_m = 1.5;   // a fix farther than this from the mean: boat moving or bad GPS
  double max_offset_m = 25.0;  // a larger offset means the wrong start point or frame: refuse

  [[nodiscard]] std::optional<std::string> validate() const;
};

enum class CalibrationStatus : std::uint8_t {
  kOk = 0,
  kTooFewFixes,
  kSpreadTooLarge,
  kOffsetTooLarge,
};

[[nodiscard]] const char* to_string(CalibrationStatus s);

/// The bias to remove: measured minus true, navigation frame metres.
struct GpsOffset {
  double north_m = 0.0;
  double east_m = 0.0;
  [[nodiscard]] core::NavPoint apply(core::NavPoint measured) const {
    return {measured.north_m - north_m, measured.east_m - east_m};
  }
};

struct CalibrationResult {
  CalibrationStatus status = CalibrationStatus::kTooFewFixes;
  GpsOffset offset;  // valid only when status == kOk
  std::size_t fix_count = 0;
  double spread_m = 0.0;  // largest distance of a fix from the mean
};

/// Collects fixes (already in the navigation frame, from usable fixes only) in a fixed ring and
/// computes the offset on demand. Plain value, no allocation, not thread-safe.
class GpsCalibration {
 public:
  static constexpr std::size_t kMaxFixes = 256;

  explicit GpsCalibration(GpsCalibrationParams p = {}, core::NavPoint known_start = {});
  void add(core::NavPoint measured);
  void reset() {
    count_ = 0;
    head_ = 0;
  }
  [[nodiscard]] CalibrationResult result() const;

 private:
  GpsCalibrationParams p_;
  core::NavPoint start_;
  std::array<core::NavPoint, kMaxFixes> fixes_{};
  std::size_t window_;
  std::size_t head_ = 0;
  std::size_t count_ = 0;
};

}  // namespace coxswain::guidance
