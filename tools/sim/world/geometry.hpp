// SPDX-License-Identifier: Apache-2.0
#pragma once
// Small planar geometry in the navigation frame (north, east metres) shared by the course loader,
// the generator and scoring. Header-only, pure.
#include <algorithm>
#include <cmath>
#include <vector>

#include "coxswain/core/frames.hpp"

namespace coxswain::sim::world {

inline double dot(core::NavPoint a, core::NavPoint b) {
  return a.north_m * b.north_m + a.east_m * b.east_m;
}
/// z of a x b with a, b as (north, east): positive when b lies clockwise (to starboard) of a.
inline double cross(core::NavPoint a, core::NavPoint b) {
  return a.north_m * b.east_m - a.east_m * b.north_m;
}
inline core::NavPoint sub(core::NavPoint a, core::NavPoint b) {
  return {a.north_m - b.north_m, a.east_m - b.east_m};
}
inline core::NavPoint add(core::NavPoint a, core::NavPoint b) {
  return {a.north_m + b.north_m, a.east_m + b.east_m};
}
inline core::NavPoint scale(core::NavPoint a, double k) { return {a.north_m * k, a.east_m * k}; }
/// Unit vector of a heading (0 = north, clockwise).
inline core::NavPoint heading_unit(double heading_deg) {
  const double h = heading_deg * 3.14159265358979323846 / 180.0;
  return {std::cos(h), std::sin(h)};
}

/// The point of segment a-b nearest p.
inline core::NavPoint nearest_on_segment(core::NavPoint p, core::NavPoint a, core::NavPoint b) {
  const core::NavPoint ab = sub(b, a);
  const double len2 = dot(ab, ab);
  double t = len2 > 0.0 ? dot(sub(p, a), ab) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return add(a, scale(ab, t));
}

/// Squared distance from p to the segment a-b (no square root, for broad phases).
inline double point_segment_distance2(core::NavPoint p, core::NavPoint a, core::NavPoint b) {
  const core::NavPoint d = sub(p, nearest_on_segment(p, a, b));
  return dot(d, d);
}

/// Distance from p to the segment a-b.
inline double point_segment_distance(core::NavPoint p, core::NavPoint a, core::NavPoint b) {
  const core::NavPoint q = nearest_on_segment(p, a, b);
  return std::hypot(p.north_m - q.north_m, p.east_m - q.east_m);
}

/// True when segments p1-p2 and q1-q2 intersect (touching counts).
inline bool segments_intersect(core::NavPoint p1, core::NavPoint p2, core::NavPoint q1,
                               core::NavPoint q2) {
  const double d1 = cross(sub(p2, p1), sub(q1, p1));
  const double d2 = cross(sub(p2, p1), sub(q2, p1));
  const double d3 = cross(sub(q2, q1), sub(p1, q1));
  const double d4 = cross(sub(q2, q1), sub(p2, q1));
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) {
    return true;
  }
  auto on = [](core::NavPoint a, core::NavPoint b, core::NavPoint p, double d) {
    return d == 0.0 && std::min(a.north_m, b.north_m) <= p.north_m &&
           p.north_m <= std::max(a.north_m, b.north_m) &&
           std::min(a.east_m, b.east_m) <= p.east_m && p.east_m <= std::max(a.east_m, b.east_m);
  };
  return on(p1, p2, q1, d1) || on(p1, p2, q2, d2) || on(q1, q2, p1, d3) || on(q1, q2, p2, d4);
}

/// Distance between two segments (0 when they intersect).
inline double segment_segment_distance(core::NavPoint p1, core::NavPoint p2, core::NavPoint q1,
                                       core::NavPoint q2) {
  if (segments_intersect(p1, p2, q1, q2)) return 0.0;
  return std::min({point_segment_distance(p1, q1, q2), point_segment_distance(p2, q1, q2),
                   point_segment_distance(q1, p1, p2), point_segment_distance(q2, p1, p2)});
}

/// Even-odd point-in-polygon (polygon closed implicitly): any random-access container of
/// NavPoint (vector, array).
template <class Polygon>
bool point_in_polygon(core::NavPoint p, const Polygon& poly) {
  bool inside = false;
  const std::size_t n = poly.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const core::NavPoint a = poly[i];
    const core::NavPoint b = poly[j];
    if ((a.east_m > p.east_m) != (b.east_m > p.east_m)) {
      const double north_at =
          a.north_m + (p.east_m - a.east_m) * (b.north_m - a.north_m) / (b.east_m - a.east_m);
      if (p.north_m < north_at) inside = !inside;
    }
  }
  return inside;
}

}  // namespace coxswain::sim::world
