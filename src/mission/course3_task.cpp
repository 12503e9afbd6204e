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

/// Find the slip's mouth in the lidar profile (two tips with a deeper inside, within the
/// course's forward half-plane) and pursue a point along its axis, so the boat lines up before
/// the mouth; once the mouth is near, hold the axis; stop when the range ahead is under the stop
/// distance. Until the slip is in lidar range: the course's forward direction. Lidar and IMU only.
/// ("The most open direction" of the plan picked a pond's corner beside the dock.)
class Course3Task final : public Task {
 public:
  Course3Task(const config::TaskConfig& t, const config::MissionConfig& m)
      : Task(t.name), d_(m.docking), slip_(slip_line_params(m)) {
    check(m.docking.approach.validate());
    check(m.docking.slip.validate());
  }

  [[nodiscard]] std::uint8_t needs() const override { return kNeedImu | kNeedLidar; }

  ReasonText enter(const TaskContext& ctx) override {
    if (!ctx.heading_valid) return reason_printf("no heading");
    if (!ctx.lidar_fresh) return reason_printf("no lidar scan");
    seen_ = false;
    committed_ = false;
    slip_.reset();
    set_phase("seek_slip", "task entered");
    return {};
  }

  TaskResult step(const TaskContext& ctx, GuidanceRequest& out) override {
    const perception::RangeProfile& p = *ctx.profile;
    const std::optional<double> ahead =
        guidance::min_range_ahead_m(p, d_.approach.ahead_half_angle_deg);
    if (ahead && *ahead < d_.approach.stop_range_m) {
      set_reason(reason_printf("stopped %.2f m from the dock", *ahead));
      return TaskResult::kDone;
    }
    const double forward_true = control::true_from_course_deg(0.0, ctx.course_zero_deg);
    if (ctx.lidar_new && !committed_) {
      const double forward_body = core::angle_diff_deg(forward_true, ctx.pose.heading_deg);
      if (const auto s = guidance::find_slip(p, d_.slip, forward_body);
          s && slip_.update(ctx.pose, *s)) {
        const double mouth_m = std::hypot(s->mouth_x_m, s->mouth_y_m);
        if (!seen_) {
          seen_ = true;
          set_phase("approach_slip",
                    reason_printf("slip mouth %.1f m away, %.1f m wide", mouth_m, s->width_m));
        }
        if (mouth_m < d_.commit_range_m) {
          committed_ = true;
          set_phase("enter_slip", reason_printf("mouth %.2f m away: holding the slip's axis "
                                                "%.0f deg",
                                                mouth_m, slip_.axis_true_deg()));
        }
      }
    }
    out.steer = true;
    out.desired_heading_deg = forward_true;
    if (seen_) {
      // Committed (mouth close): the track is no longer updated; the line still steers.
      constexpr double kRayStartM = 4.0;
      out.desired_heading_deg = slip_.follow_heading_deg(ctx.pose, kRayStartM, ctx.now_ns);
      ctx.viz->has_goal = true;
      ctx.viz->goal = slip_.mouth();
      ctx.viz->distance_to_go_m = core::distance_m(ctx.pose.position, slip_.mouth());
    }
    out.thrust_frac = d_.approach_thrust_frac;
    return TaskResult::kRunning;
  }

 private:
  config::DockingConfig d_;
  SlipTracker slip_;
  bool seen_ = false;
  bool committed_ = false;
};

}  // namespace

std::unique_ptr<Task> make_course3_task(const config::TaskConfig& t,
                                        const config::MissionConfig& m) {
  return std::make_unique<Course3Task>(t, m);
}

}  // namespace coxswain::mission::detail
