// SPDX-License-Identifier: Apache-2.0
#pragma once
// Entering the chosen dock (document 000 5.3): either pursue a point 1-2 m ahead along the ray
// from a decision point into the slip (project the boat onto the ray, aim ahead of the
// projection), or keep the marker on the image centre line (its body bearing at 0). Both stop
// when the lidar range ahead falls under the stop distance (2026 plan: 0.3 m).
#include <optional>
#include <string>

#include "coxswain/core/frames.hpp"
#include "coxswain/perception/obstacles.hpp"

namespace coxswain::guidance {

struct DockingApproachParams {
  double lookahead_m = 1.5;            // aim this far ahead of the projection (documents: 1-2 m)
  double stop_range_m = 0.3;           // range ahead below which the boat stops
  double marker_gain = 1.0;            // desired turn per degree of marker bearing
  double max_marker_turn_deg = 30.0;   // clamp of one step's marker correction
  double ahead_half_angle_deg = 10.0;  // sector used by min_range_ahead_m

  [[nodiscard]] std::optional<std::string> validate() const;
};

/// Headings TRUE, navigation frame.
struct DockingCommand {
  double desired_heading_deg = 0.0;
  core::NavPoint aim;        // pursued point (ray mode)
  double along_ray_m = 0.0;  // projection of the boat on the ray from the decision point
  double cross_ray_m = 0.0;  // + = boat to starboard of the ray
  bool stop = false;         // latched: range ahead fell under stop_range_m
};

/// Closest lidar return within +-half_angle_deg of the bow; empty when no bin there has a return.
[[nodiscard]] std::optional<double> min_range_ahead_m(const perception::RangeProfile& profile,
                                                      double half_angle_deg);

/// Holds the ray and the latched stop. Plain value, not thread-safe.
class DockingApproach {
 public:
  explicit DockingApproach(DockingApproachParams p = {}) : p_(p) {}
  /// Ray from `decision_point` through `dock_point`. False when they coincide (< 0.1 m).
  [[nodiscard]] bool set_ray(core::NavPoint decision_point, core::NavPoint dock_point);
  /// Ray pursuit from the boat pose; range_ahead_m from min_range_ahead_m (empty = unknown).
  DockingCommand pursue(const core::NavPose& pose, std::optional<double> range_ahead_m);
  /// Marker centring: marker_bearing_deg in the body frame (0 = bow); empty = not seen this
  /// frame, keep the heading.
  DockingCommand hold_marker(double heading_deg, std::optional<double> marker_bearing_deg,
                             std::optional<double> range_ahead_m);
  void reset() { stopped_ = false; }
  [[nodiscard]] bool stopped() const { return stopped_; }

 private:
  bool check_stop(std::optional<double> range_ahead_m);

  DockingApproachParams p_;
  core::NavPoint origin_;
  double ray_bearing_deg_ = 0.0;
  bool has_ray_ = false;
  bool stopped_ = false;
};

}  // namespace coxswain::guidance
