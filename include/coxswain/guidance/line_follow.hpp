// SPDX-License-Identifier: Apache-2.0
#pragma once
// Line following between two points: cross-track error and a look-ahead (LOS) desired heading,
// with an optional integral term (ILOS, Borhaug et al. 2008) that removes the steady offset a
// side current or a biased actuator would leave. Steering at the bearing to the next point
// instead (the 2022 code) draws arcs when the boat is off the leg: docs/missions.md.
#include <limits>
#include <optional>
#include <string>

#include "coxswain/core/frames.hpp"

namespace coxswain::guidance {

struct LineFollowParams {
  double lookahead_m = 4.0;     // Delta: short oscillates, long converges slowly
  double integral_gain = 0.2;   // sigma (unitless); 0 = plain LOS
  double max_integral_m = 3.0;  // |sigma * y_int| limit, metres (anti-windup)
  double max_dt_s = 0.5;        // longer steps are not integrated (dropouts)
  // Farther off the line the integral restarts from zero: it is for a current's crab on the
  // line, and joining from metres off it, it winds up and carries the boat across the line.
  double integrate_within_m = std::numeric_limits<double>::infinity();

  [[nodiscard]] std::optional<std::string> validate() const;
};

/// Headings are TRUE, navigation frame (0 = north, clockwise +, (-180, 180]).
struct LineFollowOutput {
  double desired_heading_deg = 0.0;
  double path_bearing_deg = 0.0;  // bearing of the leg from -> to
  double cross_track_m = 0.0;     // + = boat to starboard of the leg (right of its direction)
  double along_track_m = 0.0;     // projection of the boat on the leg, from `from`
  double leg_length_m = 0.0;
  double progress = 0.0;  // along / length clamped to [0, 1]
};

/// Holds only the ILOS integral state. Plain value, no allocation, not thread-safe.
class LineFollower {
 public:
  explicit LineFollower(LineFollowParams p = {}) : p_(p) {}
  /// One step. dt_s is the time since the previous step on the same leg (0 on the first).
  LineFollowOutput update(core::NavPoint from, core::NavPoint to, core::NavPoint position,
                          double dt_s);
  /// Geometry only, no integral and no state change.
  [[nodiscard]] LineFollowOutput geometry(core::NavPoint from, core::NavPoint to,
                                          core::NavPoint position) const;
  /// Call on a leg change.
  void reset() { y_int_m_ = 0.0; }
  [[nodiscard]] double integral_m() const { return p_.integral_gain * y_int_m_; }

 private:
  LineFollowParams p_;
  double y_int_m_ = 0.0;
};

}  // namespace coxswain::guidance
