// SPDX-License-Identifier: Apache-2.0
#include "coxswain/core/clock.hpp"

#include <chrono>

namespace coxswain::core {

TimeNs SteadyClock::now_ns() const {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

void ManualClock::advance_ns(TimeNs delta_ns) {
  if (delta_ns > 0) now_ns_.fetch_add(delta_ns, std::memory_order_acq_rel);
}

void ManualClock::set_ns(TimeNs t_ns) {
  TimeNs current = now_ns_.load(std::memory_order_acquire);
  while (t_ns > current &&
         !now_ns_.compare_exchange_weak(current, t_ns, std::memory_order_acq_rel)) {
  }
}

}  // namespace coxswain::core
