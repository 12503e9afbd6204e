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

/// Avoidance toward the waypoints (the gate); for course 1, then the turn to find the buoy.
class AvoidanceTask final : public AvoidingTask {
 public:
  AvoidanceTask(const config::TaskConfig& t, const config::MissionConfig& m,
                const core::LocalFrame& frame, bool course1)
      : AvoidingTask(t.name, m.avoidance),
        leg_(m.waypoints, to_route(t.waypoints, frame)),
        course1_(course1),
        c1_(m.course1),
        cruise_(m.speed.cruise_thrust_frac) {}

  [[nodiscard]] std::uint8_t needs() const override { return kNeedGnss | kNeedImu | kNeedLidar; }

  ReasonText enter(const TaskContext& ctx) override {
    ReasonText r = need_position_heading(ctx);
    if (!r.empty()) return r;
    if (!ctx.lidar_fresh) return reason_printf("no lidar scan");
    if (!leg_.start(ctx.antenna)) return reason_printf("no waypoints");
    avoidance_->reset();
    search_ = false;
    set_phase(course1_ ? "to_waypoint" : "navigate", "task entered");
    return {};
  }

  TaskResult step(const TaskContext& ctx, GuidanceRequest& out) override {
    if (search_) return search(ctx, out);
    const guidance::WaypointGuidance g = leg_.update(ctx);
    if (g.event != guidance::WaypointEvent::kNone && !g.finished) {
      set_reason(event_reason(g, core::distance_m(ctx.antenna, leg_.point(g.event_index))).view());
    }
    if (g.finished) {
      if (!course1_) {
        set_reason(reason_printf("passed the final gate"));
        return TaskResult::kDone;
      }
      search_ = true;
      search_since_ns_ = ctx.now_ns;
      search_heading_deg_ = core::wrap_deg(ctx.pose.heading_deg + c1_.turn_deg);
      set_phase(
          "search_buoy",
          reason_printf("reached the waypoint; turning %.0f deg to find "
                        "the %s buoy",
                        c1_.turn_deg, std::string_view(msg::colour_name(c1_.buoy_colour)).data())
              .view());
      return search(ctx, out);
    }
    const double goal_body = core::angle_diff_deg(g.desired_heading_deg, ctx.pose.heading_deg);
    const guidance::AvoidanceDecision d = avoidance_->decide(*ctx.obstacles, goal_body, ctx.now_ns);
    VizFrame& v = *ctx.viz;
    v.has_avoidance = true;
    v.avoidance_bearing_body_deg = d.bearing_body_deg;
    v.avoidance_status = static_cast<std::uint8_t>(d.status);
    v.danger_count = std::min<std::uint32_t>(d.bin_count, VizFrame::kMaxDangerBins);
    v.danger_min_deg = d.bin_min_deg;
    v.danger_bin_width_deg = d.bin_width_deg;
    std::copy_n(d.danger.begin(), v.danger_count, v.danger.begin());
    out.steer = true;
    out.desired_heading_deg = core::wrap_deg(ctx.pose.heading_deg + d.bearing_body_deg);
    out.thrust_frac = cruise_;
    out.speed_factor = d.speed_factor;
    return TaskResult::kRunning;
  }

 private:
  TaskResult search(const TaskContext& ctx, GuidanceRequest& out) {
    if (ctx.camera_new && ctx.camera != nullptr) {
      if (const msg::Detection* d = largest_of(*ctx.camera, c1_.buoy_colour)) {
        set_reason(reason_printf("%s buoy seen at %.0f deg",
                                 std::string_view(msg::colour_name(c1_.buoy_colour)).data(),
                                 static_cast<double>(d->bearing_deg)));
        return TaskResult::kDone;
      }
    }
    if (core::ns_to_sec(ctx.now_ns - search_since_ns_) >= c1_.search_timeout_s) {
      set_reason(reason_printf("buoy not seen within %.1f s; moving on", c1_.search_timeout_s));
      return TaskResult::kDone;
    }
    out.steer = true;
    out.desired_heading_deg = search_heading_deg_;
    out.thrust_frac = c1_.search_thrust_frac;
    return TaskResult::kRunning;
  }

  RouteLeg leg_;
  bool course1_;
  config::Course1Config c1_;
  double cruise_;
  bool search_ = false;
  core::TimeNs search_since_ns_ = 0;
  double search_heading_deg_ = 0.0;
};

}  // namespace

std::unique_ptr<Task> make_avoidance_task(const config::TaskConfig& t,
                                          const config::MissionConfig& m,
                                          const core::LocalFrame& frame, bool course1) {
  return std::make_unique<AvoidanceTask>(t, m, frame, course1);
}

}  // namespace coxswain::mission::detail
