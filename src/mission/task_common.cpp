// SPDX-License-Identifier: Apache-2.0
#include "task_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "coxswain/core/angles.hpp"

namespace coxswain::mission::detail {

ReasonText reason_printf(const char* fmt, ...) {
  ReasonText out;
  va_list args;
  va_start(args, fmt);
  (void)std::vsnprintf(out.chars.data(), out.chars.size(), fmt, args);
  va_end(args);
  return out;
}

msg::LedColour led_for(msg::Colour colour) {
  switch (colour) {
    case msg::Colour::kRed:
      return msg::LedColour::kRed;
    case msg::Colour::kGreen:
      return msg::LedColour::kGreen;
    case msg::Colour::kBlue:
      return msg::LedColour::kBlue;
    case msg::Colour::kYellow:
    case msg::Colour::kOrange:
      return msg::LedColour::kYellow;
    case msg::Colour::kPurple:
      return msg::LedColour::kPurple;
    case msg::Colour::kWhite:
      return msg::LedColour::kWhite;
    case msg::Colour::kBlack:
    case msg::Colour::kUnknown:
      break;
  }
  return msg::LedColour::kOff;
}

std::optional<double> range_near(const perception::RangeProfile& profile, double bearing_deg,
                                 double window_deg) {
  const double w = static_cast<double>(profile.bin_width_deg);
  const std::size_t bins = std::min<std::size_t>(profile.bin_count, profile.closest_range_m.size());
  if (!(w > 0.0) || bins == 0) return std::nullopt;
  std::optional<double> best;
  for (std::size_t i = 0; i < bins; ++i) {
    const double centre_deg = -180.0 + (static_cast<double>(i) + 0.5) * w;
    if (std::abs(core::angle_diff_deg(centre_deg, bearing_deg)) > window_deg + 0.5 * w) continue;
    const float r = profile.closest_range_m[i];
    if (!(r > 0.0F) || r >= perception::RangeProfile::kNoReturn) continue;
    if (!best || static_cast<double>(r) < *best) best = static_cast<double>(r);
  }
  return best;
}

void check(const std::optional<std::string>& problem) {
  if (problem) throw std::invalid_argument(*problem);
}

// Largest detection of `colour` (any shape) in a frame, or null.
const msg::Detection* largest_of(const msg::CameraDetections& cam, msg::Colour colour) {
  const msg::Detection* best = nullptr;
  const std::uint32_t n = std::min<std::uint32_t>(cam.count, msg::CameraDetections::kMaxDetections);
  for (std::uint32_t i = 0; i < n; ++i) {
    const msg::Detection& d = cam.detections[i];
    if (d.colour != colour) continue;
    if (best == nullptr || d.area_px > best->area_px) best = &d;
  }
  return best;
}

AvoidingTask::AvoidingTask(std::string_view name, const guidance::AvoidanceParams& params)
    : Task(name) {
  std::string error;
  auto av = guidance::Avoidance::create(params, &error);
  if (!av) throw std::invalid_argument("avoidance: " + error);
  avoidance_.emplace(*av);
}

ReasonText need_position_heading(const TaskContext& ctx) {
  if (!ctx.position_valid) return reason_printf("no usable GNSS fix");
  if (!ctx.heading_valid) return reason_printf("no heading");
  return {};
}

Route to_route(const std::vector<core::GeoPoint>& geo, const core::LocalFrame& frame) {
  Route r;
  for (const auto& g : geo) {
    if (r.count >= r.points.size()) break;
    r.points[r.count++] = frame.to_nav(g);
  }
  return r;
}

ReasonText event_reason(const guidance::WaypointGuidance& g, double dist_m) {
  return reason_printf("%s waypoint %zu (%.1f m)",
                       g.event == guidance::WaypointEvent::kArrived ? "arrived at" : "missed",
                       g.event_index + 1, dist_m);
}

std::unique_ptr<Task> make_task(const config::TaskConfig& task, const config::MissionConfig& m,
                                const core::LocalFrame& frame) {
  switch (task.type) {
    case config::TaskType::kHopping:
      return make_hopping_task(task, m, frame);
    case config::TaskType::kObstacleCourse:
      return make_avoidance_task(task, m, frame, false);
    case config::TaskType::kCourse1:
      return make_avoidance_task(task, m, frame, true);
    case config::TaskType::kCourse2:
      return make_course2_task(task, m, frame);
    case config::TaskType::kDocking:
      if (task.docking_style == config::DockingStyle::kCourse3) return make_course3_task(task, m);
      return make_docking2022_task(task, m, frame);
  }
  throw std::invalid_argument("unknown task type");
}

void steer_clear(guidance::Avoidance& avoidance, const TaskContext& ctx, double desired_heading_deg,
                 double reach_m, perception::ObstacleList& scratch, GuidanceRequest& out) {
  out.desired_heading_deg = desired_heading_deg;
  if (!ctx.lidar_fresh || ctx.obstacles == nullptr) return;
  scratch.clear();
  scratch.stamp_ns = ctx.obstacles->stamp_ns;
  for (std::uint32_t i = 0; i < ctx.obstacles->count; ++i) {
    const perception::ObstacleSegment& s = ctx.obstacles->segments[i];
    if (static_cast<double>(s.closest_range_m) <= reach_m) (void)scratch.push(s);
  }
  const double goal_body = core::angle_diff_deg(desired_heading_deg, ctx.pose.heading_deg);
  const guidance::AvoidanceDecision d = avoidance.decide(scratch, goal_body, ctx.now_ns);
  out.desired_heading_deg = core::wrap_deg(ctx.pose.heading_deg + d.bearing_body_deg);
  out.speed_factor = d.speed_factor;
  VizFrame& v = *ctx.viz;
  v.has_avoidance = true;
  v.avoidance_bearing_body_deg = d.bearing_body_deg;
  v.avoidance_status = static_cast<std::uint8_t>(d.status);
}

StuckWatch::Progress StuckWatch::update(core::TimeNs now_ns, core::NavPoint antenna) {
  constexpr double kStepGapS = 1.0;
  const bool resumed =
      last_step_ns_ == core::kNeverNs || core::ns_to_sec(now_ns - last_step_ns_) > kStepGapS;
  last_step_ns_ = now_ns;
  if (resumed || core::distance_m(antenna, progress_at_) > p_.stuck_distance_m) {
    progress_at_ = antenna;
    progress_ns_ = now_ns;
  }
  if (stuck_) {
    if (recovery_s(now_ns) < p_.stop_s + p_.back_off_s + p_.look_s) return Progress::kRecovering;
    stuck_ = false;
    progress_at_ = antenna;
    progress_ns_ = now_ns;
    return Progress::kRecovered;
  }
  if (p_.stuck_s > 0.0 && core::ns_to_sec(now_ns - progress_ns_) >= p_.stuck_s) {
    stuck_ = true;
    stuck_since_ns_ = now_ns;
    return Progress::kBecameStuck;
  }
  return Progress::kMoving;
}

ReasonText StuckWatch::stuck_reason(core::NavPoint antenna) const {
  return reason_printf("moved %.1f m in %.0f s: stop, back off, turn",
                       core::distance_m(antenna, progress_at_), p_.stuck_s);
}

void back_off_then_look(const guidance::MapPlannerParams& p, double heading_now_deg, double t_s,
                        double look_deg, GuidanceRequest& out) {
  out.steer = true;
  out.desired_heading_deg = heading_now_deg;
  out.thrust_frac = 0.0;
  if (t_s >= p.stop_s + p.back_off_s) {
    out.desired_heading_deg = look_deg;
    out.thrust_frac = p.look_thrust_frac;
  } else if (t_s >= p.stop_s) {
    out.thrust_frac = p.back_off_thrust_frac;
    out.speed_factor = -1.0;
  }
}

guidance::LineFollowParams slip_line_params(const config::MissionConfig& m) {
  guidance::LineFollowParams p = m.waypoints.line;
  p.lookahead_m = m.docking.approach.lookahead_m;
  // Joining a slip from metres off its axis, the integral wound up and carried the boat across
  // the axis onto a finger at the mouth (kaboat2026, 100 runs: 91 -> 92 clean, 96% -> 97%).
  p.integrate_within_m = 0.5;
  return p;
}

bool SlipTracker::update(const core::NavPose& pose, const guidance::SlipOpening& s) {
  const core::NavPoint mouth = core::body_to_nav(pose, {s.mouth_x_m, s.mouth_y_m});
  const double axis = core::wrap_deg(pose.heading_deg + s.axis_body_deg);
  if (seen_ && core::distance_m(mouth, mouth_) > kGateM && ++rejected_ < kRestartAfter) {
    return false;
  }
  if (!seen_ || rejected_ >= kRestartAfter) {
    mouth_ = mouth;
    axis_true_deg_ = axis;
    seen_ = true;
    rejected_ = 0;
    return true;
  }
  rejected_ = 0;
  constexpr double kAlpha = 0.3;
  mouth_.north_m += kAlpha * (mouth.north_m - mouth_.north_m);
  mouth_.east_m += kAlpha * (mouth.east_m - mouth_.east_m);
  axis_true_deg_ =
      core::wrap_deg(axis_true_deg_ + kAlpha * core::angle_diff_deg(axis, axis_true_deg_));
  return true;
}

double SlipTracker::follow_heading_deg(const core::NavPose& pose, double ray_start_m,
                                       core::TimeNs now_ns, double lookahead_per_m) {
  const double a = core::deg_to_rad(axis_true_deg_);
  const core::NavPoint from{mouth_.north_m - ray_start_m * std::cos(a),
                            mouth_.east_m - ray_start_m * std::sin(a)};
  const core::NavPoint to{mouth_.north_m + std::cos(a), mouth_.east_m + std::sin(a)};
  const double dt_s = last_ns_ == core::kNeverNs ? 0.0 : core::ns_to_sec(now_ns - last_ns_);
  last_ns_ = now_ns;
  const guidance::LineFollowOutput o = line_.update(from, to, pose.position, dt_s);
  if (!(lookahead_per_m > 0.0)) return o.desired_heading_deg;
  const double to_mouth_m = ray_start_m - o.along_track_m;
  const double lookahead_m = std::max(lookahead_m_, lookahead_per_m * to_mouth_m);
  const double shifted_m = o.cross_track_m + line_.integral_m();
  return core::wrap_deg(o.path_bearing_deg - core::rad_to_deg(std::atan2(shifted_m, lookahead_m)));
}

}  // namespace coxswain::mission::detail
