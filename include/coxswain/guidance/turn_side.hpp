// SPDX-License-Identifier: Apache-2.0
#pragma once
// Which way to turn round: a large change of heading is a turn of the boat's own radius, and the
// short way can carry its hull into a wall the long way clears. The turn on each side is swept
// as a circle of the hull about its turning centre against what the lidar sees, and a turn that
// the short way cannot make is taken the long way. Pure, no allocation.
#include <cstdint>
#include <optional>
#include <string>

#include "coxswain/core/frames.hpp"
#include "coxswain/guidance/avoidance.hpp"
#include "coxswain/perception/obstacles.hpp"

namespace coxswain::guidance {

struct TurnSideParams {
  bool enabled = true;
  double min_turn_deg = 60.0;  // smaller changes of heading: always the short way
  double clearance_m = 0.5;    // room kept between the swept hull and what the lidar sees
  double release_deg = 45.0;   // a side taken is held until the heading is this near the goal's
  // The pivot's turning circle at sailing speed, drift included: wider than the swept hull's
  // hard turn near obstacles (the avoidance's), since a waypoint is passed at speed.
  double turn_radius_m = 3.5;
  [[nodiscard]] std::optional<std::string> validate() const;
};

/// The hull and its turn, body frame (x forward, y starboard of the body origin); a mission takes
/// them from its avoidance parameters (boat.yaml's hull, the swept-hull turn radius).
struct TurnHull {
  double turn_radius_m = 2.6;  // of the pivot's path in a hard turn
  double pivot_ahead_m = 0.4;
  double bow_ahead_m = 0.1;
  double hull_length_m = 1.2;
  double half_beam_m = 0.4;
  /// The hull of the avoidance (boat.yaml's) on its hard turn.
  [[nodiscard]] static TurnHull from(const AvoidanceParams& p) {
    return {p.sweep_turn_radius_m, p.pivot_ahead_m, p.bow_ahead_m, p.hull_length_m, p.half_beam_m};
  }
  /// The same hull on the turning circle of `turn` (sailing speed, drift).
  [[nodiscard]] static TurnHull from(const AvoidanceParams& p, const TurnSideParams& turn) {
    TurnHull h = from(p);
    h.turn_radius_m = turn.turn_radius_m;
    return h;
  }
};

/// Degrees of heading the boat can turn to each side, on its turning circle, before its hull
/// comes within `clearance_m` of an obstacle; `kFullTurnDeg` when nothing is in the way.
struct TurnRoom {
  static constexpr double kFullTurnDeg = 360.0;
  double starboard_deg = kFullTurnDeg;
  double port_deg = kFullTurnDeg;
};
[[nodiscard]] TurnRoom turn_room(const perception::ObstacleList& obstacles, const TurnHull& hull,
                                 double clearance_m);

/// True when `target` (body frame) lies inside the turning circle on its own side, more than
/// `tolerance_m` in from it: a hard turn toward it circles round it without ever coming within
/// `tolerance_m`, so the boat must first sail on straight until it lies outside.
[[nodiscard]] bool inside_turning_circle(core::BodyPoint target, const TurnHull& hull,
                                         double tolerance_m);

/// Holds the side of a large turn from its start to its end.
class TurnSideChooser {
 public:
  enum class Side : std::uint8_t { kShortest, kStarboard, kPort };
  TurnSideChooser(const TurnSideParams& p, const TurnHull& hull) : p_(p), hull_(hull) {}
  void reset() {
    side_ = Side::kShortest;
    room_.reset();
  }
  /// A new scan: the room on each side is measured again (in the boat's frame at the scan).
  void observe(const perception::ObstacleList& obstacles) {
    room_ = turn_room(obstacles, hull_, p_.clearance_m);
  }
  /// No fresh scan: what was measured is no longer where the boat is.
  void forget() { room_.reset(); }
  /// The heading to command (true) for `desired_deg`: unchanged, or, while a turn is taken the
  /// long way, at most 90 degrees round from the present heading on that side.
  [[nodiscard]] double steer(double heading_deg, double desired_deg);
  [[nodiscard]] Side side() const { return side_; }
  [[nodiscard]] bool enabled() const { return p_.enabled; }

 private:
  TurnSideParams p_;
  TurnHull hull_;
  std::optional<TurnRoom> room_;
  Side side_ = Side::kShortest;
};

}  // namespace coxswain::guidance
