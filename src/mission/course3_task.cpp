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

/// Most open direction that is both ahead (front 180 deg) and inside the course's forward
/// half-plane; stop when the range ahead is under the stop distance. Lidar and IMU only.
class Course3Task final : public Task {
 public:
  Course3Task(const config::TaskConfig& t, const config::MissionConfig& m)
      : Task(t.name), d_(m.docking) {
    check(m.docking.approach.validate());
  }

  [[nodiscard]] std::uint8_t needs() const override { return kNeedImu | kNeedLidar; }

  ReasonText enter(const TaskContext& ctx) override {
    if (!ctx.heading_valid) return reason_printf("no heading");
    if (!ctx.lidar_fresh) return reason_printf("no lidar scan");
    set_phase("seek_open", "task entered");
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
    const double w = static_cast<double>(p.bin_width_deg);
    const std::size_t bins = std::min<std::size_t>(p.bin_count, p.closest_range_m.size());
    const auto window = static_cast<std::ptrdiff_t>(std::ceil(d_.open_window_deg / w));
    double best_range = -1.0;
    double best_bearing = 0.0;
    for (std::size_t i = 0; i < bins; ++i) {
      const double b = -180.0 + (static_cast<double>(i) + 0.5) * w;
      if (std::abs(b) > 90.0) continue;  // the front 180 deg of the lidar
      const double course =
          control::course_from_true_deg(ctx.pose.heading_deg + b, ctx.course_zero_deg);
      if (std::abs(course) > 90.0) continue;  // the course's forward half-plane
      // A direction is as open as its narrowest neighbour within the hull window.
      double r = d_.open_max_range_m;
      for (std::ptrdiff_t k = -window; k <= window; ++k) {
        const auto j = static_cast<std::size_t>(
            (static_cast<std::ptrdiff_t>(i) + k + static_cast<std::ptrdiff_t>(bins)) %
            static_cast<std::ptrdiff_t>(bins));
        const float rj = p.closest_range_m[j];
        if (rj > 0.0F && rj < perception::RangeProfile::kNoReturn) {
          r = std::min(r, static_cast<double>(rj));
        }
      }
      // Ties go to the direction nearer the bow (less turning).
      if (r > best_range + 1e-9 ||
          (std::abs(r - best_range) <= 1e-9 && std::abs(b) < std::abs(best_bearing))) {
        best_range = r;
        best_bearing = b;
      }
    }
    out.steer = true;
    out.desired_heading_deg = best_range < 0.0
                                  ? control::true_from_course_deg(0.0, ctx.course_zero_deg)
                                  : core::wrap_deg(ctx.pose.heading_deg + best_bearing);
    out.thrust_frac = d_.approach_thrust_frac;
    ctx.viz->has_avoidance = best_range >= 0.0;
    ctx.viz->avoidance_bearing_body_deg = best_bearing;
    return TaskResult::kRunning;
  }

 private:
  config::DockingConfig d_;
};

}  // namespace

std::unique_ptr<Task> make_course3_task(const config::TaskConfig& t,
                                        const config::MissionConfig& m) {
  return std::make_unique<Course3Task>(t, m);
}

}  // namespace coxswain::mission::detail
