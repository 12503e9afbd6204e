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
      : Task(t.name), d_(m.docking), approach_(m.docking.approach) {
    check(m.docking.approach.validate());
    check(m.docking.slip.validate());
  }

  [[nodiscard]] std::uint8_t needs() const override { return kNeedImu | kNeedLidar; }

  ReasonText enter(const TaskContext& ctx) override {
    if (!ctx.heading_valid) return reason_printf("no heading");
    if (!ctx.lidar_fresh) return reason_printf("no lidar scan");
    seen_ = false;
    committed_ = false;
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
      if (const auto s = guidance::find_slip(p, d_.slip, forward_body)) {
        // Into the navigation frame, so a scan that misses the mouth does not lose it; the
        // smoothing rides out single-bin jitter of the tips.
        const double h = core::deg_to_rad(ctx.pose.heading_deg);
        const core::NavPoint mouth{
            ctx.pose.position.north_m + s->mouth_x_m * std::cos(h) - s->mouth_y_m * std::sin(h),
            ctx.pose.position.east_m + s->mouth_x_m * std::sin(h) + s->mouth_y_m * std::cos(h)};
        const double axis = core::wrap_deg(ctx.pose.heading_deg + s->axis_body_deg);
        if (!seen_) {
          mouth_ = mouth;
          axis_true_deg_ = axis;
        } else {
          constexpr double kAlpha = 0.3;
          mouth_.north_m += kAlpha * (mouth.north_m - mouth_.north_m);
          mouth_.east_m += kAlpha * (mouth.east_m - mouth_.east_m);
          axis_true_deg_ =
              core::wrap_deg(axis_true_deg_ + kAlpha * core::angle_diff_deg(axis, axis_true_deg_));
        }
        const double a = core::deg_to_rad(axis_true_deg_);
        const double back_m = 4.0;  // the ray starts this far out on the axis
        (void)approach_.set_ray(
            {mouth_.north_m - back_m * std::cos(a), mouth_.east_m - back_m * std::sin(a)}, mouth_);
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
                                                mouth_m, axis_true_deg_));
        }
      }
    }
    out.steer = true;
    out.desired_heading_deg = forward_true;
    if (committed_) {
      out.desired_heading_deg = axis_true_deg_;
    } else if (seen_) {
      out.desired_heading_deg = approach_.pursue(ctx.pose, std::nullopt).desired_heading_deg;
      ctx.viz->has_goal = true;
      ctx.viz->goal = mouth_;
      ctx.viz->distance_to_go_m = core::distance_m(ctx.pose.position, mouth_);
    }
    out.thrust_frac = d_.approach_thrust_frac;
    return TaskResult::kRunning;
  }

 private:
  config::DockingConfig d_;
  guidance::DockingApproach approach_;
  bool seen_ = false;
  bool committed_ = false;
  core::NavPoint mouth_;
  double axis_true_deg_ = 0.0;
};

}  // namespace

std::unique_ptr<Task> make_course3_task(const config::TaskConfig& t,
                                        const config::MissionConfig& m) {
  return std::make_unique<Course3Task>(t, m);
}

}  // namespace coxswain::mission::detail
