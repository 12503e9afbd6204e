// SPDX-License-Identifier: Apache-2.0
#include "task_common.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>

#include "coxswain/control/heading_reference.hpp"
#include "coxswain/core/angles.hpp"
#include "coxswain/guidance/buoy_circling.hpp"
#include "coxswain/guidance/docking_approach.hpp"
#include "coxswain/guidance/waypoint_follower.hpp"
#include "coxswain/perception/marker_vote.hpp"

namespace coxswain::mission::detail {

namespace {

/// Find the slip's mouth in the lidar profile (two tips with a closed, deeper inside, within the
/// course's forward half-plane) and enter it along its axis; docked only when the lidar sees a
/// finger along each side. Until the slip shows: the course's forward direction, and once the
/// far wall is near without a slip, sweep along it (turning back at a side wall).
///
/// The boat turns on a circle of 2-2.5 m radius and the slip leaves it 0.4 m either side, so the
/// last metres must be straight, on the axis. A slip seen inside a narrow funnel round its axis is
/// entered straight away. Otherwise (sweeping along the far wall the boat sees a slip from the
/// side, 5 m out) it lines up as a pilot would: out along a line one turning circle to the side of
/// the axis, a half turn toward the axis, and in along it. An approach that reaches the mouth off
/// the axis, or a stop against anything but the slip's back, backs off and lines up again: the
/// boat never reports docked beside the slip. ("The most open direction" of the plan picked a
/// pond's corner beside the dock.)
class Course3Task final : public Task {
 public:
  Course3Task(const config::TaskConfig& t, const config::MissionConfig& m)
      : Task(t.name), d_(m.docking), slip_(slip_line_params(m)), outbound_(slip_line_params(m)) {
    check(m.docking.approach.validate());
    check(m.docking.slip.validate());
  }

  // The line-up, the speed and the crab come from the position estimate, kept with the slip.
  [[nodiscard]] std::uint8_t needs() const override { return kNeedGnss | kNeedImu | kNeedLidar; }

  ReasonText enter(const TaskContext& ctx) override {
    if (!ctx.heading_valid) return reason_printf("no heading");
    if (!ctx.lidar_fresh) return reason_printf("no lidar scan");
    stage_ = Stage::kSeek;
    sweep_side_ = 0;
    tries_ = 0;
    slip_.reset();
    speed_mps_ = 0.0;
    crab_deg_ = 0.0;
    history_count_ = 0;
    set_phase("seek_slip", "task entered");
    return {};
  }

  TaskResult step(const TaskContext& ctx, GuidanceRequest& out) override {
    const perception::RangeProfile& p = *ctx.profile;
    const std::optional<double> ahead =
        guidance::min_range_ahead_m(p, d_.approach.ahead_half_angle_deg);
    const double forward_true = control::true_from_course_deg(0.0, ctx.course_zero_deg);
    update_speed(ctx);
    // Committed (mouth close), the tips are abeam and no longer a mouth: the track is kept.
    if (ctx.lidar_new && stage_ != Stage::kEnter) {
      const double forward_body = core::angle_diff_deg(forward_true, ctx.pose.heading_deg);
      if (const auto s = guidance::find_slip(p, d_.slip, forward_body);
          s && slip_.update(ctx.pose, *s) && stage_ == Stage::kSeek) {
        first_sight(ctx, *s);
      }
    }
    out.steer = true;
    out.thrust_frac = d_.approach_thrust_frac;
    switch (stage_) {
      case Stage::kSeek:
        // The sweep keeps off walls; a wall this near anyway is backed off from, never docked at.
        if (ahead && *ahead < d_.approach.stop_range_m) {
          back_off(ctx,
                   reason_printf("stopped %.2f m from a wall, no slip seen: backing off", *ahead));
          return back_off_step(ctx, out);
        }
        out.desired_heading_deg = seek_heading(ctx, forward_true);
        return TaskResult::kRunning;
      case Stage::kOutbound:
        return outbound_step(ctx, ahead, out);
      case Stage::kTurnIn:
        return turn_in_step(ctx, ahead, out);
      case Stage::kApproach:
        return approach_step(ctx, ahead, out);
      case Stage::kEnter:
        return enter_step(ctx, ahead, out);
      case Stage::kBackOff:
        return back_off_step(ctx, out);
    }
    return TaskResult::kRunning;
  }

 private:
  enum class Stage : std::uint8_t { kSeek, kOutbound, kTurnIn, kApproach, kEnter, kBackOff };

  /// The boat on the slip's axis: how far past the mouth (negative outside), how far to starboard
  /// of the axis, and its heading off the axis (+ = to starboard of it).
  struct OnAxis {
    double along_m = 0.0;
    double cross_m = 0.0;
    double heading_off_deg = 0.0;
  };
  [[nodiscard]] OnAxis on_axis(const core::NavPose& pose) const {
    const double a = core::deg_to_rad(slip_.axis_true_deg());
    const double dn = pose.position.north_m - slip_.mouth().north_m;
    const double de = pose.position.east_m - slip_.mouth().east_m;
    return {dn * std::cos(a) + de * std::sin(a), -dn * std::sin(a) + de * std::cos(a),
            core::angle_diff_deg(pose.heading_deg, slip_.axis_true_deg())};
  }

  /// A point `along_m` past the mouth on the axis (negative: outside) and `cross_m` to starboard.
  [[nodiscard]] core::NavPoint axis_point(double along_m, double cross_m) const {
    const double a = core::deg_to_rad(slip_.axis_true_deg());
    return {slip_.mouth().north_m + along_m * std::cos(a) - cross_m * std::sin(a),
            slip_.mouth().east_m + along_m * std::sin(a) + cross_m * std::cos(a)};
  }

  /// Velocity over ground from the pose a second apart (the estimate steps at each fix, too much
  /// for scan-to-scan differences), taken at each lidar scan: the speed along the heading, and the
  /// crab (course over ground less heading) a current gives the boat.
  void update_speed(const TaskContext& ctx) {
    if (!ctx.lidar_new) return;
    const std::size_t newest = history_count_ % kHistory;
    history_[newest] = {ctx.pose, ctx.now_ns};
    ++history_count_;
    if (history_count_ < kHistory) return;
    const Sample& old = history_[history_count_ % kHistory];
    const double dt = core::ns_to_sec(ctx.now_ns - old.stamp_ns);
    if (!(dt > 0.0) || dt > 2.0 * kHistory * 0.1) return;  // a gap in the scans: wait
    const double vn = (ctx.pose.position.north_m - old.pose.position.north_m) / dt;
    const double ve = (ctx.pose.position.east_m - old.pose.position.east_m) / dt;
    // The heading over the same second: midway between its ends.
    const double mean_heading =
        core::wrap_deg(old.pose.heading_deg +
                       0.5 * core::angle_diff_deg(ctx.pose.heading_deg, old.pose.heading_deg));
    const double h = core::deg_to_rad(mean_heading);
    speed_mps_ = vn * std::cos(h) + ve * std::sin(h);
    // A current's crab needs way on the boat; a sideways speed no current has is the estimate
    // jumping (a fix after an outage, raw fixes), not a crab.
    const double sideways_mps = -vn * std::sin(h) + ve * std::cos(h);
    double crab = 0.0;
    if (speed_mps_ > kCrabMinSpeedMps && std::abs(sideways_mps) < kMaxCurrentMps) {
      const double cog = core::rad_to_deg(std::atan2(ve, vn));
      crab = std::clamp(core::angle_diff_deg(cog, mean_heading), -kMaxCrabDeg, kMaxCrabDeg);
    }
    crab_deg_ += kCrabAlpha * (crab - crab_deg_);
  }

  /// Thrust for a speed over ground: the boat's steady speed per thrust (1.65 m/s per unit, less
  /// 0.05) and a proportional correction, astern when too fast (the hull coasts a long way).
  [[nodiscard]] double thrust_for(double target_mps) const {
    const double feed = (target_mps + 0.05) / 1.65;
    return std::clamp(feed + kSpeedGain * (target_mps - speed_mps_), -0.5, 0.9);
  }

  /// The slip just seen: straight in when the boat is inside the funnel round its axis and heads
  /// toward it; else the line-up.
  void first_sight(const TaskContext& ctx, const guidance::SlipOpening& s) {
    const OnAxis o = on_axis(ctx.pose);
    const double out_m = -o.along_m;
    const double mouth_m = std::hypot(s.mouth_x_m, s.mouth_y_m);
    const bool in_funnel =
        out_m > d_.commit_range_m &&
        std::abs(o.cross_m) <= out_m * std::tan(core::deg_to_rad(d_.approach_funnel_deg)) &&
        std::abs(o.heading_off_deg) <= 60.0;
    if (in_funnel) {
      start_approach(
          reason_printf("slip mouth %.1f m away, %.1f m wide: straight in", mouth_m, s.width_m));
    } else {
      start_outbound(ctx, reason_printf("slip mouth %.1f m away, %.1f m wide, %.1f m off its "
                                        "axis: lining up",
                                        mouth_m, s.width_m, o.cross_m));
    }
  }

  /// Out along a line parallel to the axis, a turning circle's diameter to the side of it with
  /// room, to stage_distance_m out. A boat already that far out needs no line out: heading in, it
  /// approaches; heading out, it turns in.
  void start_outbound(const TaskContext& ctx, const ReasonText& why) {
    const OnAxis o = on_axis(ctx.pose);
    if (-o.along_m >= d_.stage_distance_m - kStageSlackM) {
      side_ = o.cross_m >= 0.0 ? 1 : -1;
      if (std::abs(o.heading_off_deg) <= 90.0) {
        start_approach(why);
      } else {
        stage_ = Stage::kTurnIn;
        set_phase("turn_in", why.view());
      }
      return;
    }
    side_ = line_up_side(ctx, o);
    stage_ = Stage::kOutbound;
    outbound_.reset();
    outbound_ns_ = core::kNeverNs;
    set_phase("line_up", why.view());
  }

  /// The side of the axis to line up on: the boat's own, unless the lidar shows a wall there
  /// nearer the axis than the line out plus a margin; then the other, if it has the room; else
  /// the roomier.
  [[nodiscard]] int line_up_side(const TaskContext& ctx, const OnAxis& o) const {
    const auto wall_from_axis_m = [&](int side) {
      const double body_deg =
          core::angle_diff_deg(slip_.axis_true_deg() + 90.0 * side, ctx.pose.heading_deg);
      const double range_m =
          range_near(*ctx.profile, body_deg, kSweepWindowDeg).value_or(d_.open_max_range_m);
      return side * o.cross_m + range_m;
    };
    const double need_m = 2.0 * d_.turn_radius_m + kWallMarginM;
    const int own = o.cross_m >= 0.0 ? 1 : -1;
    if (wall_from_axis_m(own) >= need_m) return own;
    if (wall_from_axis_m(-own) >= need_m) return -own;
    return wall_from_axis_m(own) >= wall_from_axis_m(-own) ? own : -own;
  }

  TaskResult outbound_step(const TaskContext& ctx, std::optional<double> ahead,
                           GuidanceRequest& out) {
    const double offset_m = 2.0 * d_.turn_radius_m * side_;
    const core::NavPoint from = axis_point(0.0, offset_m);
    const core::NavPoint to = axis_point(-d_.stage_distance_m, offset_m);
    const double dt_s =
        outbound_ns_ == core::kNeverNs ? 0.0 : core::ns_to_sec(ctx.now_ns - outbound_ns_);
    outbound_ns_ = ctx.now_ns;
    const guidance::LineFollowOutput g = outbound_.update(from, to, ctx.pose.position, dt_s);
    if (g.along_track_m >= g.leg_length_m) {
      stage_ = Stage::kTurnIn;
      set_phase("turn_in", reason_printf("%.1f m out, %.1f m to the side: turning in",
                                         -on_axis(ctx.pose).along_m, on_axis(ctx.pose).cross_m));
      return turn_in_step(ctx, ahead, out);
    }
    if (ahead && *ahead < d_.approach.stop_range_m) {
      back_off(ctx, reason_printf("%.2f m from something while lining up: backing off", *ahead));
      return back_off_step(ctx, out);
    }
    out.desired_heading_deg = core::wrap_deg(g.desired_heading_deg - crab_deg_);
    out.thrust_frac = thrust_for(kOutboundSpeedMps);
    viz_goal(ctx, to);
    return TaskResult::kRunning;
  }

  /// The half turn toward the axis (the side is fixed: the short way round may be away from it).
  TaskResult turn_in_step(const TaskContext& ctx, std::optional<double> ahead,
                          GuidanceRequest& out) {
    if (ahead && *ahead < d_.approach.stop_range_m) {
      back_off(ctx, reason_printf("%.2f m from something while turning in: backing off", *ahead));
      return back_off_step(ctx, out);
    }
    const OnAxis o = on_axis(ctx.pose);
    if (std::abs(o.heading_off_deg) <= kTurnInDoneDeg) {
      start_approach(
          reason_printf("%.1f m out, %.2f m off the axis, heading %.0f deg off it: in "
                        "along the axis",
                        -o.along_m, o.cross_m, o.heading_off_deg));
      return approach_step(ctx, std::nullopt, out);
    }
    // Boat to starboard of the axis (side +1), heading out: the axis is to its starboard.
    out.desired_heading_deg = core::wrap_deg(ctx.pose.heading_deg + side_ * kTurnStepDeg);
    out.thrust_frac = kTurnThrustFrac;
    viz_goal(ctx, slip_.mouth());
    return TaskResult::kRunning;
  }

  void start_approach(const ReasonText& why) {
    stage_ = Stage::kApproach;
    slip_.restart_line();
    set_phase("approach_slip", why.view());
  }

  /// Along the slip's axis to the commit range, where the boat must be on the axis and heading
  /// along it, or it backs off; slowing down on the way, so a miss is seen in time.
  TaskResult approach_step(const TaskContext& ctx, std::optional<double> ahead,
                           GuidanceRequest& out) {
    const OnAxis o = on_axis(ctx.pose);
    const double out_m = -o.along_m;
    if (out_m < d_.commit_range_m) {
      // The track along the axis; the heading may be off it by the crab and a little more (the
      // hull 30 deg across the slip still spans under its width).
      const double track_off_deg = core::angle_diff_deg(o.heading_off_deg + crab_deg_, 0.0);
      if (std::abs(o.cross_m) <= d_.entry_tolerance_m &&
          std::abs(track_off_deg) <= d_.entry_tolerance_deg &&
          std::abs(o.heading_off_deg) <= kMaxEntryHeadingOffDeg) {
        stage_ = Stage::kEnter;
        progress_at_ = ctx.pose.position;
        progress_ns_ = ctx.now_ns;
        set_phase("enter_slip",
                  reason_printf("mouth %.2f m away, %.2f m off the axis, heading "
                                "%.0f deg off it: holding the slip's axis %.0f deg",
                                out_m, o.cross_m, o.heading_off_deg, slip_.axis_true_deg()));
        return enter_step(ctx, ahead, out);
      }
      back_off(ctx, reason_printf("at the mouth %.2f m off the axis, heading %.0f deg off it "
                                  "(track %.0f deg): backing off to line up again",
                                  o.cross_m, o.heading_off_deg, track_off_deg));
      return back_off_step(ctx, out);
    }
    if (ahead && *ahead < d_.approach.stop_range_m) {
      back_off(ctx, reason_printf("%.2f m from something %.1f m before the mouth: backing off",
                                  *ahead, out_m));
      return back_off_step(ctx, out);
    }
    out.desired_heading_deg = follow_axis(ctx);
    const double target_mps =
        std::clamp(kEntrySpeedMps + kSlowdownPerM * (out_m - d_.commit_range_m), kEntrySpeedMps,
                   kOutboundSpeedMps);
    out.thrust_frac = thrust_for(target_mps);
    viz_goal(ctx, slip_.mouth());
    return TaskResult::kRunning;
  }

  /// Committed: holds the axis; at the stop range, or stuck, docked only with a finger along
  /// each side, else back off.
  TaskResult enter_step(const TaskContext& ctx, std::optional<double> ahead, GuidanceRequest& out) {
    if (core::distance_m(ctx.pose.position, progress_at_) > kProgressM) {
      progress_at_ = ctx.pose.position;
      progress_ns_ = ctx.now_ns;
    }
    const bool stopped = ahead && *ahead < d_.approach.stop_range_m;
    const bool stuck = core::ns_to_sec(ctx.now_ns - progress_ns_) >= kStuckS;
    if (stopped || stuck) {
      const guidance::FingersAlongside f =
          guidance::fingers_alongside(*ctx.profile, d_.finger_side_m, kFingerAftM);
      if (f.both()) {
        set_reason(
            reason_printf("docked: %.2f m ahead, fingers %.2f m to port and %.2f m to "
                          "starboard",
                          ahead ? *ahead : -1.0, f.port_m, f.starboard_m));
        return TaskResult::kDone;
      }
      back_off(ctx, reason_printf("%s without a finger along each side (port %.2f m, starboard "
                                  "%.2f m): backing off",
                                  stopped ? "stopped at the slip" : "stuck at the slip", f.port_m,
                                  f.starboard_m));
      return back_off_step(ctx, out);
    }
    out.desired_heading_deg = follow_axis(ctx);
    out.thrust_frac = thrust_for(kEntrySpeedMps);
    viz_goal(ctx, slip_.mouth());
    return TaskResult::kRunning;
  }

  void back_off(const TaskContext& ctx, const ReasonText& why) {
    stage_ = Stage::kBackOff;
    back_since_ns_ = ctx.now_ns;
    ++tries_;
    set_phase("back_off", why.view());
  }

  /// Astern until clear of the docks (or for back_off_s at most),
  /// then line up again (or seek, no slip seen yet).
  TaskResult back_off_step(const TaskContext& ctx, GuidanceRequest& out) {
    out.steer = true;
    const double backing_s = core::ns_to_sec(ctx.now_ns - back_since_ns_);
    const bool clear =
        backing_s >= kMinBackOffS && (!slip_.seen() || -on_axis(ctx.pose).along_m >= kClearOutM);
    // Something close astern ends it early: the stern is blind to the stop range ahead.
    const std::optional<double> astern = range_near(*ctx.profile, 180.0, kAsternHalfAngleDeg);
    const bool blocked = astern && *astern < kAsternStopM;
    if (clear || blocked || backing_s >= d_.back_off_s) {
      if (slip_.seen()) {
        start_outbound(ctx, reason_printf("backed off (try %d): lining up again", tries_));
        out.desired_heading_deg = ctx.pose.heading_deg;
        out.thrust_frac = 0.0;
        return TaskResult::kRunning;
      }
      stage_ = Stage::kSeek;
      sweep_side_ = 0;
      set_phase("seek_slip", "backed off: looking for the slip");
      out.desired_heading_deg = ctx.pose.heading_deg;
      out.thrust_frac = 0.0;
      return TaskResult::kRunning;
    }
    // Astern the rudder turns the boat the other way: held straight (no heading error to
    // correct), the heading loop would otherwise swing the stern round into a wall.
    out.desired_heading_deg = ctx.pose.heading_deg;
    out.thrust_frac = d_.back_off_thrust_frac;
    out.speed_factor = -1.0;
    return TaskResult::kRunning;
  }

  /// Line of sight along the slip's axis, as a course over ground: the heading allows for the
  /// crab (a 0.2 m/s current across is 15-25 deg at approach speeds, and the boat held 25 deg off
  /// the axis closed on it by 1 m in 8 m).
  double follow_axis(const TaskContext& ctx) {
    return core::wrap_deg(
        slip_.follow_heading_deg(ctx.pose, d_.stage_distance_m, ctx.now_ns, kLookaheadPerM) -
        crab_deg_);
  }

  static void viz_goal(const TaskContext& ctx, core::NavPoint goal) {
    ctx.viz->has_goal = true;
    ctx.viz->goal = goal;
    ctx.viz->distance_to_go_m = core::distance_m(ctx.pose.position, goal);
  }

  /// The course's forward direction until the far wall is near; then along the wall at the
  /// stand-off, on the side with more room, turning back at a side wall.
  double seek_heading(const TaskContext& ctx, double forward_true) {
    const perception::RangeProfile& p = *ctx.profile;
    const double forward_body = core::angle_diff_deg(forward_true, ctx.pose.heading_deg);
    const auto range_at = [&](double body_deg) {
      return range_near(p, body_deg, kSweepWindowDeg).value_or(d_.open_max_range_m);
    };
    const double to_wall_m = range_at(forward_body);
    if (sweep_side_ == 0) {
      if (to_wall_m > d_.sweep_wall_range_m) return forward_true;
      sweep_side_ = range_at(forward_body + 90.0) >= range_at(forward_body - 90.0) ? 1 : -1;
      set_phase(sweep_phase(), reason_printf("wall %.1f m ahead and no slip: along it", to_wall_m));
    }
    const double side_deg = 90.0 * sweep_side_;
    if (range_at(forward_body + side_deg) < d_.sweep_turn_back_m) {
      sweep_side_ = -sweep_side_;
      set_phase(sweep_phase(), "side wall: turning back along the far wall");
    }
    // Hold the stand-off: too far, lean toward the wall; too near, away from it.
    const double lean_deg =
        std::clamp(kStandoffGainDegPerM * (to_wall_m - d_.sweep_standoff_m), -30.0, 30.0);
    return core::wrap_deg(forward_true + sweep_side_ * (90.0 - lean_deg));
  }

  [[nodiscard]] std::string_view sweep_phase() const {
    return sweep_side_ > 0 ? "sweep_starboard" : "sweep_port";
  }

  static constexpr double kSweepWindowDeg = 5.0;
  // The slip's axis is joined by line of sight looking this far ahead per metre to the mouth
  // (with 1.5 m the boat was asked for 70 deg crossings 8 m out, turned too slowly at the
  // approach thrust, crossed the axis at 50 deg 3 m out and stopped on the finger).
  static constexpr double kLookaheadPerM = 0.5;
  static constexpr double kStandoffGainDegPerM = 15.0;
  // Speeds over ground: out along the line-up, and at the commit range (slowing down by this
  // much per metre nearer the mouth), so that an approach off the axis is stopped before the
  // fingers: the hull coasts metres from 1.2 m/s.
  static constexpr double kOutboundSpeedMps = 0.8;
  static constexpr double kEntrySpeedMps = 0.5;
  static constexpr double kSlowdownPerM = 0.12;
  static constexpr double kSpeedGain = 0.8;  // thrust per m/s of speed error
  static constexpr double kCrabAlpha = 0.3;  // smoothing of the crab per scan
  // The half turn: ask this far ahead of the heading each tick, at this thrust, until this near
  // the axis heading.
  static constexpr double kTurnStepDeg = 60.0;
  static constexpr double kTurnThrustFrac = 0.5;
  static constexpr double kTurnInDoneDeg = 45.0;
  // A boat within this of the staging distance is far enough out.
  static constexpr double kStageSlackM = 1.0;
  // Backing off stops with a return this near within this of the stern.
  static constexpr double kAsternStopM = 1.0;
  static constexpr double kAsternHalfAngleDeg = 30.0;
  // The line out keeps this much more than the turning circle's diameter from a side wall.
  static constexpr double kWallMarginM = 5.0;
  // Backing off: at least this long, and until this far out from the mouth (room for the turn
  // out: the turning circle reaches 1.5-2 m ahead).
  static constexpr double kMinBackOffS = 2.0;
  static constexpr double kClearOutM = 4.5;
  // The crab is measured above this speed and trusted up to this angle.
  static constexpr double kCrabMinSpeedMps = 0.25;
  static constexpr double kMaxCrabDeg = 35.0;
  static constexpr double kMaxCurrentMps = 0.6;
  static constexpr double kMaxEntryHeadingOffDeg = 35.0;
  // Committed, a boat that moves less than kProgressM in kStuckS is held by something.
  static constexpr double kProgressM = 0.1;
  static constexpr double kStuckS = 3.0;
  // The fingers are looked for abeam of the lidar (at the bow) and this far aft: half the hull's
  // 1.2 m, so a boat docked by the lidar has half its hull in the slip, as the judge counts.
  static constexpr double kFingerAftM = 0.6;

  config::DockingConfig d_;
  SlipTracker slip_;
  guidance::LineFollower outbound_;  // the line-up's leg out, beside the axis
  core::TimeNs outbound_ns_ = core::kNeverNs;
  Stage stage_ = Stage::kSeek;
  int sweep_side_ = 0;  // 0 = not sweeping, +1 starboard, -1 port (of the course's forward)
  int side_ = 1;        // line-up side of the axis: +1 starboard, -1 port
  int tries_ = 0;       // back-offs so far
  struct Sample {
    core::NavPose pose;
    core::TimeNs stamp_ns = 0;
  };
  static constexpr std::size_t kHistory = 10;  // scans: a second at 10 Hz
  std::array<Sample, kHistory> history_{};
  std::size_t history_count_ = 0;
  double speed_mps_ = 0.0;
  double crab_deg_ = 0.0;
  core::NavPoint progress_at_;
  core::TimeNs progress_ns_ = 0;
  core::TimeNs back_since_ns_ = 0;
};

}  // namespace

std::unique_ptr<Task> make_course3_task(const config::TaskConfig& t,
                                        const config::MissionConfig& m) {
  return std::make_unique<Course3Task>(t, m);
}

}  // namespace coxswain::mission::detail
