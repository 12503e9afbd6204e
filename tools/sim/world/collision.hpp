// SPDX-License-Identifier: Apache-2.0
#pragma once
// Collision response: the hull (the same pentagon the judge uses) against every wall, dock wall
// and buoy of a world. After each dynamics step the runner calls resolve(): every overlap is
// pushed out along its minimum translation (separating axes: the hull's edge normals and the
// obstacle's own normal; for a buoy, from its centre through the nearest point of the hull) and
// the velocity into the obstacle is removed by an impulse (dynamics::BoatModel::resolve_contact)
// with a small restitution. The hull therefore stops at what it touches and slides along it,
// never passes through. Contacts are counted by the scorer, not here. Pure geometry over an
// immutable world; one object per run (not thread-safe only through the model it is given).
#include <array>
#include <cstddef>
#include <utility>
#include <vector>

#include "coxswain/config/config.hpp"
#include "coxswain/core/frames.hpp"
#include "sim/dynamics/boat_model.hpp"
#include "sim/world/world.hpp"

namespace coxswain::sim::world {

/// The hull outline in the body frame: bow tip, starboard shoulder, starboard stern corner, port
/// stern corner, port shoulder (the shoulders a quarter length aft of the bow tip). Convex.
std::array<core::BodyPoint, 5> hull_outline_body(const config::HullConfig& hull);

/// One overlap of the hull with an obstacle: push the hull `depth_m` along `normal` (unit, from
/// the obstacle into the hull) to separate them; `point` is where they touch.
struct Penetration {
  core::NavPoint normal;
  core::NavPoint point;
  double depth_m = 0.0;
};

/// Overlap of a convex outline with the segment a-b; false when they do not overlap.
bool outline_segment_penetration(const std::array<core::NavPoint, 5>& outline, core::NavPoint a,
                                 core::NavPoint b, Penetration& out);
/// Overlap of a convex outline with the circle (center, radius_m); false when none.
bool outline_circle_penetration(const std::array<core::NavPoint, 5>& outline, core::NavPoint center,
                                double radius_m, Penetration& out);

struct CollisionParams {
  double restitution = 0.15;  // fraction of the speed into the obstacle it bounces back with
  int passes = 4;             // resolution passes per step (corners, two obstacles at once)
};

class CollisionResponse {
 public:
  CollisionResponse(const World& world, const config::HullConfig& hull,
                    CollisionParams params = {});
  /// Separates the hull of `model` from everything it overlaps and stops its motion into it.
  /// Returns the number of overlaps resolved (0 = the hull touched nothing this step).
  int resolve(dynamics::BoatModel& model) const;

 private:
  std::vector<std::pair<core::NavPoint, core::NavPoint>> segments_;
  std::vector<std::pair<core::NavPoint, double>> circles_;
  std::array<core::BodyPoint, 5> outline_body_{};
  double reach_m_ = 0.0;    // the hull's radius about the body origin (broad phase)
  double reach2_m2_ = 0.0;  // its square with a margin (the squared broad phase)
  CollisionParams params_;
};

}  // namespace coxswain::sim::world
