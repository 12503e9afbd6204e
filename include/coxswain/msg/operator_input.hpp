// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>

#include "coxswain/core/time.hpp"
#include "coxswain/msg/camera_detections.hpp"

namespace coxswain::msg {

/// Commands from the shore: the local control socket, the status page or the command line.
/// Each request carries its own counter so the core acts on every press exactly once.
struct OperatorInput {
  core::TimeNs stamp_ns = core::kNeverNs;
  std::uint32_t start_count = 0;  // incremented per "start"
  std::uint32_t hold_count = 0;   // incremented per "hold" toggle request
  bool hold = false;              // operator hold requested
  Colour target_colour = Colour::kUnknown;
  Shape target_shape = Shape::kUnknown;
};

}  // namespace coxswain::msg
