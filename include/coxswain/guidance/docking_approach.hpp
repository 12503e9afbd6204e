// SPDX-License-Identifier: Apache-2.0
#pragma once
// Entering the chosen dock (the KABOAT 2022 report 5.3): either pursue a point 1-2 m ahead along
// the ray from a decision point into the slip (project the boat onto the ray, aim ahead of the
// projection), or keep the marker on the image centre line (its body bearing at 0). Both stop
// when the lidar range ahead falls under the stop distance (2026 plan: 0.3 m).
#include <cstddef>
#include <limits>
#include <optional>
#include <span>
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

/// Which slip the target marker of one camera frame belongs to. `marker_bearings_deg`: body
/// bearings of every dock marker in the frame; `target_index`: which of them is the target;
/// `slip_bearings_deg`: each slip's expected body bearing (from the map and the pose). When the
/// frame holds one marker per slip, the target's rank from port to starboard names the slip: a
/// position error shifts every expected bearing alike and cannot swap neighbours. Otherwise the
/// slip whose expected bearing is nearest the target's, if within `window_deg`. Empty when
/// undecidable (bad index, no slips, nothing within the window).
[[nodiscard]] std::optional<std::size_t> slip_of_marker(std::span<const double> marker_bearings_deg,
                                                        std::size_t target_index,
                                                        std::span<const double> slip_bearings_deg,
                                                        double window_deg);

/// A slip mouth found in a lidar profile (2026 course 3, no marker to match). Body frame about
/// the profile's origin: x forward, y starboard.
struct SlipOpening {
  double mouth_x_m = 0.0;  // middle of the mouth (between the side walls' tips)
  double mouth_y_m = 0.0;
  double axis_body_deg = 0.0;  // direction into the slip (perpendicular to the mouth)
  double width_m = 0.0;        // distance between the tips
  double depth_m = 0.0;        // how much deeper than its tips the inside reaches
};

struct SlipFinderParams {
  double min_width_m = 1.2;       // narrower gaps do not take the hull (beam plus margin)
  double max_width_m = 2.6;       // wider gaps are open water between obstacles, not a slip
  double min_depth_m = 1.0;       // the inside reaches at least this much beyond the tips
  double max_depth_m = 6.0;       // and ends within this (a back wall): open water behind a gap
                                  // between two obstacles is no slip
  double max_bearing_deg = 85.0;  // only mouths within this of the forward direction
  double max_range_m = 12.0;      // ignore tips farther than this
  double max_axis_deg = 45.0;     // the slip's axis within this of the forward direction: a gap
                                  // seen edge-on (tips at different depths) is no mouth

  [[nodiscard]] std::optional<std::string> validate() const;
};

/// The slip mouth nearest the expected width within +-max_bearing_deg of `forward_body_deg`
/// (the course's forward direction in the body frame): two tips (returns nearer than their
/// neighbours: a finger's or quay wall's end) a slip's width apart, nothing between them nearer
/// than the line joining them, and a closed inside (a return in every bin) reaching at least
/// min_depth_m and at most max_depth_m beyond it. Unlike "the most
/// open direction" this ignores a pond's corner, which has no tips. Empty when none.
[[nodiscard]] std::optional<SlipOpening> find_slip(const perception::RangeProfile& profile,
                                                   const SlipFinderParams& params,
                                                   double forward_body_deg);

/// As find_slip, but the mouth whose middle is nearest `expected_mouth` (body frame), e.g. the
/// chosen one of several slips side by side; empty when none lies within `max_offset_m` of it.
[[nodiscard]] std::optional<SlipOpening> find_slip_near(const perception::RangeProfile& profile,
                                                        const SlipFinderParams& params,
                                                        double forward_body_deg,
                                                        core::BodyPoint expected_mouth,
                                                        double max_offset_m);

/// As find_slip, but the mouth of the slip whose marker (on its axis, `marker_depth_m` inside the
/// mouth) is the one the camera sees at `marker_bearing_deg`: every quantity is relative to the
/// bow, so neither a GNSS nor a compass error can pick a neighbour. Empty when no mouth's marker
/// is within `max_error_deg` of the sighting.
[[nodiscard]] std::optional<SlipOpening> find_slip_toward(const perception::RangeProfile& profile,
                                                          const SlipFinderParams& params,
                                                          double forward_body_deg,
                                                          double marker_bearing_deg,
                                                          double marker_depth_m,
                                                          double max_error_deg);

/// What the lidar sees along the hull's sides: on each side, a wall (a finger, a slip's side)
/// abeam of the lidar and again `aft_m` behind it, both within `max_side_m` of the centre line and
/// parallel to it within `max_skew_m`. A boat whose bow is in a slip has both fingers so; a boat
/// beside a slip, or nosed into a corner, has at most one side so. Distances are across the
/// centre line; -1 for a side without such a wall.
struct FingersAlongside {
  double port_m = -1.0;
  double starboard_m = -1.0;
  [[nodiscard]] bool both() const { return port_m >= 0.0 && starboard_m >= 0.0; }
};

/// Returns more than `bow_ahead_m` ahead of the lidar (the bow's tip) are ahead of the hull,
/// never beside it: a slip's back a hand's breadth ahead is no finger.
[[nodiscard]] FingersAlongside fingers_alongside(
    const perception::RangeProfile& profile, double max_side_m, double aft_m,
    double bow_ahead_m = std::numeric_limits<double>::infinity(), double max_skew_m = 0.3);

/// Ray pursuit in the body frame: heading change (body bearing, + starboard) toward a point
/// `lookahead_m` along the slip's axis beyond the boat's projection on it, so the boat lines up
/// with the axis before it reaches the mouth instead of cutting the corner.
[[nodiscard]] double slip_pursuit_bearing_deg(const SlipOpening& slip, double lookahead_m);

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
