// SPDX-License-Identifier: Apache-2.0
#pragma once
// The lidar's view of a world: wall and dock segments and buoy circles in the navigation frame,
// and a ray caster. Rays are cast in bursts from near one position (one lidar revolution): the
// caster sorts the objects in reach into 2-degree bearing bins once per burst, so each ray tests
// only the few objects that can lie along it. Not thread-safe (the bins are scratch space); the
// object lists are immutable after construction.
#include <array>
#include <cstdint>
#include <vector>

#include "coxswain/core/frames.hpp"
#include "sim/world/world.hpp"

namespace coxswain::sim::sensors {

struct Segment {
  core::NavPoint a;
  core::NavPoint b;
};

struct Circle {
  core::NavPoint center;
  double radius_m = 0.0;
};

class RayScene {
 public:
  RayScene() = default;
  /// Walls, every dock wall and every buoy of `world`.
  explicit RayScene(const world::World& world);

  void add_segment(const Segment& s);
  void add_circle(const Circle& c);
  [[nodiscard]] const std::vector<Segment>& segments() const { return segments_; }
  [[nodiscard]] const std::vector<Circle>& circles() const { return circles_; }

  /// Prepares for rays from anywhere within `radius_m` of `center`, reaching `max_range_m`.
  void prepare(core::NavPoint center, double radius_m, double max_range_m);
  /// True while `p` lies within the prepared region.
  [[nodiscard]] bool covers(core::NavPoint p) const;
  /// Radius of the prepared region; negative when not prepared.
  [[nodiscard]] double prepared_radius_m() const { return radius_m_; }
  /// Object entries over all bins of the last prepare() (its cost, and how much each ray tests).
  [[nodiscard]] std::size_t bin_entries() const;
  /// Distance to the first object along the ray from `origin` at navigation bearing
  /// `bearing_deg`, or a negative value when nothing lies within the prepared max range.
  /// `origin` must be covered (see covers()).
  [[nodiscard]] double cast(core::NavPoint origin, double bearing_deg) const;
  /// Same with the bearing already in [0, 360) and its direction (cos, sin) given, for callers
  /// that step the direction incrementally.
  [[nodiscard]] double cast(core::NavPoint origin, double bearing_360_deg, double dn,
                            double de) const;
  /// Same without bins, testing every object: the reference for tests.
  [[nodiscard]] double cast_brute(core::NavPoint origin, double bearing_deg,
                                  double max_range_m) const;

 private:
  static constexpr int kBins = 180;
  static constexpr double kBinDeg = 360.0 / kBins;
  void add_span(std::uint32_t tagged, double lo_deg, double hi_deg);

  std::vector<Segment> segments_;
  std::vector<Circle> circles_;
  // Index tagged with the kind in the top bit (1 = circle).
  std::array<std::vector<std::uint32_t>, kBins> bins_{};
  core::NavPoint center_;
  double radius_m_ = -1.0;
  double max_range_m_ = 0.0;
};

/// Distance along the unit ray (ox, oy) + t (dx, dy) to segment s, or -1.
[[nodiscard]] double ray_segment(core::NavPoint o, double dn, double de, const Segment& s);
/// Distance along the ray to the first crossing of circle c, or -1 (origin inside: -1).
[[nodiscard]] double ray_circle(core::NavPoint o, double dn, double de, const Circle& c);

}  // namespace coxswain::sim::sensors
