// SPDX-License-Identifier: Apache-2.0
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "coxswain/core/angles.hpp"
#include "coxswain/guidance/docking_approach.hpp"
#include "coxswain/guidance/waypoint_follower.hpp"
#include "coxswain/perception/marker_vote.hpp"
#include "task_common.hpp"

namespace coxswain::mission::detail {

namespace {

core::NavPoint along(core::NavPoint p, double heading_deg, double distance_m) {
  const double h = core::deg_to_rad(heading_deg);
  return {p.north_m + distance_m * std::cos(h), p.east_m + distance_m * std::sin(h)};
}

/// KABOAT 2022 docking. Every camera frame votes, for each slip whose marker it shows, whether
/// that marker is the target (markers are told apart by where the map puts them, or by their
/// order across the frame); so the target is usually known by the survey point in front of
/// the docks, and the boat goes straight in along its slip's axis. Otherwise the documents'
/// process: visit each slip's decision point (joining the slip's axis from behind by line of
/// sight), face its marker and vote. The target slip is entered by ray pursuit along its axis
/// (by line of sight on the lidar's mouth once seen), the axis shifted sideways by the camera's
/// fix of the marker (the GNSS error is larger than the slip's room), and the boat stops by lidar.
class Docking2022Task final : public AvoidingTask {
 public:
  static constexpr std::size_t kMaxSlips = 8;
  // A mouth whose slip's marker is within this of the camera's sight is the target's: the gap
  // between two docks, 1.5 m aside, is 14 deg off even from 6 m.
  static constexpr double kMarkerOverMouthDeg = 6.0;
  static constexpr double kAxisToleranceDeg = 20.0;
  // The approach along a slip's axis starts this far behind its decision point (any boat behind
  // it is on the leg), and is taken when the boat is at least this much more than the line-up
  // distance behind the decision point.
  static constexpr double kAxisLegM = 30.0;
  static constexpr double kAxisApproachMinM = 1.0;
  // On the slip's line the boat looks this far ahead per metre still to go to the mouth: a slip
  // joined from metres off its axis is joined at an angle the boat can turn out of before the
  // mouth (as in course 3; a small gain here: 200 runs, seeds 1-200: 12 -> 9 contacts, 199 of
  // 200 docked either way).
  static constexpr double kSlipLookaheadPerM = 0.5;
  enum class Phase : std::uint8_t { kSurvey, kGoto, kFace, kEnter };

  Docking2022Task(const config::TaskConfig& t, const config::MissionConfig& m,
                  const core::LocalFrame& frame)
      : AvoidingTask(t.name, m.avoidance),
        d_(m.docking),
        follower_(m.waypoints),
        line_following_(m.waypoints.line_following),
        axis_line_([&m] {
          guidance::LineFollowParams line = m.waypoints.line;
          line.lookahead_m = m.docking.axis_lookahead_m;
          return line;
        }()),
        approach_(m.docking.approach),
        slip_tracker_(slip_line_params(m)),
        dock_heading_deg_(t.dock_heading_deg),
        config_colour_(t.target_colour),
        config_shape_(t.target_shape) {
    check(m.docking.approach.validate());
    if (auto vote_problem = m.vision_vote.validate()) throw std::invalid_argument(*vote_problem);
    slip_count_ = std::min(t.slips.size(), kMaxSlips);
    core::NavPoint centre;
    for (std::size_t i = 0; i < slip_count_; ++i) {
      slips_[i] = frame.to_nav(t.slips[i]);
      markers_[i] = along(slips_[i], dock_heading_deg_, d_.slip_depth_m);
      decision_[i] = along(slips_[i], dock_heading_deg_, -d_.decision_distance_m);
      line_up_[i] = along(decision_[i], dock_heading_deg_, -d_.line_up_distance_m);
      votes_[i] = perception::MarkerVote(m.vision_vote);
      centre.north_m += slips_[i].north_m / static_cast<double>(slip_count_);
      centre.east_m += slips_[i].east_m / static_cast<double>(slip_count_);
    }
    survey_ = along(centre, dock_heading_deg_, -d_.survey_distance_m);
    // A slip's sides lie nearer its axis than half the way to the next slip's: so far the
    // fingers are looked for beside a boat that stopped (at least finger_side_m).
    double spacing_m = 0.0;  // between the nearest two slips
    for (std::size_t i = 0; i + 1 < slip_count_; ++i) {
      for (std::size_t j = i + 1; j < slip_count_; ++j) {
        const double d = core::distance_m(slips_[i], slips_[j]);
        if (spacing_m == 0.0 || d < spacing_m) spacing_m = d;
      }
    }
    finger_side_m_ = std::max(d_.finger_side_m, 0.5 * spacing_m + kFingerSlackM);
    const double h = core::deg_to_rad(dock_heading_deg_);
    axis_ = {std::cos(h), std::sin(h)};
    side_ = {-std::sin(h), std::cos(h)};
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
    for (std::size_t i = 0; i < slip_count_; ++i) votes_[i].reset();
    ratio_.fill(-1.0);
    target_slip_.reset();
    fix_m_ = 0.0;
    approach_.reset();
    avoidance_->reset();
    ctx.status->docking_slip = -1;
    phase_ = Phase::kSurvey;
    const std::array<core::NavPoint, 1> route{survey_};
    (void)follower_.set_route(route);
    set_phase("survey", reason_printf("looking for the %s %s",
                                      std::string_view(msg::colour_name(colour_)).data(),
                                      std::string_view(msg::shape_name(shape_)).data()));
    return {};
  }

  TaskResult step(const TaskContext& ctx, GuidanceRequest& out) override {
    observe(ctx);
    switch (phase_) {
      case Phase::kSurvey:
        if (target_slip_) return goto_target(ctx, out);
        if (follow(ctx, survey_, out)) return TaskResult::kRunning;
        goto_slip(0, reason_printf("survey point reached undecided; visiting the slips"));
        out.steer = false;
        return TaskResult::kRunning;
      case Phase::kGoto:
        // Another slip decided, or this one while still short of its decision point.
        if (target_slip_ && (*target_slip_ != slip_ || straight_in(ctx, slip_))) {
          return goto_target(ctx, out);
        }
        if (to_decision_point(ctx, out)) return TaskResult::kRunning;
        phase_ = Phase::kFace;
        face_since_ns_ = core::kNeverNs;
        set_phase(slip_phase("face_slip").view(),
                  reason_printf("at the decision point of slip %zu", slip_ + 1));
        return face(ctx, out);
      case Phase::kFace:
        return face(ctx, out);
      case Phase::kEnter:
        break;
    }
    return enter_step(ctx, out);
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

  /// The pose in the map's frame: the raw estimate moved by the camera's sideways fix.
  [[nodiscard]] core::NavPoint corrected(core::NavPoint p) const {
    return {p.north_m - fix_m_ * side_.north_m, p.east_m - fix_m_ * side_.east_m};
  }

  /// One camera frame: each dock marker in it is matched to a slip (by where the map puts it, or
  /// by the markers' order across the frame). That slip gets a vote, "seen" when the marker is the
  /// target; slips whose marker is not in the frame get none, so a slip is judged only on frames
  /// that show it. Every matched marker also fixes the boat's sideways position against the map:
  /// the GNSS error (a metre or more) is larger than a slip's spare room.
  void observe(const TaskContext& ctx) {
    if (!ctx.camera_new || ctx.camera == nullptr) return;
    std::array<double, msg::CameraDetections::kMaxDetections> bearings{};
    std::array<bool, msg::CameraDetections::kMaxDetections> is_target{};
    std::size_t n = 0;
    const std::size_t count =
        std::min<std::size_t>(ctx.camera->count, msg::CameraDetections::kMaxDetections);
    for (std::size_t k = 0; k < count; ++k) {
      const msg::Detection& det = ctx.camera->detections[k];
      if (det.shape == msg::Shape::kUnknown || det.shape == msg::Shape::kBuoy) continue;
      bearings[n] = static_cast<double>(det.bearing_deg);
      is_target[n] = det.colour == colour_ && det.shape == shape_;
      ++n;
    }
    if (n == 0) return;
    const core::NavPoint boat = corrected(ctx.pose.position);
    std::array<double, kMaxSlips> expected{};
    for (std::size_t i = 0; i < slip_count_; ++i) {
      expected[i] =
          core::angle_diff_deg(core::bearing_deg(boat, markers_[i]), ctx.pose.heading_deg);
    }
    std::array<bool, kMaxSlips> shown{};
    std::array<bool, kMaxSlips> target_shown{};
    const std::span<const double> marker_span(bearings.data(), n);
    const std::span<const double> slip_span(expected.data(), slip_count_);
    double fix_sum_m = 0.0;
    std::size_t fixes = 0;
    for (std::size_t k = 0; k < n; ++k) {
      if (phase_ == Phase::kEnter && is_target[k]) {
        // The target marker is unique: its bearing picks the slip's mouth out of the lidar
        // profile, whatever the map says.
        marker_true_deg_ = core::wrap_deg(ctx.pose.heading_deg + bearings[k]);
        marker_seen_ns_ = ctx.camera->stamp_ns;
      }
      const auto j = guidance::slip_of_marker(marker_span, k, slip_span, d_.marker_window_deg);
      if (!j) continue;
      shown[*j] = true;
      target_shown[*j] = target_shown[*j] || is_target[k];
      // While entering, only the target's own marker fixes the pose.
      if (phase_ == Phase::kEnter && (*j != slip_ || !is_target[k])) continue;
      if (const auto f = sideways_fix(ctx, *j, bearings[k])) {
        fix_sum_m += *f;
        ++fixes;
      }
    }
    if (fixes > 0) {
      fix_m_ += d_.marker_fix_gain * (fix_sum_m / static_cast<double>(fixes) - fix_m_);
      fix_m_ = std::clamp(fix_m_, -d_.max_marker_fix_m, d_.max_marker_fix_m);
    }
    if (phase_ == Phase::kEnter) return;
    for (std::size_t i = 0; i < slip_count_; ++i) {
      if (shown[i]) (void)votes_[i].add(ctx.camera->stamp_ns, target_shown[i]);
    }
    if (target_slip_) return;
    for (std::size_t i = 0; i < slip_count_; ++i) {
      const perception::VoteTally t = votes_[i].tally(ctx.now_ns);
      if (t.frames > 0) ratio_[i] = t.ratio;
      if (t.decided) {
        target_slip_ = i;
        decided_hits_ = t.hits;
        decided_frames_ = t.frames;
        return;
      }
    }
  }

  /// The sideways offset (along `side_`) between where the raw pose and the camera put slip
  /// `j`'s marker and where the map has it; empty when the sight is too close or too oblique.
  [[nodiscard]] std::optional<double> sideways_fix(const TaskContext& ctx, std::size_t j,
                                                   double bearing_body_deg) const {
    const core::NavPoint boat = corrected(ctx.pose.position);
    const double ahead_m = along_axis_m(boat, markers_[j]);
    const double sight_deg =
        core::angle_diff_deg(ctx.pose.heading_deg + bearing_body_deg, dock_heading_deg_);
    // Close in, the marker fills the frame and its centre is no longer a sharp fix.
    if (ahead_m < 1.0 || std::abs(sight_deg) > 60.0) return std::nullopt;
    // Far off, a marker's bearing fixes little and the frame may not show every marker, so
    // the marker can be matched to a neighbour's slip: the fix jumped by metres and swung the
    // boat about among the buoys.
    if (ahead_m > d_.marker_fix_max_range_m) return std::nullopt;
    const double across_m = ahead_m * std::tan(core::deg_to_rad(sight_deg));
    const double boat_side_m = (ctx.pose.position.north_m - markers_[j].north_m) * side_.north_m +
                               (ctx.pose.position.east_m - markers_[j].east_m) * side_.east_m;
    return boat_side_m + across_m;
  }

  /// Waypoint following to `goal` with lidar avoidance; false once there.
  bool follow(const TaskContext& ctx, core::NavPoint goal, GuidanceRequest& out) {
    const guidance::WaypointGuidance g = follower_.update(corrected(ctx.antenna), ctx.now_ns);
    viz_goal(ctx, goal);
    if (g.finished) return false;
    out.steer = true;
    out.desired_heading_deg = g.desired_heading_deg;
    out.schedule_distance_m = g.distance_to_go_m;
    // Only what lies before the goal is in the way: the docks behind a decision point are not.
    steer_clear(*avoidance_, ctx, g.desired_heading_deg, g.distance_to_go_m + 0.5, near_, out);
    return true;
  }

  /// Toward the decision point of slip `slip_`; false once there. From well behind it the boat
  /// follows the slip's axis by line of sight, so it joins the axis at a bounded angle and
  /// arrives on it, facing the slip: the outer slips leave about a metre between hull and pool
  /// wall, and a boat that reaches its line-up point crossing the axis overshoots into the wall.
  /// From beside it (moving on from a neighbour's decision point), the route via the line-up
  /// point.
  bool to_decision_point(const TaskContext& ctx, GuidanceRequest& out) {
    const core::NavPoint p = corrected(ctx.antenna);
    const core::NavPoint goal = decision_[slip_];
    if (!approach_chosen_) {
      approach_chosen_ = true;
      const double behind_m = along_axis_m(p, goal);
      // Without line following (the documents' bearing steering), always the route.
      on_axis_ = line_following_ && behind_m >= d_.line_up_distance_m + kAxisApproachMinM;
      axis_line_.reset();
      axis_last_ns_ = core::kNeverNs;
    }
    if (!on_axis_) return follow(ctx, goal, out);
    const core::NavPoint from = along(goal, dock_heading_deg_, -kAxisLegM);
    const double dt_s =
        axis_last_ns_ == core::kNeverNs ? 0.0 : core::ns_to_sec(ctx.now_ns - axis_last_ns_);
    axis_last_ns_ = ctx.now_ns;
    const guidance::LineFollowOutput g = axis_line_.update(from, goal, p, dt_s);
    // Arrived once abeam of the decision point (a radius would end the leg a metre short,
    // still crossing the axis).
    if (g.along_track_m >= g.leg_length_m) return false;
    viz_goal(ctx, goal);
    const double to_go_m = core::distance_m(p, goal);
    out.steer = true;
    out.desired_heading_deg = g.desired_heading_deg;
    out.schedule_distance_m = to_go_m;
    steer_clear(*avoidance_, ctx, g.desired_heading_deg, to_go_m + 0.5, near_, out);
    return true;
  }

  /// To the decision point of slip `i`, lined up on its axis from behind.
  void goto_slip(std::size_t i, const ReasonText& why) {
    slip_ = i;
    phase_ = Phase::kGoto;
    approach_chosen_ = false;
    avoidance_->reset();
    const std::array<core::NavPoint, 2> route{line_up_[i], decision_[i]};
    (void)follower_.set_route(route);
    set_phase(slip_phase("goto_slip").view(), why.view());
  }

  TaskResult goto_target(const TaskContext& ctx, GuidanceRequest& out) {
    const std::size_t i = *target_slip_;
    ctx.status->docking_slip = static_cast<std::int32_t>(i);
    const ReasonText why = reason_printf("target marker at slip %zu (%zu of %zu frames)", i + 1,
                                         decided_hits_, decided_frames_);
    // Already in front of it (facing it at its decision point): in at once.
    if (phase_ == Phase::kFace && slip_ == i) return enter_slip(ctx, i, why);
    // Decided on the way in, still behind its decision point: straight in along the slip's axis.
    // Stopping at the decision point first left an outer slip's axis, 3 m aside of the survey
    // point, only 4 m to be joined in; the boat reached it 2-3 m off and met a finger (100 runs,
    // seeds 1-100: 91% / 80 clean -> 100% / 95). Without line following (the documents' bearing
    // steering), their process: visit, face, enter.
    if (phase_ != Phase::kFace && straight_in(ctx, i)) return enter_slip(ctx, i, why);
    goto_slip(i, why);
    out.steer = false;
    return TaskResult::kRunning;
  }

  /// How far `to` lies beyond `from` along the slips' axis.
  [[nodiscard]] double along_axis_m(core::NavPoint from, core::NavPoint to) const {
    return (to.north_m - from.north_m) * axis_.north_m + (to.east_m - from.east_m) * axis_.east_m;
  }

  /// How far the boat is behind slip `i`'s decision point, along the slips' axis.
  [[nodiscard]] double behind_decision_m(const TaskContext& ctx, std::size_t i) const {
    return along_axis_m(corrected(ctx.pose.position), decision_[i]);
  }

  /// Whether slip `i`, once decided, is entered from where the boat is, without its decision
  /// point: with line following, from anywhere short of that point.
  [[nodiscard]] bool straight_in(const TaskContext& ctx, std::size_t i) const {
    return line_following_ && behind_decision_m(ctx, i) >= 0.0;
  }

  TaskResult enter_slip(const TaskContext& ctx, std::size_t i, const ReasonText& why) {
    slip_ = i;
    phase_ = Phase::kEnter;
    ctx.status->docking_slip = static_cast<std::int32_t>(i);
    approach_.reset();
    slip_tracker_.reset();
    committed_ = false;
    backing_since_ns_ = core::kNeverNs;
    marker_seen_ns_ = core::kNeverNs;
    if (!approach_.set_ray(decision_[i], slips_[i])) {
      set_reason(reason_printf("slip %zu: decision point equals the slip", i + 1));
      return TaskResult::kFailed;
    }
    set_phase(slip_phase("enter_slip").view(), why.view());
    return TaskResult::kRunning;
  }

  TaskResult face(const TaskContext& ctx, GuidanceRequest& out) {
    if (target_slip_) {
      if (*target_slip_ != slip_) return goto_target(ctx, out);
    }
    const double err = core::angle_diff_deg(dock_heading_deg_, ctx.pose.heading_deg);
    const bool facing = std::abs(err) <= d_.face_tolerance_deg;
    if (facing && target_slip_) return goto_target(ctx, out);
    // The look is timed from when the boat faces the slip, not from its arrival: a slow turn
    // must not eat the look.
    if (facing && face_since_ns_ == core::kNeverNs) face_since_ns_ = ctx.now_ns;
    if (face_since_ns_ != core::kNeverNs &&
        core::ns_to_sec(ctx.now_ns - face_since_ns_) >= d_.face_time_s) {
      const double r = std::max(ratio_[slip_], 0.0);
      if (slip_ + 1 < slip_count_) {
        goto_slip(slip_ + 1,
                  reason_printf("slip %zu is not the target (ratio %.2f)", slip_ + 1, r));
        out.steer = false;
        return TaskResult::kRunning;
      }
      // Every slip seen without a decision: the best ratio, if the target was seen at all.
      std::size_t best = 0;
      for (std::size_t i = 1; i < slip_count_; ++i) {
        if (ratio_[i] > ratio_[best]) best = i;
      }
      if (ratio_[best] > 0.0) {
        const ReasonText why = reason_printf("no slip decided; slip %zu has the best ratio %.2f",
                                             best + 1, ratio_[best]);
        if (best == slip_) return enter_slip(ctx, best, why);
        target_slip_ = best;
        goto_slip(best, why);
        out.steer = false;
        return TaskResult::kRunning;
      }
      set_reason(reason_printf("target marker not seen at any slip"));
      return TaskResult::kFailed;
    }
    viz_goal(ctx, markers_[slip_]);
    out.steer = true;
    out.desired_heading_deg = dock_heading_deg_;
    out.thrust_frac = facing ? 0.0 : d_.turn_thrust_frac;
    return TaskResult::kRunning;
  }

  /// Ray pursuit into the slip from the camera-fixed pose; the stop is latched by the lidar
  /// range ahead, and the boat slows as that range falls so it does not coast into the back.
  TaskResult enter_step(const TaskContext& ctx, GuidanceRequest& out) {
    if (backing_since_ns_ != core::kNeverNs) {
      if (core::ns_to_sec(ctx.now_ns - backing_since_ns_) < kBackOffS) {
        out.steer = true;
        out.desired_heading_deg = ctx.pose.heading_deg;
        out.thrust_frac = kBackOffThrustFrac;
        out.speed_factor = -1.0;
        return TaskResult::kRunning;
      }
      // Backed off: in again, the slip looked for afresh.
      backing_since_ns_ = core::kNeverNs;
      approach_.reset();
      slip_tracker_.reset();
      committed_ = false;
      set_phase(slip_phase("enter_slip").view(), "backed off; entering again");
    }
    std::optional<double> ahead;
    if (ctx.lidar_fresh && ctx.profile != nullptr) {
      ahead = guidance::min_range_ahead_m(*ctx.profile, d_.approach.ahead_half_angle_deg);
    }
    // Behind the decision point, whatever is close ahead is a buoy on the way, not the slip's
    // back (8 m and more away): it neither stops nor slows the boat; avoidance steers round it.
    const double behind_m = behind_decision_m(ctx, slip_);
    if (behind_m > 0.0) ahead.reset();
    core::NavPose pose = ctx.pose;
    pose.position = corrected(ctx.pose.position);
    if (ctx.lidar_new && ctx.profile != nullptr && !committed_) {
      // The chosen slip's mouth where the camera-fixed map puts it; its neighbours are a slip
      // width and more away.
      const core::BodyPoint expected = core::nav_to_body(pose, slips_[slip_]);
      const double axis_body_deg = core::angle_diff_deg(dock_heading_deg_, ctx.pose.heading_deg);
      // The docks' heading is known: only a compass error turns a slip's axis away from it.
      guidance::SlipFinderParams finder = d_.slip;
      finder.max_axis_deg = std::min(finder.max_axis_deg, kAxisToleranceDeg);
      // Best: the mouth under the target marker the camera sees now (all relative to the bow);
      // else the mouth where the camera-fixed map puts it.
      const bool marker_recent =
          marker_seen_ns_ != core::kNeverNs && core::ns_to_sec(ctx.now_ns - marker_seen_ns_) <= 0.5;
      std::optional<guidance::SlipOpening> s;
      if (marker_recent) {
        s = guidance::find_slip_toward(*ctx.profile, finder, axis_body_deg,
                                       core::angle_diff_deg(marker_true_deg_, ctx.pose.heading_deg),
                                       d_.slip_depth_m, kMarkerOverMouthDeg);
      }
      if (!s) {
        s = guidance::find_slip_near(*ctx.profile, finder, axis_body_deg, expected,
                                     d_.slip_match_m);
      }
      if (s && slip_tracker_.update(ctx.pose, *s)) {
        committed_ = std::hypot(s->mouth_x_m, s->mouth_y_m) < d_.commit_range_m;
      }
    }
    guidance::DockingCommand c = approach_.pursue(pose, ahead);
    // The lidar's own sight of the mouth beats the map: it is where the boat's pose puts it.
    if (slip_tracker_.seen()) {
      c.desired_heading_deg = slip_tracker_.follow_heading_deg(ctx.pose, d_.decision_distance_m,
                                                               ctx.now_ns, kSlipLookaheadPerM);
    }
    if (c.stop) {
      // Something close ahead is the slip's back only with the slip's sides along the hull: a
      // finger's end or a neighbouring dock's face stops the boat as well.
      guidance::FingersAlongside f;
      if (ctx.lidar_fresh && ctx.profile != nullptr) {
        f = guidance::fingers_alongside(*ctx.profile, finger_side_m_, kFingerAftM,
                                        avoidance_->params().bow_ahead_m);
      }
      if (f.both()) {
        set_reason(
            reason_printf("docked in slip %zu (%.2f m ahead, fingers %.2f / %.2f m, "
                          "camera fix %.2f m, %s)",
                          slip_ + 1, ahead ? *ahead : -1.0, f.port_m, f.starboard_m, fix_m_,
                          slip_tracker_.seen() ? "lidar mouth" : "map"));
        return TaskResult::kDone;
      }
      backing_since_ns_ = ctx.now_ns;
      set_phase(slip_phase("back_off").view(),
                reason_printf("stopped %.2f m short of something without a finger along each "
                              "side (port %.2f m, starboard %.2f m): backing off",
                              ahead ? *ahead : -1.0, f.port_m, f.starboard_m));
      out.steer = true;
      out.desired_heading_deg = ctx.pose.heading_deg;
      out.thrust_frac = 0.0;
      return TaskResult::kRunning;
    }
    out.steer = true;
    out.desired_heading_deg = c.desired_heading_deg;
    // Entered from behind the decision point, buoys may still lie on the way there (the docks
    // beyond it are no obstacle).
    if (behind_m > 0.0) {
      steer_clear(*avoidance_, ctx, c.desired_heading_deg, behind_m + 0.5, near_, out);
    }
    out.thrust_frac = d_.approach_thrust_frac;
    if (ahead) {
      const double slow_m = 1.5;  // from this range ahead down to the stop, ease off
      out.speed_factor = std::clamp((*ahead - d_.approach.stop_range_m) / slow_m, 0.6, 1.0);
    }
    return TaskResult::kRunning;
  }

  config::DockingConfig d_;
  guidance::WaypointFollower follower_;
  bool line_following_;
  guidance::LineFollower axis_line_;  // the approach along a slip's axis
  core::TimeNs axis_last_ns_ = core::kNeverNs;
  bool approach_chosen_ = false;  // whether on_axis_ is set for this approach
  bool on_axis_ = false;          // approaching along the slip's axis (else via the route)
  guidance::DockingApproach approach_;
  SlipTracker slip_tracker_;
  perception::ObstacleList near_;
  double dock_heading_deg_;
  msg::Colour config_colour_;
  msg::Shape config_shape_;
  msg::Colour colour_ = msg::Colour::kUnknown;
  msg::Shape shape_ = msg::Shape::kUnknown;
  std::array<core::NavPoint, kMaxSlips> slips_{};
  std::array<core::NavPoint, kMaxSlips> markers_{};
  std::array<core::NavPoint, kMaxSlips> decision_{};
  std::array<core::NavPoint, kMaxSlips> line_up_{};
  std::array<perception::MarkerVote, kMaxSlips> votes_;
  std::array<double, kMaxSlips> ratio_{};
  core::NavPoint survey_;
  std::size_t slip_count_ = 0;
  std::size_t slip_ = 0;
  std::optional<std::size_t> target_slip_;
  std::size_t decided_hits_ = 0;
  std::size_t decided_frames_ = 0;
  core::NavPoint axis_;           // unit vector into the slips
  core::NavPoint side_;           // unit vector to starboard of the axis
  double fix_m_ = 0.0;            // the camera's sideways fix of the GNSS position
  bool committed_ = false;        // mouth close: holding the slip's axis
  double marker_true_deg_ = 0.0;  // last camera sight of the target marker, while entering
  core::TimeNs marker_seen_ns_ = core::kNeverNs;
  Phase phase_ = Phase::kSurvey;
  core::TimeNs face_since_ns_ = core::kNeverNs;
  core::TimeNs backing_since_ns_ = core::kNeverNs;  // backing off a false stop
  // The fingers are looked for abeam of the lidar and this far aft (half the hull's length, so
  // half the hull is in the slip, as the judge counts); a false stop backs off this long.
  static constexpr double kFingerAftM = 0.6;
  static constexpr double kBackOffS = 3.0;
  static constexpr double kBackOffThrustFrac = 0.6;
  static constexpr double kFingerSlackM =
      0.2;                      // beyond half the slips' spacing: the finger's width
  double finger_side_m_ = 1.2;  // see the constructor
};

}  // namespace

std::unique_ptr<Task> make_docking2022_task(const config::TaskConfig& t,
                                            const config::MissionConfig& m,
                                            const core::LocalFrame& frame) {
  return std::make_unique<Docking2022Task>(t, m, frame);
}

}  // namespace coxswain::mission::detail
