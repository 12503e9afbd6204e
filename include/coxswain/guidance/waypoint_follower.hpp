// SPDX-License-Identifier: Apache-2.0
#pragma once
// Hopping-tour waypoint following (docs/missions.md): visit a route of points in order;
// a point counts inside its arrival radius; a point passed abeam within the slip radius counts as
// missed and is skipped rather than circled back to; between points the boat follows the leg
// (LineFollower) instead of the bare bearing.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "coxswain/core/frames.hpp"
#include "coxswain/core/time.hpp"
#include "coxswain/guidance/line_follow.hpp"
#include "coxswain/guidance/nav_filter.hpp"

namespace coxswain::guidance {

struct WaypointFollowerParams {
  /// KABOAT counts a point when half the boat is inside 2 m; 1.5 m at the GPS antenna (mid-length)
  /// leaves a margin for GPS noise.
  double arrival_radius_m = 1.5;
  /// With a position covariance: a point counts when it lies inside the rule's radius with this
  /// one-sided confidence (distance + k sigma along the line of sight <= rule_radius_m), in
  /// place of the fixed margin above. 0 = the fixed margin always.
  double arrival_confidence = 0.95;
  /// The rule's circle at the antenna (KABOAT: half the boat inside 2 m; the antenna sits at
  /// mid-length).
  double rule_radius_m = 2.0;
  /// Passed the perpendicular through the point (along-track beyond the leg end) within this
  /// distance: the point is missed; advance instead of looping back.
  double slip_radius_m = 4.0;
  /// false = steer at the bearing of the point (the documents' 2022 behaviour).
  bool line_following = true;
  LineFollowParams line;

  [[nodiscard]] std::optional<std::string> validate() const;
};

enum class WaypointEvent : std::uint8_t { kNone = 0, kArrived, kMissed };

/// One step's result. Headings TRUE, navigation frame.
struct WaypointGuidance {
  bool finished = false;  // every point visited or missed; hold/neutral
  std::size_t index = 0;  // the point being steered to (== size when finished)
  core::NavPoint target;  // that point
  double desired_heading_deg = 0.0;
  double distance_to_go_m = 0.0;  // to the current point
  double cross_track_m = 0.0;     // + = starboard of the leg
  double leg_progress = 0.0;      // 0..1 along the current leg
  // The point counts once the boat is this near it, as the estimate stands now (the fixed
  // arrival radius, or the rule's radius less the confidence margin; 0 when out of reach).
  double reach_m = 0.0;
  WaypointEvent event = WaypointEvent::kNone;  // what happened to the previous point this step
  std::size_t event_index = 0;                 // which point the event is about
};

/// Route of up to kMaxWaypoints points; the first leg starts where the boat is at the first
/// update(). Plain value, fixed storage, deterministic, not thread-safe.
class WaypointFollower {
 public:
  static constexpr std::size_t kMaxWaypoints = 64;

  explicit WaypointFollower(WaypointFollowerParams p = {});
  /// Replaces the route and restarts at its first point. False (route unchanged) when empty or
  /// longer than kMaxWaypoints.
  [[nodiscard]] bool set_route(std::span<const core::NavPoint> points);
  /// One step from the boat's position (GPS-offset-corrected, navigation frame) and, when the
  /// estimator has one, its covariance (arrival by confidence).
  WaypointGuidance update(core::NavPoint position, core::TimeNs stamp_ns,
                          const PositionCovariance* covariance = nullptr);

  [[nodiscard]] std::size_t size() const { return count_; }
  [[nodiscard]] std::size_t index() const { return index_; }
  [[nodiscard]] bool finished() const { return index_ >= count_; }
  [[nodiscard]] std::size_t arrived_count() const { return arrived_; }
  [[nodiscard]] std::size_t missed_count() const { return missed_; }

 private:
  void advance(core::NavPoint position);

  WaypointFollowerParams p_;
  double k_sigma_ = 0.0;
  LineFollower line_;
  std::array<core::NavPoint, kMaxWaypoints> route_{};
  std::size_t count_ = 0;
  std::size_t index_ = 0;
  core::NavPoint leg_start_;
  bool has_leg_start_ = false;
  core::TimeNs last_ns_ = core::kNeverNs;
  std::size_t arrived_ = 0;
  std::size_t missed_ = 0;
};

}  // namespace coxswain::guidance
