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

/// Visit each slip's decision point, face its marker and vote; enter the target slip by ray
/// pursuit; stop by lidar.
class Docking2022Task final : public Task {
 public:
  static constexpr std::size_t kMaxSlips = 8;
  enum class Phase : std::uint8_t { kGoto, kFace, kEnter };

  Docking2022Task(const config::TaskConfig& t, const config::MissionConfig& m,
                  const core::LocalFrame& frame)
      : Task(t.name),
        d_(m.docking),
        waypoint_params_(m.waypoints),
        follower_(m.waypoints),
        vote_(m.vision_vote),
        approach_(m.docking.approach),
        dock_heading_deg_(t.dock_heading_deg),
        config_colour_(t.target_colour),
        config_shape_(t.target_shape) {
    check(m.docking.approach.validate());
    slip_count_ = std::min(t.slips.size(), kMaxSlips);
    const double c = std::cos(core::deg_to_rad(t.dock_heading_deg));
    const double s = std::sin(core::deg_to_rad(t.dock_heading_deg));
    for (std::size_t i = 0; i < slip_count_; ++i) {
      slips_[i] = frame.to_nav(t.slips[i]);
      decision_[i] = {slips_[i].north_m - d_.decision_distance_m * c,
                      slips_[i].east_m - d_.decision_distance_m * s};
    }
  }

  [[nodiscard]] std::uint8_t needs() const override { return kNeedGnss | kNeedImu | kNeedLidar; }

  ReasonText enter(const TaskContext& ctx) override {
    ReasonText r = need_position_heading(ctx);
    if (!r.empty()) return r;
    colour_ = ctx.target_colour != msg::Colour::kUnknown ? ctx.target_colour : config_colour_;
    shape_ = ctx.target_shape != msg::Shape::kUnknown ? ctx.target_shape : config_shape_;
    if (colour_ == msg::Colour::kUnknown || shape_ == msg::Shape::kUnknown) {
      return reason_printf(
          "no target marker (give one on the command line or the control "
          "interface)");
    }
    if (slip_count_ == 0) return reason_printf("no slips configured");
    ratio_.fill(-1.0);
    approach_.reset();
    ctx.status->docking_slip = -1;
    goto_slip(
        ctx, 0,
        reason_printf("looking for the %s %s", std::string_view(msg::colour_name(colour_)).data(),
                      std::string_view(msg::shape_name(shape_)).data()));
    return {};
  }

  TaskResult step(const TaskContext& ctx, GuidanceRequest& out) override {
    if (phase_ == Phase::kGoto) {
      const guidance::WaypointGuidance g = follower_.update(ctx.antenna, ctx.now_ns);
      viz_goal(ctx, decision_[slip_]);
      if (g.finished) {
        phase_ = Phase::kFace;
        face_since_ns_ = ctx.now_ns;
        vote_.reset();
        set_phase(slip_phase("face_slip").view(),
                  reason_printf("at the decision point of slip %zu", slip_ + 1));
      } else {
        out.steer = true;
        out.desired_heading_deg = g.desired_heading_deg;
        out.schedule_distance_m = g.distance_to_go_m;
        return TaskResult::kRunning;
      }
    }
    if (phase_ == Phase::kFace) return face(ctx, out);
    // Enter by ray pursuit; the stop is latched by the lidar range ahead.
    std::optional<double> ahead;
    if (ctx.lidar_fresh && ctx.profile != nullptr) {
      ahead = guidance::min_range_ahead_m(*ctx.profile, d_.approach.ahead_half_angle_deg);
    }
    const guidance::DockingCommand c = approach_.pursue(ctx.pose, ahead);
    viz_goal(ctx, slips_[slip_]);
    if (c.stop) {
      set_reason(
          reason_printf("docked in slip %zu (%.2f m ahead)", slip_ + 1, ahead ? *ahead : -1.0));
      return TaskResult::kDone;
    }
    out.steer = true;
    out.desired_heading_deg = c.desired_heading_deg;
    out.thrust_frac = d_.approach_thrust_frac;
    return TaskResult::kRunning;
  }

 private:
  FixedText<24> slip_phase(const char* stem) const {
    FixedText<24> p;
    (void)std::snprintf(p.chars.data(), p.chars.size(), "%s%zu", stem, slip_ + 1);
    return p;
  }

  static void viz_goal(const TaskContext& ctx, core::NavPoint p) {
    ctx.viz->has_goal = true;
    ctx.viz->goal = p;
    ctx.viz->distance_to_go_m = core::distance_m(ctx.antenna, p);
  }

  void goto_slip(const TaskContext& ctx, std::size_t i, const ReasonText& why) {
    slip_ = i;
    phase_ = Phase::kGoto;
    const std::array<core::NavPoint, 1> route{decision_[i]};
    (void)follower_.set_route(route);
    (void)ctx;
    set_phase(slip_phase("goto_slip").view(), why.view());
  }

  TaskResult enter_slip(const TaskContext& ctx, std::size_t i, const ReasonText& why) {
    slip_ = i;
    phase_ = Phase::kEnter;
    ctx.status->docking_slip = static_cast<std::int32_t>(i);
    if (!approach_.set_ray(decision_[i], slips_[i])) {
      set_reason(reason_printf("slip %zu: decision point equals the slip", i + 1));
      return TaskResult::kFailed;
    }
    approach_.reset();
    set_phase(slip_phase("enter_slip").view(), why.view());
    return TaskResult::kRunning;
  }

  TaskResult face(const TaskContext& ctx, GuidanceRequest& out) {
    const double err = core::angle_diff_deg(dock_heading_deg_, ctx.pose.heading_deg);
    const bool facing = std::abs(err) <= d_.face_tolerance_deg;
    if (facing && ctx.camera_new && ctx.camera != nullptr) {
      bool seen = false;
      const std::uint32_t n =
          std::min<std::uint32_t>(ctx.camera->count, msg::CameraDetections::kMaxDetections);
      for (std::uint32_t k = 0; k < n; ++k) {
        const msg::Detection& det = ctx.camera->detections[k];
        // A neighbouring slip's marker is in the frame too, off to the side: not this slip's.
        const bool centred = std::abs(static_cast<double>(det.bearing_deg)) <= d_.marker_window_deg;
        seen = seen || (centred && det.colour == colour_ && det.shape == shape_);
      }
      (void)vote_.add(ctx.camera->stamp_ns, seen);
    }
    const perception::VoteTally t = vote_.tally(ctx.now_ns);
    ratio_[slip_] = t.ratio;
    if (t.decided) {
      return enter_slip(ctx, slip_,
                        reason_printf("target marker at slip %zu (%zu of %zu frames)", slip_ + 1,
                                      t.hits, t.frames));
    }
    if (core::ns_to_sec(ctx.now_ns - face_since_ns_) >= d_.face_time_s) {
      if (slip_ + 1 < slip_count_) {
        goto_slip(ctx, slip_ + 1,
                  reason_printf("slip %zu is not the target (ratio %.2f)", slip_ + 1, t.ratio));
        out.steer = false;
        return TaskResult::kRunning;
      }
      // Every slip seen without a decision: the best ratio, if the target was seen at all.
      std::size_t best = 0;
      for (std::size_t i = 1; i < slip_count_; ++i) {
        if (ratio_[i] > ratio_[best]) best = i;
      }
      if (ratio_[best] > 0.0) {
        return enter_slip(ctx, best,
                          reason_printf("no slip decided; slip %zu has the best "
                                        "ratio %.2f",
                                        best + 1, ratio_[best]));
      }
      set_reason(reason_printf("target marker not seen at any slip"));
      return TaskResult::kFailed;
    }
    // Turn toward the marker slowly; once facing, drift while the votes come in.
    out.steer = true;
    out.desired_heading_deg = dock_heading_deg_;
    out.thrust_frac = facing ? 0.0 : d_.approach_thrust_frac * 0.5;
    return TaskResult::kRunning;
  }

  config::DockingConfig d_;
  guidance::WaypointFollowerParams waypoint_params_;
  guidance::WaypointFollower follower_;
  perception::MarkerVote vote_;
  guidance::DockingApproach approach_;
  double dock_heading_deg_;
  msg::Colour config_colour_;
  msg::Shape config_shape_;
  msg::Colour colour_ = msg::Colour::kUnknown;
  msg::Shape shape_ = msg::Shape::kUnknown;
  std::array<core::NavPoint, kMaxSlips> slips_{};
  std::array<core::NavPoint, kMaxSlips> decision_{};
  std::array<double, kMaxSlips> ratio_{};
  std::size_t slip_count_ = 0;
  std::size_t slip_ = 0;
  Phase phase_ = Phase::kGoto;
  core::TimeNs face_since_ns_ = 0;
};

}  // namespace

std::unique_ptr<Task> make_docking2022_task(const config::TaskConfig& t,
                                            const config::MissionConfig& m,
                                            const core::LocalFrame& frame) {
  return std::make_unique<Docking2022Task>(t, m, frame);
}

}  // namespace coxswain::mission::detail
