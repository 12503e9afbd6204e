// SPDX-License-Identifier: Apache-2.0
#pragma once
// Geodetic <-> navigation frame through GeographicLib's LocalCartesian (an exact ECEF-based local
// tangent plane), with X = north and Y = east at the chosen origin.
#include <memory>

#include "coxswain/core/frames.hpp"

namespace coxswain::core {

struct GeoPoint {
  double lat_deg = 0.0;
  double lon_deg = 0.0;
  double height_m = 0.0;  // ellipsoidal; 0 when unknown, which costs < 1 mm over a contest field
};

/// Converts between WGS-84 and the local navigation frame. Immutable after construction, so it is
/// safe to share between threads. Construction and conversion do not allocate after the first.
class LocalFrame {
 public:
  explicit LocalFrame(GeoPoint origin);
  ~LocalFrame();
  LocalFrame(const LocalFrame& other);
  LocalFrame& operator=(const LocalFrame& other);
  LocalFrame(LocalFrame&&) noexcept;
  LocalFrame& operator=(LocalFrame&&) noexcept;

  [[nodiscard]] const GeoPoint& origin() const { return origin_; }
  [[nodiscard]] NavPoint to_nav(const GeoPoint& p) const;
  [[nodiscard]] GeoPoint to_geo(NavPoint p, double height_m = 0.0) const;

 private:
  struct Impl;
  GeoPoint origin_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace coxswain::core
