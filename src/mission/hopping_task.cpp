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
#include "coxswain/guidance/turn_side.hpp"
#include "coxswain/guidance/waypoint_follower.hpp"
#include "coxswain/perception/marker_vote.hpp"

namespace coxswain::mission::detail {

namespace {

/// Hopping tour: line following between the waypoints, speed schedule by distance to go. With
/// a lidar, a large turn at a waypoint goes the long way round when the short way's turning
/// circle is blocked (a pool's wall); a boat that makes no progress (pinned on a wall) stops,
/// backs off and turns to the leg.
class HoppingTask final : public Task {
 public:
  HoppingTask(const config::TaskConfig& t, const config::MissionConfig& m,
              const core::LocalFrame& frame)
      : Task(t.name),
        leg_(m.waypoints, to_route(t.waypoints, frame)),
        progress_(m.planning.planner),
        turn_(m.planning.turn_side, guidance::TurnHull::from(m.avoidance, m.planning.turn_side)),
        hard_turn_(guidance::TurnHull::from(m.avoidance)) {}

  [[nodiscard]] std::uint8_t needs() const override { return kNeedGnss | kNeedImu; }

  ReasonText enter(const TaskContext& ctx) override {
    ReasonText r = need_position_heading(ctx);
    if (!r.empty()) return r;
    if (!leg_.start(ctx.antenna)) return reason_printf("no waypoints");
    progress_.reset();
    turn_.reset();
    set_phase("to_wp1", "task entered");
    return {};
  }

  TaskResult step(const TaskContext& ctx, GuidanceRequest& out) override {
    const core::NavPoint before = ctx.antenna;
    const guidance::WaypointGuidance g = leg_.update(ctx);
    if (g.event != guidance::WaypointEvent::kNone) {
      turn_.reset();  // a new leg: its turn is chosen afresh
      const ReasonText why =
          g.event == guidance::WaypointEvent::kNone
              ? ReasonText{}
              : event_reason(g, core::distance_m(before, leg_.point(g.event_index)));
      if (g.finished) {
        set_reason(reason_printf("route complete: %u arrived, %u missed",
                                 ctx.status->waypoints_arrived, ctx.status->waypoints_missed));
        return TaskResult::kDone;
      }
      set_phase(leg_phase(g).view(), why.view());
    }
    if (g.finished) {
      set_reason(reason_printf("route complete"));
      return TaskResult::kDone;
    }
    out.steer = true;
    out.schedule_distance_m = g.distance_to_go_m;
    switch (progress_.update(ctx.now_ns, ctx.antenna)) {
      case StuckWatch::Progress::kBecameStuck:
        set_phase("stuck", progress_.stuck_reason(ctx.antenna).view());
        [[fallthrough]];
      case StuckWatch::Progress::kRecovering:
        back_off_then_look(progress_.params(), ctx.pose.heading_deg,
                           progress_.recovery_s(ctx.now_ns), g.desired_heading_deg, out);
        return TaskResult::kRunning;
      case StuckWatch::Progress::kRecovered:
        set_phase(leg_phase(g).view(), "backed off; on along the leg");
        break;
      case StuckWatch::Progress::kMoving:
        break;
    }
    if (ctx.lidar_new && ctx.obstacles != nullptr) {
      turn_.observe(*ctx.obstacles);
    } else if (!ctx.lidar_fresh) {
      turn_.forget();
    }
    double desired_deg = g.desired_heading_deg;
    // A waypoint inside the turning circle would be circled for ever: straight on first, until
    // the turn can reach it.
    if (turn_.side() == guidance::TurnSideChooser::Side::kShortest && turn_.enabled() &&
        guidance::inside_turning_circle(core::nav_to_body(ctx.pose, g.target), hard_turn_,
                                        std::max(g.reach_m, kMinReachM))) {
      desired_deg = ctx.pose.heading_deg;
    }
    out.desired_heading_deg = turn_.steer(ctx.pose.heading_deg, desired_deg);
    return TaskResult::kRunning;
  }

 private:
  // A point out of the estimate's reach is still steered through as nearly as the turn allows.
  static constexpr double kMinReachM = 0.3;

  static FixedText<24> leg_phase(const guidance::WaypointGuidance& g) {
    FixedText<24> ph;
    (void)std::snprintf(ph.chars.data(), ph.chars.size(), "to_wp%zu", g.index + 1);
    return ph;
  }

  RouteLeg leg_;
  StuckWatch progress_;
  guidance::TurnSideChooser turn_;
  guidance::TurnHull hard_turn_;  // the swept hull's hard turn: where a point cannot be reached
};

}  // namespace

std::unique_ptr<Task> make_hopping_task(const config::TaskConfig& t, const config::MissionConfig& m,
                                        const core::LocalFrame& frame) {
  return std::make_unique<HoppingTask>(t, m, frame);
}

}  // namespace coxswain::mission::detail
