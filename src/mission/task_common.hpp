// SPDX-License-Identifier: Apache-2.0
#pragma once
// Internal to the mission core: pieces the task implementations share (route following, checks)
// and the constructor of each task, one source file per task.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "coxswain/guidance/docking_approach.hpp"
#include "coxswain/guidance/waypoint_follower.hpp"
#include "tasks.hpp"

namespace coxswain::mission::detail {

/// Throws std::invalid_argument with the problem when there is one (engine parameter checks).
void check(const std::optional<std::string>& problem);

/// Largest detection of `colour` (any shape) in a frame, or null.
const msg::Detection* largest_of(const msg::CameraDetections& cam, msg::Colour colour);

/// Refusal reason when position or heading is not usable; empty when both are.
ReasonText need_position_heading(const TaskContext& ctx);

/// A task that steers with an avoidance engine: builds it from the mission's parameters and
/// rebuilds it on live retuning.
class AvoidingTask : public Task {
 public:
  void retune_avoidance(const guidance::AvoidanceParams& params) override {
    // Validated by the core: create() cannot fail here. The new engine starts without a side.
    if (auto av = guidance::Avoidance::create(params)) avoidance_.emplace(*av);
  }

 protected:
  /// Throws std::invalid_argument when the parameters are not valid.
  AvoidingTask(std::string_view name, const guidance::AvoidanceParams& params);

  std::optional<guidance::Avoidance> avoidance_;
};

// Waypoints of a task in the navigation frame (fixed storage).
struct Route {
  std::array<core::NavPoint, guidance::WaypointFollower::kMaxWaypoints> points{};
  std::size_t count = 0;
  [[nodiscard]] std::span<const core::NavPoint> span() const { return {points.data(), count}; }
};

Route to_route(const std::vector<core::GeoPoint>& geo, const core::LocalFrame& frame);

// Shared waypoint-following step: follower, viz, counters, phase names. Returns the guidance.
class RouteLeg {
 public:
  RouteLeg(const guidance::WaypointFollowerParams& p, Route route)
      : params_(p), follower_(p), route_(route) {}

  [[nodiscard]] bool start(core::NavPoint position) {
    leg_start_ = position;
    return follower_.set_route(route_.span());
  }
  guidance::WaypointGuidance update(const TaskContext& ctx) {
    const guidance::WaypointGuidance g = follower_.update(
        ctx.antenna, ctx.now_ns, ctx.position_cov_valid ? &ctx.position_cov : nullptr);
    if (g.event == guidance::WaypointEvent::kArrived) {
      ++ctx.status->waypoints_arrived;
      leg_start_ = route_.points[g.event_index];
    } else if (g.event == guidance::WaypointEvent::kMissed) {
      ++ctx.status->waypoints_missed;
      leg_start_ = route_.points[g.event_index];
    }
    if (!g.finished) {
      VizFrame& v = *ctx.viz;
      v.has_goal = true;
      v.goal = g.target;
      v.arrival_radius_m = ctx.position_cov_valid && params_.arrival_confidence > 0.0
                               ? params_.rule_radius_m
                               : params_.arrival_radius_m;
      v.active_waypoint = static_cast<std::int32_t>(g.index);
      v.has_leg = true;
      v.leg_start = leg_start_;
      v.cross_track_m = g.cross_track_m;
      v.distance_to_go_m = g.distance_to_go_m;
    }
    return g;
  }
  [[nodiscard]] std::size_t size() const { return route_.count; }
  [[nodiscard]] core::NavPoint point(std::size_t i) const { return route_.points[i]; }

 private:
  guidance::WaypointFollowerParams params_;
  guidance::WaypointFollower follower_;
  Route route_;
  core::NavPoint leg_start_;
};

ReasonText event_reason(const guidance::WaypointGuidance& g, double dist_m);

/// Progress of a task that means to go somewhere: stuck when the boat moved less than
/// `stuck_distance_m` in `stuck_s` (a bow on a wall, a hull pinned in a corner). A stuck boat
/// recovers for stop_s + back_off_s + look_s (back_off_then_look), then sails on.
class StuckWatch {
 public:
  enum class Progress : std::uint8_t {
    kMoving,       // sail on
    kBecameStuck,  // this step: the recovery starts
    kRecovering,   // within the recovery
    kRecovered,    // this step: the recovery ended, sail on
  };
  explicit StuckWatch(const guidance::MapPlannerParams& p) : p_(p) {}
  void reset() {
    stuck_ = false;
    last_step_ns_ = core::kNeverNs;
  }
  /// Once per step. Steps further apart than a second mean the task was paused (a hold): the
  /// progress clock starts again.
  Progress update(core::TimeNs now_ns, core::NavPoint antenna);
  /// Something else moves the boat on its own (another recovery): no stuck meanwhile.
  void progress_made(core::TimeNs now_ns) {
    stuck_ = false;
    progress_ns_ = now_ns;
  }
  [[nodiscard]] double recovery_s(core::TimeNs now_ns) const {
    return core::ns_to_sec(now_ns - stuck_since_ns_);
  }
  /// Why the recovery started: how far the boat moved in the last stuck_s.
  [[nodiscard]] ReasonText stuck_reason(core::NavPoint antenna) const;
  /// The stop, back-off and look times and thrusts the recovery runs on.
  [[nodiscard]] const guidance::MapPlannerParams& params() const { return p_; }

 private:
  guidance::MapPlannerParams p_;
  core::NavPoint progress_at_;
  core::TimeNs progress_ns_ = 0;
  core::TimeNs last_step_ns_ = core::kNeverNs;
  bool stuck_ = false;
  core::TimeNs stuck_since_ns_ = 0;
};

/// `t_s` seconds into a recovery: stopped, then astern on the present heading, then turning to
/// `look_deg` at the look thrust (the times and thrusts of `p`).
void back_off_then_look(const guidance::MapPlannerParams& p, double heading_now_deg, double t_s,
                        double look_deg, GuidanceRequest& out);

/// Steers toward `desired_heading_deg` (true) around the lidar's obstacles nearer than `reach_m`
/// (what lies beyond the goal is not in the way); sets the request's heading and speed factor and
/// the avoidance part of the visualization. No lidar: the heading unchanged. `scratch` holds the
/// filtered obstacles (fixed storage, no allocation).
void steer_clear(guidance::Avoidance& avoidance, const TaskContext& ctx, double desired_heading_deg,
                 double reach_m, perception::ObstacleList& scratch, GuidanceRequest& out);

/// Line following into a slip: the mission's line-following gains, the docking look-ahead.
guidance::LineFollowParams slip_line_params(const config::MissionConfig& m);

/// A slip mouth seen by the lidar, kept in the navigation frame so a scan that misses it does not
/// lose it, smoothed so single-bin jitter of the tips does not steer. Positions from the pose the
/// scan was taken with: a GNSS or compass error moves the boat and the mouth alike, so steering
/// on the pair is as good as the lidar.
class SlipTracker {
 public:
  explicit SlipTracker(const guidance::LineFollowParams& line = {})
      : line_(line), lookahead_m_(line.lookahead_m) {}
  void reset() {
    seen_ = false;
    rejected_ = 0;
    line_.reset();
    last_ns_ = core::kNeverNs;
  }
  /// Starts the line following afresh (a new approach): the integral and its timer cleared, the
  /// slip kept.
  void restart_line() {
    line_.reset();
    last_ns_ = core::kNeverNs;
  }
  /// Adds one sighting (body frame of `pose`). A sighting more than kGateM from the track is a
  /// different gap and ignored, unless the track has seen nothing else for kRestartAfter scans.
  /// Returns whether it was taken.
  bool update(const core::NavPose& pose, const guidance::SlipOpening& s);
  [[nodiscard]] bool seen() const { return seen_; }
  [[nodiscard]] core::NavPoint mouth() const { return mouth_; }
  [[nodiscard]] double axis_true_deg() const { return axis_true_deg_; }
  /// Line following (ILOS: the integral takes out a side current's crab) along the slip's axis,
  /// from `ray_start_m` outside the mouth to its inside, so the boat lines up before the mouth
  /// instead of cutting the corner. `now_ns` times the integral. With `lookahead_per_m` > 0 the
  /// line of sight looks this far ahead per metre still to go to the mouth (never less than the
  /// line's own lookahead): a slip seen far off its axis is joined at an angle the boat can turn
  /// out of before the mouth.
  [[nodiscard]] double follow_heading_deg(const core::NavPose& pose, double ray_start_m,
                                          core::TimeNs now_ns, double lookahead_per_m = 0.0);

 private:
  static constexpr double kGateM = 1.0;
  static constexpr int kRestartAfter = 10;
  bool seen_ = false;
  int rejected_ = 0;
  core::NavPoint mouth_;
  double axis_true_deg_ = 0.0;
  guidance::LineFollower line_;
  double lookahead_m_;
  core::TimeNs last_ns_ = core::kNeverNs;
};

std::unique_ptr<Task> make_hopping_task(const config::TaskConfig& t, const config::MissionConfig& m,
                                        const core::LocalFrame& frame);
/// The 2022 obstacle course, or 2026 course 1 when `course1` (then the turn to find the buoy).
std::unique_ptr<Task> make_avoidance_task(const config::TaskConfig& t,
                                          const config::MissionConfig& m,
                                          const core::LocalFrame& frame, bool course1);
std::unique_ptr<Task> make_course2_task(const config::TaskConfig& t, const config::MissionConfig& m,
                                        const core::LocalFrame& frame);
std::unique_ptr<Task> make_docking2022_task(const config::TaskConfig& t,
                                            const config::MissionConfig& m,
                                            const core::LocalFrame& frame);
std::unique_ptr<Task> make_course3_task(const config::TaskConfig& t,
                                        const config::MissionConfig& m);

}  // namespace coxswain::mission::detail
