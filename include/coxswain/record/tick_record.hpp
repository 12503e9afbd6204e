// SPDX-License-Identifier: Apache-2.0
#pragma once
// What the tick hands the recorder each tick: the Snapshot the core saw, the command it produced,
// its state path and what to draw. Plain data in msg/core types, so any host of the core (daemon,
// simulator, replay) can fill it without depending on the mission module.
#include <array>
#include <cstdint>
#include <string_view>

#include "coxswain/core/latest_store.hpp"
#include "coxswain/msg/actuator_command.hpp"

namespace coxswain::record {

/// An obstacle to draw, in the body frame (x forward, y starboard), metres.
struct VizObstacle {
  float x_m = 0.0F;
  float y_m = 0.0F;
  float radius_m = 0.0F;
};

/// A point in the navigation frame (X north, Y east), metres.
struct VizPoint {
  double north_m = 0.0;
  double east_m = 0.0;
};

/// The tick's visualization data (turned into foxglove.FrameTransform and foxglove.SceneUpdate
/// on the recorder's thread). Fixed size: copied into the tick queue, never allocated.
struct TickViz {
  static constexpr std::size_t kMaxObstacles = 32;
  static constexpr std::size_t kMaxPathPoints = 64;
  /// Boat pose in the navigation frame (X north, Y east, metres; heading deg, 0 north, clockwise).
  bool pose_valid = false;
  double north_m = 0.0;
  double east_m = 0.0;
  double heading_deg = 0.0;
  /// The position estimate's covariance (north/east, m^2): drawn as its 95 % ellipse and kept
  /// in the scene's metadata.
  bool cov_valid = false;
  double cov_nn_m2 = 0.0;
  double cov_ne_m2 = 0.0;
  double cov_ee_m2 = 0.0;
  /// Where the guidance wants to go, body-frame bearing (0 bow, + starboard).
  bool target_valid = false;
  double target_bearing_deg = 0.0;
  /// The sector the avoidance considers dangerous, body-frame bearings from start to end
  /// clockwise, out to range_m.
  bool danger_valid = false;
  double danger_start_deg = 0.0;
  double danger_end_deg = 0.0;
  double danger_range_m = 0.0;
  std::uint32_t obstacle_count = 0;
  std::array<VizObstacle, kMaxObstacles> obstacles{};
  /// The route in the navigation frame: the goal and its arrival circle, the leg from its start,
  /// the gate being judged (its buoys as seen by the lidar, or the nominal gate) and the global
  /// planner's path.
  bool goal_valid = false;
  VizPoint goal;
  double arrival_radius_m = 0.0;
  bool leg_valid = false;
  VizPoint leg_start;
  bool gate_valid = false;
  bool gate_by_lidar = false;
  VizPoint gate_port;
  VizPoint gate_starboard;
  std::uint32_t path_count = 0;
  std::array<VizPoint, kMaxPathPoints> path{};
  float hull_length_m = 1.2F;
  float hull_beam_m = 0.8F;
};

/// One tick as recorded. The references must stay valid during Recorder::record_tick only.
struct TickInput {
  std::uint64_t tick_index = 0;
  core::TimeNs now_ns = 0;
  const core::Snapshot* snapshot = nullptr;  // required
  msg::ActuatorCommand command;
  std::string_view state_path;   // e.g. "ACTIVE:HOPPING:TRACKING", cut at 255 bytes
  const TickViz* viz = nullptr;  // optional
};

}  // namespace coxswain::record
