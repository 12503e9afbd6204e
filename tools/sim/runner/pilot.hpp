// SPDX-License-Identifier: Apache-2.0
#pragma once
// What drives the simulated boat: the mission core behind this interface (or a test's own
// controller). Called at the tick rate with a snapshot of the store and the virtual time; writes
// the command for the Arduino, exactly what the daemon's tick produces. Deterministic, no clock
// reads. Called from the runner's thread only.
#include "coxswain/core/latest_store.hpp"
#include "coxswain/core/time.hpp"
#include "coxswain/msg/actuator_command.hpp"

namespace coxswain::sim::runner {

class Pilot {
 public:
  virtual ~Pilot() = default;
  virtual void step(const core::Snapshot& snapshot, core::TimeNs now_ns,
                    msg::ActuatorCommand& out) = 0;
};

}  // namespace coxswain::sim::runner
