// SPDX-License-Identifier: Apache-2.0
#pragma once
// The one angle-bin representation every avoidance strategy works on (docs/missions.md).
#include <array>
#include <cstddef>
#include <optional>
#include <string>

#include "coxswain/perception/obstacles.hpp"

namespace coxswain::guidance {

/// The fan of candidate headings, body frame (0 = bow, + starboard), degrees.
struct AngleFan {
  double min_deg = -90.0;      // port edge of the fan
  double max_deg = 90.0;       // starboard edge; max_deg - min_deg in (0, 360]
  double bin_width_deg = 1.0;  // (max - min) / width must be a whole number <= kMaxBins

  /// Empty when valid, else what is wrong.
  [[nodiscard]] std::optional<std::string> validate() const;
};

/// Fixed-capacity bins over a fan of body-frame headings. Bin i covers the headings
/// [min + i * w, min + (i + 1) * w). `range_m(i)` is the distance to the closest obstacle point
/// that a hull of half-width `corridor_half_width_m` steered anywhere inside bin i would come
/// within reach of: a point at distance d and at an angle delta outside the bin blocks it when
/// d * sin(delta) <= half-width, i.e. the margin is asin(min(1, half_width / d)) and shrinks with
/// distance. Every bin a segment covers is filled (a wall spanning the whole fan, or crossing the
/// bow, included), with the segment's true closest distance inside that bin, not a first point.
/// Plain value; not thread-safe; no allocation after `configure`.
class AngleBins {
 public:
  static constexpr std::size_t kMaxBins = 720;
  static constexpr double kNoObstacle = 1.0e9;  // no obstacle in the bin

  /// Sets the fan and precomputes the bin directions. Returns false (and keeps the previous fan)
  /// when the fan is invalid.
  [[nodiscard]] bool configure(const AngleFan& fan);

  /// Empties every bin.
  void clear();
  /// Clears, then adds every segment of `list` whose closest point is within `max_range_m`.
  void fill(const perception::ObstacleList& list, double corridor_half_width_m, double max_range_m);
  /// Adds one segment (lowering bins' ranges where it is closer).
  void add_segment(const perception::ObstacleSegment& seg, double corridor_half_width_m);

  [[nodiscard]] std::size_t size() const { return count_; }
  [[nodiscard]] const AngleFan& fan() const { return fan_; }
  [[nodiscard]] double center_deg(std::size_t i) const {
    return fan_.min_deg + (static_cast<double>(i) + 0.5) * fan_.bin_width_deg;
  }
  /// Bin holding `bearing_deg` (wrapped), or size() when the bearing is outside the fan.
  [[nodiscard]] std::size_t index_of(double bearing_deg) const;
  [[nodiscard]] double range_m(std::size_t i) const { return range_m_[i]; }
  [[nodiscard]] const std::array<double, kMaxBins>& ranges_m() const { return range_m_; }
  /// Closest range over all bins (kNoObstacle when empty).
  [[nodiscard]] double min_range_m() const;
  /// What fill(list, corridor_half_width_m, max_range_m) and then min_range_m() would give,
  /// without filling (nor touching) the bins: the nearest segments first, stopping at the first
  /// that cannot come closer.
  [[nodiscard]] double nearest_m(const perception::ObstacleList& list, double corridor_half_width_m,
                                 double max_range_m) const;

 private:
  // Bins that may be touched, as up to two half-open index runs (two when wrapping round).
  struct Runs {
    std::size_t begin[2] = {0, 0};
    std::size_t end[2] = {0, 0};  // exclusive
    int count = 0;
  };
  [[nodiscard]] Runs candidate_bins(double from_deg, double sweep_deg) const;
  // The closest point of a segment to the body origin: its parameter along the segment and
  // its distance.
  struct Closest {
    double t = 0.0;
    double d_m = 0.0;
  };
  // That of segment a + t d, t in [0, 1]; the point at a parameter already found.
  [[nodiscard]] static Closest closest_to_origin(double af, double as, double df, double ds);
  [[nodiscard]] static Closest closest_at(double af, double as, double df, double ds, double t);
  // Calls visit(bin, d_min, f, s, at_closest) for every bin the segment reaches: at_closest when
  // the bin holds the segment's own closest point (`closest`, distance d_min), else (f, s) is
  // the point of the segment nearest the origin that the bin reaches.
  template <class Visit>
  void visit_bins(const perception::ObstacleSegment& seg, const Closest& closest,
                  double corridor_half_width_m, Visit&& visit) const;
  // add_segment() with the segment's closest point already found.
  void add_segment(const perception::ObstacleSegment& seg, const Closest& closest,
                   double corridor_half_width_m);

  AngleFan fan_{};
  std::size_t count_ = 0;
  std::array<double, kMaxBins> range_m_{};
  // Unit vectors (forward, starboard) of the bin edges (count_ + 1) and centres.
  std::array<double, kMaxBins + 1> edge_cos_{};
  std::array<double, kMaxBins + 1> edge_sin_{};
  std::array<double, kMaxBins> mid_cos_{};
  std::array<double, kMaxBins> mid_sin_{};
};

}  // namespace coxswain::guidance
