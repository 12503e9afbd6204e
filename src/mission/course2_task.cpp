// SPDX-License-Identifier: Apache-2.0
#include "task_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "coxswain/control/heading_reference.hpp"
#include "coxswain/core/angles.hpp"
#include "coxswain/guidance/buoy_circling.hpp"
#include "coxswain/guidance/docking_approach.hpp"
#include "coxswain/guidance/waypoint_follower.hpp"
#include "coxswain/perception/marker_vote.hpp"

namespace coxswain::mission::detail {

namespace {

/// Circle the buoy once on the camera side, identify the target colour, light the LED, go on.
class Course2Task final : public AvoidingTask {
 public:
  enum class Phase : std::uint8_t { kCircling, kSeekColour, kToWaypoint };

  Course2Task(const config::TaskConfig& t, const config::MissionConfig& m,
              const core::LocalFrame& frame)
      : AvoidingTask(t.name, m.avoidance),
        c_(m.course2),
        circling_(m.course2.circling),
        leg_(m.waypoints, to_route(t.waypoints, frame)),
        votes_{perception::MarkerVote(m.vision_vote), perception::MarkerVote(m.vision_vote),
               perception::MarkerVote(m.vision_vote), perception::MarkerVote(m.vision_vote),
               perception::MarkerVote(m.vision_vote), perception::MarkerVote(m.vision_vote),
               perception::MarkerVote(m.vision_vote), perception::MarkerVote(m.vision_vote)} {
    check(m.course2.circling.validate());
    colour_count_ = std::min<std::size_t>(m.course2.colours.size(), colours_.size());
    for (std::size_t i = 0; i < colour_count_; ++i) colours_[i] = m.course2.colours[i];
  }

  [[nodiscard]] std::uint8_t needs() const override { return kNeedGnss | kNeedImu; }

  ReasonText enter(const TaskContext& ctx) override {
    ReasonText r = need_position_heading(ctx);
    if (!r.empty()) return r;
    circling_.reset();
    avoidance_->reset();
    tracked_ = false;
    for (auto& v : votes_) v.reset();
    phase_ = Phase::kCircling;
    set_phase("circling", "task entered");
    return {};
  }

  TaskResult step(const TaskContext& ctx, GuidanceRequest& out) override {
    switch (phase_) {
      case Phase::kCircling:
        return circle(ctx, out);
      case Phase::kSeekColour:
        return seek(ctx, out);
      case Phase::kToWaypoint:
        break;
    }
    const guidance::WaypointGuidance g = leg_.update(ctx);
    if (g.finished) {
      set_reason(reason_printf("reached the course 2 waypoint"));
      return TaskResult::kDone;
    }
    out.steer = true;
    out.schedule_distance_m = g.distance_to_go_m;
    steer_clear(*avoidance_, ctx, g.desired_heading_deg, kAvoidReachM, near_, out);
    return TaskResult::kRunning;
  }

 private:
  // Leaving the circle, the buoy itself is in the way: every leg after it avoids obstacles
  // this near.
  static constexpr double kAvoidReachM = 8.0;

  TaskResult circle(const TaskContext& ctx, GuidanceRequest& out) {
    guidance::BuoyObservation obs;
    const msg::Detection* seen = nullptr;
    // An old bearing steered on while the heading changes would overshoot: only recent frames.
    if (ctx.camera != nullptr &&
        core::ns_to_sec(ctx.now_ns - ctx.camera->stamp_ns) <= c_.buoy_memory_s) {
      seen = largest_of(*ctx.camera, c_.buoy_colour);
    }
    if (c_.lidar_tracking) track(ctx, seen);
    if (tracked_) {
      const core::BodyPoint b = core::nav_to_body(ctx.pose, buoy_);
      obs.bearing_deg = core::rad_to_deg(std::atan2(b.starboard_m, b.forward_m));
      obs.range_m = std::max(std::hypot(b.forward_m, b.starboard_m) - c_.buoy_radius_m, 0.0);
      ctx.viz->has_goal = true;
      ctx.viz->goal = buoy_;
      ctx.viz->distance_to_go_m = *obs.range_m;
    } else if (seen != nullptr) {
      obs.bearing_deg = static_cast<double>(seen->bearing_deg);
      if (ctx.lidar_fresh && ctx.profile != nullptr) {
        obs.range_m = range_near(*ctx.profile, *obs.bearing_deg, c_.buoy_range_window_deg);
      }
    }
    const guidance::BuoyCirclingOutput o = circling_.update(ctx.pose.heading_deg, obs);
    // Leaving across the circle can run the boat into whatever is just outside it (the buoy
    // near a wall): circle on until the heading points the way out.
    const double exit_true = control::true_from_course_deg(c_.exit_course_deg, ctx.course_zero_deg);
    if (o.done &&
        std::abs(core::angle_diff_deg(ctx.pose.heading_deg, exit_true)) <= c_.exit_align_deg) {
      phase_ = Phase::kSeekColour;
      seek_since_ns_ = ctx.now_ns;
      set_phase("seek_colour",
                reason_printf("one full turn around the buoy (%.0f deg)", o.progress_deg).view());
      return seek(ctx, out);
    }
    out.steer = true;
    out.desired_heading_deg = o.desired_heading_deg;
    out.thrust_frac = c_.circling_thrust_frac;
    return TaskResult::kRunning;
  }

  /// Lidar tracking of the buoy in the navigation frame: found by the camera (bearing) and the
  /// lidar (range), then followed scan by scan as the nearest small obstacle to where it should
  /// be. Lost after track_timeout_s unseen; a camera sight far from the track re-acquires it.
  void track(const TaskContext& ctx, const msg::Detection* seen) {
    if (tracked_ && core::ns_to_sec(ctx.now_ns - buoy_seen_ns_) > c_.track_timeout_s) {
      tracked_ = false;
    }
    if (seen != nullptr && ctx.lidar_fresh && ctx.profile != nullptr) {
      const double bearing = static_cast<double>(seen->bearing_deg);
      bool agrees = false;
      if (tracked_) {
        const core::BodyPoint b = core::nav_to_body(ctx.pose, buoy_);
        const double track_bearing = core::rad_to_deg(std::atan2(b.starboard_m, b.forward_m));
        agrees = std::abs(core::angle_diff_deg(track_bearing, bearing)) <= 15.0;
      }
      if (!agrees) {
        if (const auto r = range_near(*ctx.profile, bearing, c_.buoy_range_window_deg)) {
          const double b = core::deg_to_rad(bearing);
          const double d = *r + c_.buoy_radius_m;
          buoy_ = core::body_to_nav(ctx.pose, {d * std::cos(b), d * std::sin(b)});
          tracked_ = true;
          buoy_seen_ns_ = ctx.now_ns;
        }
      }
    }
    if (!tracked_ || !ctx.lidar_new || ctx.obstacles == nullptr) return;
    const core::BodyPoint predicted = core::nav_to_body(ctx.pose, buoy_);
    double best_m = c_.track_gate_m;
    std::optional<core::BodyPoint> best;
    for (std::uint32_t i = 0; i < ctx.obstacles->count; ++i) {
      const perception::ObstacleSegment& seg = ctx.obstacles->segments[i];
      const double x = 0.5 * (seg.begin.forward_m + seg.end.forward_m);
      const double y = 0.5 * (seg.begin.starboard_m + seg.end.starboard_m);
      const double length = std::hypot(seg.end.forward_m - seg.begin.forward_m,
                                       seg.end.starboard_m - seg.begin.starboard_m);
      if (length > 2.0 * c_.buoy_radius_m + 0.3) continue;  // a wall piece, not the buoy
      // The lidar sees the near side: the centre is a radius farther along the ray.
      const double r = std::hypot(x, y);
      if (!(r > 0.0)) continue;
      const core::BodyPoint centre{x * (r + c_.buoy_radius_m) / r, y * (r + c_.buoy_radius_m) / r};
      const double miss = std::hypot(centre.forward_m - predicted.forward_m,
                                     centre.starboard_m - predicted.starboard_m);
      if (miss < best_m) {
        best_m = miss;
        best = centre;
      }
    }
    if (!best) return;
    const core::NavPoint measured = core::body_to_nav(ctx.pose, *best);
    constexpr double kAlpha = 0.5;
    buoy_.north_m += kAlpha * (measured.north_m - buoy_.north_m);
    buoy_.east_m += kAlpha * (measured.east_m - buoy_.east_m);
    buoy_seen_ns_ = ctx.now_ns;
  }

  TaskResult seek(const TaskContext& ctx, GuidanceRequest& out) {
    if (ctx.camera_new && ctx.camera != nullptr) {
      for (std::size_t i = 0; i < colour_count_; ++i) {
        const bool seen =
            colours_[i] != c_.buoy_colour && largest_of(*ctx.camera, colours_[i]) != nullptr;
        (void)votes_[i].add(ctx.camera->stamp_ns, seen);
      }
    }
    for (std::size_t i = 0; i < colour_count_; ++i) {
      const perception::VoteTally t = votes_[i].tally(ctx.now_ns);
      if (!t.decided) continue;
      ctx.status->identified_colour = colours_[i];
      out.led = led_for(colours_[i]);
      return to_waypoint(
          ctx,
          reason_printf("target colour %s (%zu of %zu frames)",
                        std::string_view(msg::colour_name(colours_[i])).data(), t.hits, t.frames),
          out);
    }
    if (core::ns_to_sec(ctx.now_ns - seek_since_ns_) >= c_.colour_timeout_s) {
      return to_waypoint(ctx, reason_printf("no colour within %.0f s", c_.colour_timeout_s), out);
    }
    out.steer = true;
    out.thrust_frac = c_.seek_thrust_frac;
    steer_clear(*avoidance_, ctx,
                control::true_from_course_deg(c_.exit_course_deg, ctx.course_zero_deg),
                kAvoidReachM, near_, out);
    return TaskResult::kRunning;
  }

  TaskResult to_waypoint(const TaskContext& ctx, const ReasonText& why, GuidanceRequest& out) {
    if (!leg_.start(ctx.antenna)) {
      set_reason(reason_printf("no waypoint after the colour"));
      return TaskResult::kDone;
    }
    phase_ = Phase::kToWaypoint;
    set_phase("to_waypoint", why.view());
    out.steer = false;
    return TaskResult::kRunning;
  }

  config::Course2Config c_;
  guidance::BuoyCircling circling_;
  perception::ObstacleList near_;
  RouteLeg leg_;
  std::array<perception::MarkerVote, 8> votes_;
  std::array<msg::Colour, 8> colours_{};
  std::size_t colour_count_ = 0;
  Phase phase_ = Phase::kCircling;
  core::TimeNs seek_since_ns_ = 0;
  bool tracked_ = false;  // the buoy's position is known (lidar track)
  core::NavPoint buoy_;
  core::TimeNs buoy_seen_ns_ = 0;
};

}  // namespace

std::unique_ptr<Task> make_course2_task(const config::TaskConfig& t, const config::MissionConfig& m,
                                        const core::LocalFrame& frame) {
  return std::make_unique<Course2Task>(t, m, frame);
}

}  // namespace coxswain::mission::detail
