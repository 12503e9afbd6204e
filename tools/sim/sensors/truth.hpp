// SPDX-License-Identifier: Apache-2.0
#pragma once
// What the simulated sensors need to know about the boat at one instant: the ground truth they
// measure. The runner fills it from its own dynamics state (sim_world's TruthState); the lead
// adapts between the two. Plain data.
#include "coxswain/core/frames.hpp"

namespace coxswain::sim::sensors {

struct BoatTruth {
  /// Pose of the body origin (the bow reference point) in the navigation frame; heading is TRUE
  /// (0 = true north, clockwise), (-180, 180].
  core::NavPose pose;
  double surge_mps = 0.0;           // body x (forward) velocity through the ground
  double sway_mps = 0.0;            // body y (starboard) velocity
  double yaw_rate_dps = 0.0;        // clockwise seen from above (= rate about body z down)
  double accel_forward_mps2 = 0.0;  // body-frame linear acceleration, gravity excluded
  double accel_starboard_mps2 = 0.0;
  double vel_north_mps = 0.0;  // velocity of the body origin over ground, navigation frame
  double vel_east_mps = 0.0;
};

}  // namespace coxswain::sim::sensors
