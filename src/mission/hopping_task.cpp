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

/// Hopping tour: line following between the waypoints, speed schedule by distance to go.
class HoppingTask final : public Task {
 public:
  HoppingTask(const config::TaskConfig& t, const config::MissionConfig& m,
              const core::LocalFrame& frame)
      : Task(t.name), leg_(m.waypoints, to_route(t.waypoints, frame)) {}

  [[nodiscard]] std::uint8_t needs() const override { return kNeedGnss | kNeedImu; }

  ReasonText enter(const TaskContext& ctx) override {
    ReasonText r = need_position_heading(ctx);
    if (!r.empty()) return r;
    if (!leg_.start(ctx.antenna)) return reason_printf("no waypoints");
    set_phase("to_wp1", "task entered");
    return {};
  }

  TaskResult step(const TaskContext& ctx, GuidanceRequest& out) override {
    const core::NavPoint before = ctx.antenna;
    const guidance::WaypointGuidance g = leg_.update(ctx);
    if (g.event != guidance::WaypointEvent::kNone) {
      const ReasonText why =
          g.event == guidance::WaypointEvent::kNone
              ? ReasonText{}
              : event_reason(g, core::distance_m(before, leg_.point(g.event_index)));
      if (g.finished) {
        set_reason(reason_printf("route complete: %u arrived, %u missed",
                                 ctx.status->waypoints_arrived, ctx.status->waypoints_missed));
        return TaskResult::kDone;
      }
      FixedText<24> ph;
      (void)std::snprintf(ph.chars.data(), ph.chars.size(), "to_wp%zu", g.index + 1);
      set_phase(ph.view(), why.view());
    }
    if (g.finished) {
      set_reason(reason_printf("route complete"));
      return TaskResult::kDone;
    }
    out.steer = true;
    out.desired_heading_deg = g.desired_heading_deg;
    out.schedule_distance_m = g.distance_to_go_m;
    return TaskResult::kRunning;
  }

 private:
  RouteLeg leg_;
};

}  // namespace

std::unique_ptr<Task> make_hopping_task(const config::TaskConfig& t, const config::MissionConfig& m,
                                        const core::LocalFrame& frame) {
  return std::make_unique<HoppingTask>(t, m, frame);
}

}  // namespace coxswain::mission::detail
