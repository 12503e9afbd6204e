// SPDX-License-Identifier: Apache-2.0
#pragma once
// `coxswain-sim run --map-frames DIR`: what the boat believed, drawn every so often as PNG: its
// lidar map (unknown grey, seen free pale, occupied black), the planner's inflation, the
// planned path, the boat's estimate and its true hull, and the course's true obstacles as
// outlines. For finding why a run sailed where it did.
#include <string>

#include "coxswain/core/frames.hpp"
#include "sim/runner/mission_pilot.hpp"
#include "sim/world/world.hpp"

namespace coxswain::sim::app {

class MapFrameWriter {
 public:
  /// Writes a frame every `period_s` of simulated time into `dir` (created).
  MapFrameWriter(std::string dir, double period_s, const world::World& world);
  /// After every tick; draws when a period has passed and the mission has a map.
  void on_step(double t_s, const runner::MissionPilot& pilot, const core::NavPose& truth);
  [[nodiscard]] int written() const { return written_; }

 private:
  std::string dir_;
  double period_s_;
  const world::World& world_;
  double next_s_ = 0.0;
  int written_ = 0;
};

}  // namespace coxswain::sim::app
