// SPDX-License-Identifier: Apache-2.0
#pragma once
// The seam between the lockstep runner and the simulated sensors (tools/sim/sensors). After every
// dynamics step the runner hands the suite the boat's truth and the virtual time; the suite
// publishes whatever samples fall due (lidar scans, IMU samples, GNSS fixes, camera detections)
// into the store exactly as the daemon's drivers would, stamped with `now_ns`. A suite gets the
// world, boat config and seed at construction; it must be deterministic for a seed (its own Rng
// streams, no clock reads, no threads). Called from the runner's thread only.
#include "coxswain/core/latest_store.hpp"
#include "coxswain/core/time.hpp"
#include "sim/dynamics/boat_model.hpp"

namespace coxswain::sim::runner {

class SensorSuite {
 public:
  virtual ~SensorSuite() = default;
  /// `truth` is the state at `now_ns` (after the step that reached it).
  virtual void step(const dynamics::TruthState& truth, core::TimeNs now_ns,
                    core::LatestStore& store) = 0;
};

}  // namespace coxswain::sim::runner
