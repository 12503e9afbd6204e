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
class Course2Task final : public Task {
 public:
  enum class Phase : std::uint8_t { kCircling, kSeekColour, kToWaypoint };

  Course2Task(const config::TaskConfig& t, const config::MissionConfig& m,
              const core::LocalFrame& frame)
      : Task(t.name),
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
    out.desired_heading_deg = g.desired_heading_deg;
    out.schedule_distance_m = g.distance_to_go_m;
    return TaskResult::kRunning;
  }

 private:
  TaskResult circle(const TaskContext& ctx, GuidanceRequest& out) {
    guidance::BuoyObservation obs;
    // An old bearing steered on while the heading changes would overshoot: only recent frames.
    if (ctx.camera != nullptr &&
        core::ns_to_sec(ctx.now_ns - ctx.camera->stamp_ns) <= c_.buoy_memory_s) {
      if (const msg::Detection* d = largest_of(*ctx.camera, c_.buoy_colour)) {
        obs.bearing_deg = static_cast<double>(d->bearing_deg);
        if (ctx.lidar_fresh && ctx.profile != nullptr) {
          obs.range_m = range_near(*ctx.profile, *obs.bearing_deg, c_.buoy_range_window_deg);
        }
      }
    }
    const guidance::BuoyCirclingOutput o = circling_.update(ctx.pose.heading_deg, obs);
    if (o.done) {
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
    out.desired_heading_deg =
        control::true_from_course_deg(c_.exit_course_deg, ctx.course_zero_deg);
    out.thrust_frac = c_.seek_thrust_frac;
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
  RouteLeg leg_;
  std::array<perception::MarkerVote, 8> votes_;
  std::array<msg::Colour, 8> colours_{};
  std::size_t colour_count_ = 0;
  Phase phase_ = Phase::kCircling;
  core::TimeNs seek_since_ns_ = 0;
};

}  // namespace

std::unique_ptr<Task> make_course2_task(const config::TaskConfig& t, const config::MissionConfig& m,
                                        const core::LocalFrame& frame) {
  return std::make_unique<Course2Task>(t, m, frame);
}

}  // namespace coxswain::mission::detail
