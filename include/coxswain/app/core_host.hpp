// SPDX-License-Identifier: Apache-2.0
#pragma once
// Glue between the pure mission core and the daemon's edges: what the tick records and logs of
// each step. Shared by every host of the core (daemon, simulator, replay) so they record alike.
#include <span>
#include <vector>

#include "coxswain/config/config.hpp"
#include "coxswain/drivers/device_session.hpp"
#include "coxswain/host/step_record.hpp"
#include "coxswain/mission/mission_core.hpp"

namespace coxswain::app {

/// Logs this step's state transitions (one line each, with the reason).
void log_transitions(const mission::TransitionLog& transitions);

/// Hands raw bytes to two sinks (flight recorder and capture mode). Either may be null.
class RawByteTee final : public drivers::RawByteSink {
 public:
  RawByteTee(drivers::RawByteSink* first, drivers::RawByteSink* second)
      : first_(first), second_(second) {}
  void on_raw(msg::DeviceId device, drivers::RawDirection direction, core::TimeNs stamp_ns,
              std::span<const std::uint8_t> bytes) noexcept override {
    if (first_ != nullptr) first_->on_raw(device, direction, stamp_ns, bytes);
    if (second_ != nullptr) second_->on_raw(device, direction, stamp_ns, bytes);
  }

 private:
  drivers::RawByteSink* first_;
  drivers::RawByteSink* second_;
};

}  // namespace coxswain::app
