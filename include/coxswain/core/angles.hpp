// SPDX-License-Identifier: Apache-2.0
#pragma once
// The one place angles are wrapped. Convention (docs/conventions.md): headings and bearings in
// degrees, 0 = north (or the bow), clockwise (to starboard) positive, range (-180, 180].
#include <numbers>

namespace coxswain::core {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kDegPerRad = 180.0 / std::numbers::pi;
inline constexpr double kRadPerDeg = std::numbers::pi / 180.0;

[[nodiscard]] constexpr double deg_to_rad(double angle_deg) { return angle_deg * kRadPerDeg; }
[[nodiscard]] constexpr double rad_to_deg(double angle_rad) { return angle_rad * kDegPerRad; }

/// Wraps into (-180, 180]. Non-finite input is returned unchanged.
[[nodiscard]] double wrap_deg(double angle_deg);
/// Wraps into (-pi, pi]. Non-finite input is returned unchanged.
[[nodiscard]] double wrap_rad(double angle_rad);
/// Wraps into [0, 360): for sensor angles that are reported that way (lidar, compass).
[[nodiscard]] double wrap_deg_360(double angle_deg);

/// Signed shortest turn from `from_deg` to `to_deg`, in (-180, 180]; positive = to starboard.
[[nodiscard]] inline double angle_diff_deg(double to_deg, double from_deg) {
  return wrap_deg(to_deg - from_deg);
}

/// Wrap-safe mean of angles: accumulates unit vectors, so 179 and -179 average to 180, not 0.
/// Plain value type, no allocation.
class CircularMean {
 public:
  void add(double angle_deg, double weight = 1.0);
  void reset() { *this = CircularMean{}; }
  [[nodiscard]] bool empty() const { return weight_sum_ <= 0.0; }
  /// Mean in (-180, 180]; 0 when empty or when the vectors cancel.
  [[nodiscard]] double mean_deg() const;
  /// Mean resultant length in [0, 1]: 1 = all angles equal, 0 = spread evenly.
  [[nodiscard]] double concentration() const;

 private:
  double sum_sin_ = 0.0;
  double sum_cos_ = 0.0;
  double weight_sum_ = 0.0;
};

}  // namespace coxswain::core
