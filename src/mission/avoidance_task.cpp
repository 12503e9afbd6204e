// SPDX-License-Identifier: Apache-2.0
#include "task_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "coxswain/control/heading_reference.hpp"
#include "coxswain/core/angles.hpp"
#include "coxswain/guidance/buoy_circling.hpp"
#include "coxswain/guidance/docking_approach.hpp"
#include "coxswain/guidance/nav_filter.hpp"
#include "coxswain/guidance/waypoint_follower.hpp"
#include "coxswain/perception/marker_vote.hpp"

namespace coxswain::mission::detail {

namespace {

/// The two buoys of a gate as the lidar places them, in the navigation frame of the pose each
/// scan was taken with, and whether the boat's track has crossed between them.
struct GateTrack {
  bool seen = false;
  core::NavPoint left;   // port end, looking along the leg
  core::NavPoint right;  // starboard end
  [[nodiscard]] core::NavPoint mid() const {
    return {0.5 * (left.north_m + right.north_m), 0.5 * (left.east_m + right.east_m)};
  }
  /// From the port end to the starboard end.
  [[nodiscard]] core::NavPoint span() const {
    return {right.north_m - left.north_m, right.east_m - left.east_m};
  }
};

/// Avoidance toward the waypoints (the gates); for course 1, then the turn to find the buoy.
/// With the planner: a global path on the map to the waypoint (or through the gate), whose
/// look-ahead point is the goal the reactive avoidance steers to; no path: stop, back off, turn
/// to look, replan.
class AvoidanceTask final : public AvoidingTask {
 public:
  AvoidanceTask(const config::TaskConfig& t, const config::MissionConfig& m,
                const core::LocalFrame& frame, bool course1)
      : AvoidingTask(t.name, m.avoidance),
        route_(to_route(t.waypoints, frame)),
        leg_(m.waypoints, route_),
        wp_(m.waypoints),
        k_sigma_(m.waypoints.arrival_confidence > 0.0
                     ? guidance::normal_quantile(m.waypoints.arrival_confidence)
                     : 0.0),
        course1_(course1),
        c1_(m.course1),
        plan_(m.planning.planner),
        gates_(m.planning.gates),
        judge_gates_(!course1 && m.planning.gates.judge_by_lidar),
        legacy_(!m.planning.planner.enabled && !m.planning.gates.judge_by_lidar),
        cruise_(m.speed.cruise_thrust_frac),
        progress_(m.planning.planner) {}

  [[nodiscard]] std::uint8_t needs() const override { return kNeedGnss | kNeedImu | kNeedLidar; }

  ReasonText enter(const TaskContext& ctx) override {
    ReasonText r = need_position_heading(ctx);
    if (!r.empty()) return r;
    if (!ctx.lidar_fresh) return reason_printf("no lidar scan");
    if (route_.count == 0 || !leg_.start(ctx.antenna)) return reason_printf("no waypoints");
    avoidance_->reset();
    search_ = false;
    index_ = 0;
    leg_start_ = ctx.antenna;
    gate_ = {};
    passed_count_ = 0;
    have_prev_ = false;
    confirm_past_m_.reset();
    last_plan_ns_ = core::kNeverNs;
    if (ctx.plan != nullptr) taken_plans_ = ctx.plan->made;  // plans made before are not ours
    no_path_ = false;
    off_map_ = false;
    failures_ = 0;
    look_sign_ = 1.0;
    manoeuvre_ = Manoeuvre::kNone;
    astern_holdoff_ns_ = core::kNeverNs;
    progress_.reset();
    set_phase(sailing_phase(), "task entered");
    return {};
  }

  TaskResult step(const TaskContext& ctx, GuidanceRequest& out) override {
    if (ctx.lidar_new) ++scans_seen_;
    if (search_) return search(ctx, out);
    if (legacy_) return legacy_step(ctx, out);
    if (judge_gates_ && ctx.lidar_new && ctx.obstacles != nullptr) track_gate(ctx);
    if (advance(ctx)) {
      // The task's reason holds how the last waypoint was judged.
      if (!course1_) return TaskResult::kDone;
      return start_search(ctx, out);
    }
    const bool moving_on = watch_progress(ctx);
    const core::NavPoint goal = steering_goal(ctx);
    core::NavPoint aim = goal;
    bool planned_aim = false;
    double sight = 1.0;
    // The last metres through a gate are the avoidance's: the inflated buoys leave the planner
    // a passage only a cell or two wide.
    const bool in_gate_mouth = judge_gates_ && gate_.seen && gate_side(gate_, ctx.antenna) < 0.0 &&
                               core::distance_m(ctx.antenna, gate_.mid()) < kGateMouthM;
    if (plan_.enabled && ctx.map != nullptr && ctx.planner != nullptr && ctx.plan != nullptr &&
        !in_gate_mouth) {
      replan(ctx, goal);
      if (no_path_) {
        progress_.progress_made(ctx.now_ns);  // the no-path recovery moves the boat on its own
        return recover(ctx, out);
      }
      if (!off_map_) {
        if (const auto sg = ctx.planner->subgoal(ctx.antenna)) {
          aim = *sg;
          planned_aim = true;
        }
        sight = sight_factor(ctx);
      }
    }
    if (!moving_on) return unstick(ctx, aim, out);
    fill_viz(ctx, goal);
    const double turned_deg = steer(ctx, core::bearing_deg(ctx.antenna, aim), out, planned_aim);
    // The avoidance turned far from the sub-goal: round a corner of the path it would take the
    // free heading nearest the sub-goal's bearing, which may lead into the pocket the path goes
    // round. The path's nearer point in plain sight says which way round.
    if (planned_aim && std::abs(turned_deg) > kDivergeDeg) {
      if (const auto near = ctx.planner->subgoal(ctx.antenna, kNearSubgoalM);
          near && core::distance_m(*near, aim) > 0.25) {
        steer(ctx, core::bearing_deg(ctx.antenna, *near), out, true);
      }
    }
    if (planned_aim) {
      out.speed_factor *= turn_factor(ctx, aim);
      astern(ctx, aim, out);
    } else if (manoeuvre_ != Manoeuvre::kNone) {
      manoeuvre_ = Manoeuvre::kNone;  // no path to back along
      set_phase(sailing_phase(), "no planned path: astern ends");
    }
    out.speed_factor *= sight;
    return TaskResult::kRunning;
  }

 private:
  static constexpr std::size_t kMaxPassed = 16;

  TaskResult start_search(const TaskContext& ctx, GuidanceRequest& out) {
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

  /// Without the planner and the lidar gates (both off in the mission file): the reactive
  /// avoidance toward the waypoint follower's heading, the arrival judged on the GNSS estimate.
  TaskResult legacy_step(const TaskContext& ctx, GuidanceRequest& out) {
    const guidance::WaypointGuidance g = leg_.update(ctx);
    if (g.event != guidance::WaypointEvent::kNone && !g.finished) {
      set_reason(event_reason(g, core::distance_m(ctx.antenna, leg_.point(g.event_index))).view());
    }
    if (g.finished) {
      if (!course1_) {
        set_reason(reason_printf("passed the final gate"));
        return TaskResult::kDone;
      }
      return start_search(ctx, out);
    }
    steer(ctx, g.desired_heading_deg, out);
    return TaskResult::kRunning;
  }

  /// Steers toward `desired_deg` round what the lidar sees; returns how far (deg) the avoidance
  /// turned from it.
  double steer(const TaskContext& ctx, double desired_deg, GuidanceRequest& out,
               bool planned = false) {
    const double goal_body = core::angle_diff_deg(desired_deg, ctx.pose.heading_deg);
    const guidance::AvoidanceDecision d =
        avoidance_->decide(*ctx.obstacles, goal_body, ctx.now_ns, planned);
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
    return core::angle_diff_deg(d.bearing_body_deg, goal_body);
  }
  static constexpr double kDivergeDeg = 45.0;
  static constexpr double kNearSubgoalM = 1.0;
  static constexpr double kBuoyIsolationM = 0.8;
  static constexpr double kGateMouthM = 3.0;
  static constexpr double kGateLookaheadM = 4.0;

  [[nodiscard]] core::NavPoint target() const { return route_.points[index_]; }

  /// Unit vector along the current leg (north, east); north when the leg has no length.
  [[nodiscard]] core::NavPoint leg_dir() const {
    const core::NavPoint t = target();
    const double dn = t.north_m - leg_start_.north_m;
    const double de = t.east_m - leg_start_.east_m;
    const double len = std::hypot(dn, de);
    if (!(len > 1e-6)) return {1.0, 0.0};
    return {dn / len, de / len};
  }

  /// A gate is being judged: its buoys are in sight, or (the obstacle course, whose waypoints are
  /// all gates; course 1's waypoint is a place) the nominal gate stands in for them.
  [[nodiscard]] bool judging_a_gate() const { return judge_gates_ && (gate_.seen || !course1_); }

  /// The gate being judged: the buoys as the lidar places them, or (none seen, obstacle course)
  /// the nominal gate, planning.gates.width_m wide, square to the leg through the waypoint.
  [[nodiscard]] GateTrack judged_gate() const {
    if (gate_.seen) return gate_;
    const core::NavPoint t = target();
    const core::NavPoint l = leg_dir();
    const double half = 0.5 * gates_.width_m;
    const core::NavPoint port{l.east_m, -l.north_m};  // the leg turned 90 deg to port
    return {true,
            {t.north_m + half * port.north_m, t.east_m + half * port.east_m},
            {t.north_m - half * port.north_m, t.east_m - half * port.east_m}};
  }

  /// A gate's forward normal: square to the line between its ends, on the leg's side.
  [[nodiscard]] core::NavPoint gate_normal(const GateTrack& g) const {
    const double dn = g.span().north_m;
    const double de = g.span().east_m;
    const double len = std::max(std::hypot(dn, de), 1e-6);
    // Left to right turned 90 deg to port is forward (north-east frame, clockwise headings).
    core::NavPoint n{de / len, -dn / len};
    const core::NavPoint l = leg_dir();
    if (n.north_m * l.north_m + n.east_m * l.east_m < 0.0) n = {-n.north_m, -n.east_m};
    return n;
  }

  /// The stern's position on the estimate.
  [[nodiscard]] core::NavPoint stern_of(const TaskContext& ctx) const {
    const guidance::AvoidanceParams& hull = avoidance_->params();
    return core::body_to_nav(ctx.pose, {hull.bow_ahead_m - hull.hull_length_m, 0.0});
  }

  /// The phase the task sails in between manoeuvres.
  [[nodiscard]] const char* sailing_phase() const { return course1_ ? "to_waypoint" : "navigate"; }

  /// How far inside a gate judged on the estimate a crossing must lie, along `bearing_deg`: k
  /// sigma of the estimate; 0 with the buoys in sight or without the filter's covariance.
  [[nodiscard]] double estimate_margin_m(const TaskContext& ctx, double bearing_deg) const {
    if (gate_.seen || !ctx.position_cov_valid || !(wp_.arrival_confidence > 0.0)) return 0.0;
    return k_sigma_ * ctx.position_cov.sigma_along_m(bearing_deg);
  }

  /// The gate passed (the reason already set): on to the next; true when the route is done.
  bool count_gate(const TaskContext& ctx) {
    if (phase() != sailing_phase()) set_phase(sailing_phase(), reason());
    next_waypoint(ctx, true);
    return index_ >= route_.count;
  }

  /// Where the track was this tick, relative to the line it is judged on.
  void remember(core::NavPoint p, double side) {
    prev_ = p;
    prev_side_ = side;
    prev_by_lidar_ = gate_.seen;
    have_prev_ = true;
  }

  [[nodiscard]] double gate_side(const GateTrack& g, core::NavPoint p) const {
    const core::NavPoint n = gate_normal(g);
    const core::NavPoint c = g.mid();
    return (p.north_m - c.north_m) * n.north_m + (p.east_m - c.east_m) * n.east_m;
  }

  /// Looks for the current waypoint's gate among this scan's buoys (and follows it once seen).
  void track_gate(const TaskContext& ctx) {
    const perception::ObstacleList& obs = *ctx.obstacles;
    const std::uint32_t n =
        std::min<std::uint32_t>(obs.count, perception::ObstacleList::kMaxSegments);
    std::size_t count = 0;
    for (std::uint32_t i = 0; i < n && count < buoys_.size(); ++i) {
      const perception::ObstacleSegment& s = obs.segments[i];
      if (s.kind == perception::ObstacleKind::kWall) continue;
      const double len =
          std::hypot(s.end.forward_m - s.begin.forward_m, s.end.starboard_m - s.begin.starboard_m);
      if (len > gates_.max_buoy_length_m) continue;
      const core::BodyPoint mid{0.5 * (s.begin.forward_m + s.end.forward_m),
                                0.5 * (s.begin.starboard_m + s.end.starboard_m)};
      // A buoy stands alone: a short piece with other pieces beside it is part of a wall or
      // dock (the far ends of a wall break into short pieces too).
      bool alone = true;
      for (std::uint32_t j = 0; j < n && alone; ++j) {
        if (j == i) continue;
        const perception::ObstacleSegment& o = obs.segments[j];
        const auto near = [&](core::BodyPoint q) {
          return std::hypot(q.forward_m - mid.forward_m, q.starboard_m - mid.starboard_m) <
                 kBuoyIsolationM;
        };
        alone = !near(o.begin) && !near(o.end);
      }
      if (!alone) continue;
      buoys_[count++] = core::body_to_nav(ctx.pose, mid);
    }
    const core::NavPoint wp = target();
    const core::NavPoint l = leg_dir();
    const double cos_max = std::cos(core::deg_to_rad(90.0 - gates_.max_angle_deg));
    double best = std::numeric_limits<double>::infinity();
    GateTrack found;
    for (std::size_t i = 0; i < count; ++i) {
      for (std::size_t j = i + 1; j < count; ++j) {
        const core::NavPoint a = buoys_[i];
        const core::NavPoint b = buoys_[j];
        const double d = core::distance_m(a, b);
        if (std::abs(d - gates_.width_m) > gates_.width_tolerance_m) continue;
        const core::NavPoint mid{0.5 * (a.north_m + b.north_m), 0.5 * (a.east_m + b.east_m)};
        // Square to the leg: the buoys' line makes at most max_angle_deg with the leg's normal.
        const double along =
            std::abs(((b.north_m - a.north_m) * l.north_m + (b.east_m - a.east_m) * l.east_m) / d);
        if (along > cos_max) continue;
        bool passed = false;
        for (std::size_t k = 0; k < std::min(passed_count_, kMaxPassed); ++k) {
          passed = passed || core::distance_m(mid, passed_[k]) < gates_.track_gate_m;
        }
        if (passed) continue;
        double score = 0.0;
        if (gate_.seen) {
          score = core::distance_m(mid, gate_.mid());
          if (score > gates_.track_gate_m) continue;
        } else {
          score = core::distance_m(mid, wp);
          if (score > gates_.search_radius_m) continue;
        }
        if (score >= best) continue;
        best = score;
        // Port end first, looking along the leg.
        const double cross = l.north_m * (b.east_m - a.east_m) - l.east_m * (b.north_m - a.north_m);
        found.seen = true;
        found.left = cross > 0.0 ? a : b;
        found.right = cross > 0.0 ? b : a;
      }
    }
    if (!found.seen) return;
    if (!gate_.seen) {
      gate_ = found;
      return;
    }
    constexpr double kAlpha = 0.5;
    gate_.left.north_m += kAlpha * (found.left.north_m - gate_.left.north_m);
    gate_.left.east_m += kAlpha * (found.left.east_m - gate_.left.east_m);
    gate_.right.north_m += kAlpha * (found.right.north_m - gate_.right.north_m);
    gate_.right.east_m += kAlpha * (found.right.east_m - gate_.right.east_m);
  }

  void next_waypoint(const TaskContext& ctx, bool arrived) {
    if (gate_.seen && passed_count_ < kMaxPassed) passed_[passed_count_++] = gate_.mid();
    if (arrived) {
      ++ctx.status->waypoints_arrived;
    } else {
      ++ctx.status->waypoints_missed;
    }
    leg_start_ = target();
    ++index_;
    gate_ = {};
    have_prev_ = false;
    confirm_past_m_.reset();
    last_plan_ns_ = core::kNeverNs;
  }

  /// Judges the current waypoint; true when the route is done.
  bool advance(const TaskContext& ctx) {
    const core::NavPoint p = ctx.antenna;
    if (judging_a_gate()) {
      // The track must cross the segment between the gate's ends: the buoys as the lidar places
      // them (relative geometry, which a GNSS bias does not move), or without them the nominal
      // gate, whose crossing must lie inside its ends by k sigma of the estimate.
      const GateTrack g = judged_gate();
      const double side = gate_side(g, p);
      if (have_prev_ && prev_by_lidar_ != gate_.seen) {  // another line
        have_prev_ = false;
        confirm_past_m_.reset();
      }
      if (confirm_past_m_) {
        // Crossed between the ends: counted once the stern is past the line too, on the
        // estimate confidently so (else a boat stopping at the finish may stop short of it).
        if (gate_side(g, stern_of(ctx)) >= *confirm_past_m_) {
          set_reason(confirm_reason_.view());
          return count_gate(ctx);
        }
        if (side < 0.0) confirm_past_m_.reset();  // back before the line: cross it again
        remember(p, side);
        return false;
      }
      if (have_prev_ && prev_side_ < 0.0 && side >= 0.0) {
        const double f = prev_side_ / (prev_side_ - side);
        const core::NavPoint x{prev_.north_m + f * (p.north_m - prev_.north_m),
                               prev_.east_m + f * (p.east_m - prev_.east_m)};
        const double dn = g.span().north_m;
        const double de = g.span().east_m;
        const double width = std::max(std::hypot(dn, de), 1e-9);
        const double across =
            ((x.north_m - g.left.north_m) * dn + (x.east_m - g.left.east_m) * de) / width;
        const double margin = estimate_margin_m(ctx, core::rad_to_deg(std::atan2(de, dn)));
        const char* by = gate_.seen ? "lidar" : "GNSS";
        if (across >= margin && across <= width - margin) {
          set_reason(reason_printf("passed gate %zu between its %s (%s, %.0f%% across)", index_ + 1,
                                   gate_.seen ? "buoys" : "ends", by, 100.0 * across / width));
          const core::NavPoint n = gate_normal(g);
          const double past_m =
              estimate_margin_m(ctx, core::rad_to_deg(std::atan2(n.east_m, n.north_m)));
          if (gate_side(g, stern_of(ctx)) < past_m) {
            confirm_past_m_ = past_m;
            confirm_reason_ =
                reason_printf("%s, stern %.1f m past it", reason().chars.data(), past_m);
            remember(p, side);
            return false;
          }
          return count_gate(ctx);
        }
        const bool port = across < 0.5 * width;
        const double out_m = port ? margin - across : across - (width - margin);
        set_phase("turn_back",
                  reason_printf("missed gate %zu: crossed %.1f m outside its %s %s (%s); "
                                "turning back",
                                index_ + 1, out_m, port ? "port" : "starboard",
                                gate_.seen ? "buoy" : "end", by));
        ++ctx.status->waypoints_missed;
      } else if (have_prev_ && prev_side_ >= 0.0 && side < 0.0 && phase() == "turn_back") {
        set_phase(sailing_phase(), reason_printf("back before gate %zu", index_ + 1));
      }
      remember(p, side);
      return false;
    }
    // A place (course 1's waypoint, or gates not judged): the position estimate inside the
    // arrival radius, or passed abeam. With the filter's covariance the estimate must be
    // confidently inside the rule's radius, so an uncertain estimate (an outage, a bias not yet
    // pinned) never counts it.
    const core::NavPoint t = target();
    const double dist = core::distance_m(p, t);
    const bool by_confidence = ctx.position_cov_valid && wp_.arrival_confidence > 0.0;
    const bool arrived = by_confidence ? guidance::confidently_within(p, ctx.position_cov, t,
                                                                      wp_.rule_radius_m, k_sigma_)
                                       : dist <= wp_.arrival_radius_m;
    if (arrived) {
      set_reason(reason_printf("arrived at waypoint %zu (%.1f m, GNSS)", index_ + 1, dist).view());
      next_waypoint(ctx, true);
      return index_ >= route_.count;
    }
    const core::NavPoint l = leg_dir();
    const double along = (p.north_m - t.north_m) * l.north_m + (p.east_m - t.east_m) * l.east_m;
    if (along > 0.0 && dist <= wp_.slip_radius_m && !judge_gates_) {
      set_reason(reason_printf("missed waypoint %zu (%.1f m)", index_ + 1, dist).view());
      next_waypoint(ctx, false);
      return index_ >= route_.count;
    }
    return false;
  }

  /// Where the path goes: through the gate (to a point beyond it) when the boat is before it,
  /// back to a point before it when past it; else the waypoint.
  [[nodiscard]] core::NavPoint steering_goal(const TaskContext& ctx) const {
    if (!judging_a_gate()) return target();
    const GateTrack g = judged_gate();
    const core::NavPoint n = gate_normal(g);
    const core::NavPoint c = g.mid();
    const double side = gate_side(g, ctx.antenna);
    // Before a gate judged on the estimate: a point on its centre line kGateLookaheadM ahead of
    // the boat (from approach_m before the gate to 1.5 m beyond it), so the boat comes at it
    // square and on the centre line, where the estimate's error matters least. Buoys in sight:
    // through the gate they mark.
    const double ahead =
        gate_.seen ? 1.5 : std::clamp(side + kGateLookaheadM, -gates_.approach_m, 1.5);
    // Confirming a crossing: on through the gate, past where the stern must get.
    const double k = confirm_past_m_ ? *confirm_past_m_ + avoidance_->params().hull_length_m + 1.5
                     : side < 0.0    ? ahead
                                     : -gates_.approach_m;
    return {c.north_m + k * n.north_m, c.east_m + k * n.east_m};
  }

  /// Takes the outcome of the last plan made for this task, then asks for a new one when one is
  /// due: at most every replan_period_s, or at once when the goal moves. A plan asked for on this
  /// tick is made after it (PlanRequest), so its outcome is taken on the next.
  void replan(const TaskContext& ctx, core::NavPoint goal) {
    take_plan(ctx);
    const bool goal_moved = core::distance_m(goal, planned_goal_) > 0.5;
    if (last_plan_ns_ != core::kNeverNs && !goal_moved &&
        core::ns_to_sec(ctx.now_ns - last_plan_ns_) < plan_.replan_period_s) {
      return;
    }
    last_plan_ns_ = ctx.now_ns;
    planned_goal_ = goal;
    PlanRequest& r = *ctx.plan;
    r.pending = true;
    r.owner = this;
    r.start = ctx.antenna;
    r.goal = goal;
    r.wall_count = 0;
    if (judging_a_gate() && gates_.wall_m > 0.0) {
      // The gate's line beyond its ends is a wall for the path: it crosses between them.
      const GateTrack g = judged_gate();
      const double dn = g.span().north_m;
      const double de = g.span().east_m;
      const double width = std::max(std::hypot(dn, de), 1e-9);
      const double f = gates_.wall_m / width;
      r.walls[0] = {g.left, {g.left.north_m - f * dn, g.left.east_m - f * de}};
      r.walls[1] = {g.right, {g.right.north_m + f * dn, g.right.east_m + f * de}};
      r.wall_count = 2;
    }
  }

  void take_plan(const TaskContext& ctx) {
    const PlanRequest& r = *ctx.plan;
    if (r.made == taken_plans_) return;
    taken_plans_ = r.made;
    if (r.made_for != this) return;
    const guidance::PlanStatus st = r.status;
    off_map_ = st == guidance::PlanStatus::kStartOutside;
    if (off_map_) return;  // no map out here: the avoidance alone, toward the goal
    if (st == guidance::PlanStatus::kOk) {
      failures_ = 0;
      if (no_path_) {
        no_path_ = false;
        set_phase(sailing_phase(), "path found again");
      }
      return;
    }
    // One failed plan may be a noisy scan; two in a row is no way through.
    if (++failures_ >= 2 && !no_path_) {
      no_path_ = true;
      no_path_since_ns_ = ctx.now_ns;
      look_heading_deg_ = look_heading(ctx);
      look_sign_ = -look_sign_;
      set_phase("no_path", reason_printf("no path to the goal (%s): stop, back off, look",
                                         guidance::to_string(st)));
    }
  }

  /// Never outrun the lidar: the speed falls as the planned path nears water not yet seen.
  [[nodiscard]] double sight_factor(const TaskContext& ctx) const {
    if (!(plan_.sight_full_speed_m > 0.0)) return 1.0;
    const double seen = ctx.planner->seen_ahead_m(*ctx.map, ctx.antenna, plan_.sight_full_speed_m);
    return std::max(plan_.sight_min_speed_factor, seen / plan_.sight_full_speed_m);
  }

  /// Slow for a turn (planner.turn_slow_deg): 1 with the aim within turn_slow_deg of the bow,
  /// down to turn_min_speed_factor at 90 deg off it or more.
  [[nodiscard]] double turn_factor(const TaskContext& ctx, core::NavPoint aim) const {
    if (!(plan_.turn_slow_deg > 0.0)) return 1.0;
    const double off_deg =
        std::abs(core::angle_diff_deg(core::bearing_deg(ctx.antenna, aim), ctx.pose.heading_deg));
    const double f =
        std::clamp((off_deg - plan_.turn_slow_deg) / (90.0 - plan_.turn_slow_deg), 0.0, 1.0);
    return 1.0 - f * (1.0 - plan_.turn_min_speed_factor);
  }

  /// Follows the boat's progress; false while it is stuck (moved less than stuck_distance_m in
  /// stuck_s) and backing off, true when it may sail on.
  bool watch_progress(const TaskContext& ctx) {
    switch (progress_.update(ctx.now_ns, ctx.antenna)) {
      case StuckWatch::Progress::kMoving:
        return true;
      case StuckWatch::Progress::kRecovering:
        return false;
      case StuckWatch::Progress::kRecovered:
        set_phase(sailing_phase(), "backed off; on toward the goal");
        return true;
      case StuckWatch::Progress::kBecameStuck:
        break;
    }
    look_sign_ = -look_sign_;
    planned_goal_ = steering_goal(ctx);
    set_phase("stuck", progress_.stuck_reason(ctx.antenna).view());
    return false;
  }

  /// Astern along the path (planner.astern_*): with the path's sub-goal behind and no room for
  /// the swept hull to turn to it, as in a pocket narrower than the turning circle, the boat
  /// backs along the path stern first instead of swinging its stern into the pocket's side:
  /// the stern follows the path while it leads behind, then the boat backs straight on to make
  /// room. Once the turn to the sub-goal has room, it turns onto it at look_thrust_frac,
  /// steering at the sub-goal itself (the avoidance would take the free heading nearest it,
  /// back into the pocket), until the sub-goal is near the bow; a turn that runs out of room
  /// backs on again. The water astern closing, or astern_max_m backed in all, ends it. Called
  /// after steer(); overrides `out` while it lasts.
  void astern(const TaskContext& ctx, core::NavPoint aim, GuidanceRequest& out) {
    if (!plan_.astern_enabled || ctx.obstacles == nullptr) return;
    const double to_aim_deg = core::bearing_deg(ctx.antenna, aim);
    const double off_bow_deg = core::angle_diff_deg(to_aim_deg, ctx.pose.heading_deg);
    const double turn_deg = std::abs(off_bow_deg);
    if (manoeuvre_ == Manoeuvre::kNone &&
        (turn_deg <= plan_.astern_behind_deg ||
         (astern_holdoff_ns_ != core::kNeverNs && ctx.now_ns < astern_holdoff_ns_))) {
      return;
    }
    const guidance::Side side =
        off_bow_deg >= 0.0 ? guidance::Side::kStarboard : guidance::Side::kPort;
    const bool room = avoidance_->turn_room_deg(*ctx.obstacles, side, turn_deg) >= turn_deg;
    const bool stern_clear = avoidance_->astern_room_m(*ctx.obstacles, plan_.astern_look_m) > 0.0;
    const double backed_m = core::distance_m(ctx.antenna, astern_from_);
    const auto end = [&](const char* why) {
      manoeuvre_ = Manoeuvre::kNone;
      astern_holdoff_ns_ = ctx.now_ns + core::sec_to_ns(kAsternHoldoffS);
      set_phase(sailing_phase(), reason_printf("%s after %.1f m astern", why, backed_m));
    };
    switch (manoeuvre_) {
      case Manoeuvre::kNone:
        if (room || !stern_clear) return;
        manoeuvre_ = Manoeuvre::kAstern;
        astern_from_ = ctx.antenna;
        set_phase("astern",
                  reason_printf("path behind (%.0f deg) and no room to turn: astern", off_bow_deg));
        break;
      case Manoeuvre::kAstern:
        if (room) {
          manoeuvre_ = Manoeuvre::kTurn;
          set_phase("turn_to_path", reason_printf("room to turn %.0f deg after %.1f m astern",
                                                  off_bow_deg, backed_m));
        } else if (!stern_clear) {
          end("astern blocked");
          return;
        } else if (backed_m >= plan_.astern_max_m) {
          end("astern far enough");
          return;
        }
        break;
      case Manoeuvre::kTurn:
        if (turn_deg <= kTurnedDeg) {
          end("turned onto the path");
          return;
        }
        if (!room) {
          // Back on to make room (the distance backed counts from the first time astern).
          if (!stern_clear || backed_m >= plan_.astern_max_m) {
            end("no room left to turn");
            return;
          }
          manoeuvre_ = Manoeuvre::kAstern;
          set_phase("astern",
                    reason_printf("no room left to turn (%.0f deg): astern again", off_bow_deg));
        }
        break;
    }
    out.steer = true;
    if (manoeuvre_ == Manoeuvre::kTurn) {
      out.desired_heading_deg = to_aim_deg;
      out.thrust_frac = plan_.look_thrust_frac;
      out.speed_factor = 1.0;
      return;
    }
    // Stern first along the path itself, the stern steered onto it (the sub-goal may lie round
    // the corner the stern would cut). Once that part of the path leads off the bow, straight
    // back.
    const guidance::AvoidanceParams& hull = avoidance_->params();
    const core::NavPoint stern =
        core::body_to_nav(ctx.pose, {hull.bow_ahead_m - hull.hull_length_m, 0.0});
    const core::NavPoint back_to = ctx.planner->along_path(stern, kAsternAimM).value_or(aim);
    const double back_to_deg = core::bearing_deg(stern, back_to);
    out.desired_heading_deg =
        std::abs(core::angle_diff_deg(back_to_deg, ctx.pose.heading_deg)) > kAsternBehindDeg
            ? core::wrap_deg(back_to_deg + 180.0)
            : ctx.pose.heading_deg;
    out.thrust_frac = plan_.astern_thrust_frac;
    out.speed_factor = -1.0;
  }
  static constexpr double kAsternBehindDeg = 90.0;
  static constexpr double kTurnedDeg = 30.0;
  static constexpr double kAsternHoldoffS = 2.0;
  static constexpr double kAsternAimM = 1.5;

  /// Stuck: stop, back off astern on the same heading, then turn toward the path's sub-goal
  /// (with the planner) or square to the goal, one side then the other (without).
  TaskResult unstick(const TaskContext& ctx, core::NavPoint aim, GuidanceRequest& out) {
    const bool planned = plan_.enabled && ctx.planner != nullptr && !off_map_ &&
                         ctx.planner->status() == guidance::PlanStatus::kOk;
    const double look_deg = planned ? core::bearing_deg(ctx.antenna, aim) : look_heading(ctx);
    return back_off_then_look(ctx, progress_.recovery_s(ctx.now_ns), look_deg, out);
  }

  /// `t` seconds into a recovery (stuck or no path): back_off_then_look, drawn.
  /// With something within astern_look_m of the stern (a boat pinned stern first on a wall)
  /// backing off would only press it on: it turns to look at once.
  TaskResult back_off_then_look(const TaskContext& ctx, double t, double look_deg,
                                GuidanceRequest& out) {
    if (t >= plan_.stop_s && t < plan_.stop_s + plan_.back_off_s && stern_blocked(ctx)) {
      t = plan_.stop_s + plan_.back_off_s;
    }
    detail::back_off_then_look(plan_, ctx.pose.heading_deg, t, look_deg, out);
    fill_viz(ctx, steering_goal(ctx));
    return TaskResult::kRunning;
  }

  /// Square to the goal's bearing, one side then the other: looking round, never at the goal.
  double look_heading(const TaskContext& ctx) const {
    const double to_goal = core::bearing_deg(ctx.antenna, planned_goal_);
    return core::wrap_deg(to_goal + look_sign_ * plan_.look_turn_deg);
  }

  /// No path: stop, back off, turn to look; the replans above end it. Never toward the goal.
  TaskResult recover(const TaskContext& ctx, GuidanceRequest& out) {
    double t = core::ns_to_sec(ctx.now_ns - no_path_since_ns_);
    const double cycle = plan_.stop_s + plan_.back_off_s + plan_.look_s;
    if (cycle > 0.0 && t >= cycle) {
      // A new cycle looks the other way.
      no_path_since_ns_ = ctx.now_ns;
      look_heading_deg_ = look_heading(ctx);
      look_sign_ = -look_sign_;
      t = 0.0;
    }
    return back_off_then_look(ctx, t, look_heading_deg_, out);
  }

  /// Something within astern_look_m of the stern, in this scan: worked out once per scan (the
  /// obstacles are in the body frame and change only with a new scan).
  bool stern_blocked(const TaskContext& ctx) {
    if (ctx.obstacles == nullptr) return false;
    if (stern_checked_scan_ != scans_seen_) {
      stern_checked_scan_ = scans_seen_;
      stern_blocked_ = !(avoidance_->astern_room_m(*ctx.obstacles, plan_.astern_look_m) > 0.0);
    }
    return stern_blocked_;
  }

  void fill_viz(const TaskContext& ctx, core::NavPoint goal) const {
    VizFrame& v = *ctx.viz;
    v.has_goal = true;
    v.goal = goal;
    v.arrival_radius_m = ctx.position_cov_valid && wp_.arrival_confidence > 0.0
                             ? wp_.rule_radius_m
                             : wp_.arrival_radius_m;
    v.active_waypoint = static_cast<std::int32_t>(index_);
    v.has_leg = true;
    v.leg_start = leg_start_;
    v.distance_to_go_m = core::distance_m(ctx.antenna, goal);
    if (judging_a_gate()) {
      const GateTrack g = judged_gate();
      v.has_gate = true;
      v.gate_by_lidar = gate_.seen;
      v.gate_port = g.left;
      v.gate_starboard = g.right;
    }
    v.path_count = 0;
    if (plan_.enabled && ctx.planner != nullptr && !off_map_ && !no_path_ &&
        ctx.planner->status() == guidance::PlanStatus::kOk) {
      thin_path(ctx.planner->path(), v);
    }
  }

  /// Every k-th cell of the path (its ends always), so any length fits the frame.
  static void thin_path(const std::vector<core::NavPoint>& path, VizFrame& v) {
    const std::size_t n = path.size();
    if (n == 0) return;
    const std::size_t step = (n + VizFrame::kMaxPathPoints - 2) / (VizFrame::kMaxPathPoints - 1);
    for (std::size_t i = 0; i + 1 < n && v.path_count + 1 < VizFrame::kMaxPathPoints; i += step) {
      v.path[v.path_count++] = path[i];
    }
    v.path[v.path_count++] = path[n - 1];
  }

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

  Route route_;
  RouteLeg leg_;
  guidance::WaypointFollowerParams wp_;
  double k_sigma_;  // one-sided quantile of waypoints.arrival_confidence
  bool course1_;
  config::Course1Config c1_;
  guidance::MapPlannerParams plan_;
  guidance::GateParams gates_;
  bool judge_gates_;
  bool legacy_;
  double cruise_;
  bool search_ = false;
  core::TimeNs search_since_ns_ = 0;
  double search_heading_deg_ = 0.0;
  // Route and gates.
  std::size_t index_ = 0;
  core::NavPoint leg_start_;
  GateTrack gate_;
  std::array<core::NavPoint, kMaxPassed> passed_{};
  std::size_t passed_count_ = 0;
  std::array<core::NavPoint, perception::ObstacleList::kMaxSegments> buoys_{};
  bool have_prev_ = false;
  core::NavPoint prev_;
  double prev_side_ = 0.0;
  // prev_side_ measured from the lidar's buoys (else from the nominal gate).
  bool prev_by_lidar_ = false;
  // A crossing between the ends waits for the stern to be this far past the line (on the
  // estimate); the reason it will be counted with.
  std::optional<double> confirm_past_m_;
  ReasonText confirm_reason_;
  // Planning.
  core::TimeNs last_plan_ns_ = core::kNeverNs;
  core::NavPoint planned_goal_;
  std::uint64_t taken_plans_ = 0;  // PlanRequest::made when this task last looked
  int failures_ = 0;
  bool no_path_ = false;
  bool off_map_ = false;
  core::TimeNs no_path_since_ns_ = 0;
  double look_heading_deg_ = 0.0;
  double look_sign_ = 1.0;
  std::uint64_t scans_seen_ = 0;                   // new scans this task has stepped through
  std::uint64_t stern_checked_scan_ = UINT64_MAX;  // the scan stern_blocked_ was worked out for
  bool stern_blocked_ = false;
  StuckWatch progress_;
  // Astern along the path.
  enum class Manoeuvre : std::uint8_t { kNone, kAstern, kTurn };
  Manoeuvre manoeuvre_ = Manoeuvre::kNone;
  core::NavPoint astern_from_;
  core::TimeNs astern_holdoff_ns_ = core::kNeverNs;
};

}  // namespace

std::unique_ptr<Task> make_avoidance_task(const config::TaskConfig& t,
                                          const config::MissionConfig& m,
                                          const core::LocalFrame& frame, bool course1) {
  return std::make_unique<AvoidanceTask>(t, m, frame, course1);
}

}  // namespace coxswain::mission::detail
