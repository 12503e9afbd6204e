// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/core_host.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>

#include "coxswain/mission/tunable_parameters.hpp"

namespace coxswain::app {

void log_transitions(const mission::TransitionLog& transitions) {
  for (std::uint32_t i = 0; i < transitions.count && i < mission::TransitionLog::kCapacity; ++i) {
    const mission::Transition& t = transitions.entries[i];
    spdlog::info("mission: {} -> {}: {}", t.from.view(), t.to.view(), t.reason.view());
  }
  if (transitions.dropped > 0) {
    spdlog::warn("mission: {} transitions in one tick were not logged", transitions.dropped);
  }
}

}  // namespace coxswain::app
