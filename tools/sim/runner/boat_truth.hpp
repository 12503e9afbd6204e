// SPDX-License-Identifier: Apache-2.0
#pragma once
// The one place the dynamics' truth becomes what the simulated sensors measure (lockstep and
// devices mode alike).
#include "coxswain/core/frames.hpp"
#include "sim/dynamics/boat_model.hpp"
#include "sim/sensors/truth.hpp"

namespace coxswain::sim::runner {

/// The dynamics report the centre of gravity's velocity; the sensors get the body origin's.
[[nodiscard]] inline sensors::BoatTruth to_boat_truth(const dynamics::TruthState& truth) {
  sensors::BoatTruth b;
  b.pose = truth.pose;
  const core::NavPoint v = dynamics::velocity_at(truth, truth.pose.position);
  const core::BodyPoint body = core::nav_to_body({{0.0, 0.0}, truth.pose.heading_deg}, v);
  b.surge_mps = body.forward_m;
  b.sway_mps = body.starboard_m;
  b.yaw_rate_dps = truth.yaw_rate_dps;
  b.accel_forward_mps2 = truth.accel_forward_mps2;
  b.accel_starboard_mps2 = truth.accel_starboard_mps2;
  b.vel_north_mps = v.north_m;
  b.vel_east_mps = v.east_m;
  return b;
}

}  // namespace coxswain::sim::runner
