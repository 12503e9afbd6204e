// SPDX-License-Identifier: Apache-2.0
#include "tasks.hpp"

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

namespace {

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

ReasonText need_position_heading(const TaskContext& ctx) {
  if (!ctx.position_valid) return reason_printf("no usable GNSS fix");
  if (!ctx.heading_valid) return reason_printf("no heading");
  return {};
}

// Waypoints of a task in the navigation frame (fixed storage).
struct Route {
  std::array<core::NavPoint, guidance::WaypointFollower::kMaxWaypoints> points{};
  std::size_t count = 0;
  [[nodiscard]] std::span<const core::NavPoint> span() const { return {points.data(), count}; }
};

Route to_route(const std::vector<core::GeoPoint>& geo, const core::LocalFrame& frame) {
  Route r;
  for (const auto& g : geo) {
    if (r.count >= r.points.size()) break;
    r.points[r.count++] = frame.to_nav(g);
  }
  return r;
}

// Shared waypoint-following step: follower, viz, counters, phase names. Returns the guidance.
class RouteLeg {
 public:
  RouteLeg(const guidance::WaypointFollowerParams& p, Route route)
      : params_(p), follower_(p), route_(route) {}

  [[nodiscard]] bool start(core::NavPoint position) {
    leg_start_ = position;
    return follower_.set_route(route_.span());
  }
  guidance::WaypointGuidance update(const TaskContext& ctx) {
    const guidance::WaypointGuidance g = follower_.update(ctx.antenna, ctx.now_ns);
    if (g.event == guidance::WaypointEvent::kArrived) {
      ++ctx.status->waypoints_arrived;
      leg_start_ = route_.points[g.event_index];
    } else if (g.event == guidance::WaypointEvent::kMissed) {
      ++ctx.status->waypoints_missed;
      leg_start_ = route_.points[g.event_index];
    }
    if (!g.finished) {
      VizFrame& v = *ctx.viz;
      v.has_goal = true;
      v.goal = g.target;
      v.arrival_radius_m = params_.arrival_radius_m;
      v.active_waypoint = static_cast<std::int32_t>(g.index);
      v.has_leg = true;
      v.leg_start = leg_start_;
      v.cross_track_m = g.cross_track_m;
      v.distance_to_go_m = g.distance_to_go_m;
    }
    return g;
  }
  [[nodiscard]] std::size_t size() const { return route_.count; }
  [[nodiscard]] core::NavPoint point(std::size_t i) const { return route_.points[i]; }

 private:
  guidance::WaypointFollowerParams params_;
  guidance::WaypointFollower follower_;
  Route route_;
  core::NavPoint leg_start_;
};

ReasonText event_reason(const guidance::WaypointGuidance& g, double dist_m) {
  return reason_printf("%s waypoint %zu (%.1f m)",
                       g.event == guidance::WaypointEvent::kArrived ? "arrived at" : "missed",
                       g.event_index + 1, dist_m);
}

// ---- hopping ------------------------------------------------------------------------------

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

// ---- obstacle course (2022) and course 1 (2026) -----------------------------------------

/// Avoidance toward the waypoints (the gate); for course 1, then the turn to find the buoy.
class AvoidanceTask final : public Task {
 public:
  AvoidanceTask(const config::TaskConfig& t, const config::MissionConfig& m,
                const core::LocalFrame& frame, bool course1)
      : Task(t.name),
        leg_(m.waypoints, to_route(t.waypoints, frame)),
        course1_(course1),
        c1_(m.course1),
        cruise_(m.cruise_thrust_frac) {
    std::string error;
    auto av = guidance::Avoidance::create(m.avoidance, &error);
    if (!av) throw std::invalid_argument("avoidance: " + error);
    avoidance_.emplace(std::move(*av));
  }

  [[nodiscard]] std::uint8_t needs() const override { return kNeedGnss | kNeedImu | kNeedLidar; }

  ReasonText enter(const TaskContext& ctx) override {
    ReasonText r = need_position_heading(ctx);
    if (!r.empty()) return r;
    if (!ctx.lidar_fresh) return reason_printf("no lidar scan");
    if (!leg_.start(ctx.antenna)) return reason_printf("no waypoints");
    avoidance_->reset();
    search_ = false;
    set_phase(course1_ ? "to_waypoint" : "navigate", "task entered");
    return {};
  }

  TaskResult step(const TaskContext& ctx, GuidanceRequest& out) override {
    if (search_) return search(ctx, out);
    const guidance::WaypointGuidance g = leg_.update(ctx);
    if (g.event != guidance::WaypointEvent::kNone && !g.finished) {
      set_reason(event_reason(g, core::distance_m(ctx.antenna, leg_.point(g.event_index))).view());
    }
    if (g.finished) {
      if (!course1_) {
        set_reason(reason_printf("passed the final gate"));
        return TaskResult::kDone;
      }
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
    const double goal_body = core::angle_diff_deg(g.desired_heading_deg, ctx.pose.heading_deg);
    const guidance::AvoidanceDecision d = avoidance_->decide(*ctx.obstacles, goal_body, ctx.now_ns);
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
    return TaskResult::kRunning;
  }

 private:
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

  RouteLeg leg_;
  bool course1_;
  config::Course1Config c1_;
  double cruise_;
  std::optional<guidance::Avoidance> avoidance_;
  bool search_ = false;
  core::TimeNs search_since_ns_ = 0;
  double search_heading_deg_ = 0.0;
};

// ---- course 2 (2026) ----------------------------------------------------------------------

/// Circle the buoy once on the camera side, identify the target colour, light the LED, go on.
class Course2Task final : public Task {
 public:
  enum class Phase : std::uint8_t { kCircling, kSeekColour, kToWaypoint };

  Course2Task(const config::TaskConfig& t, const config::MissionConfig& m,
              const core::LocalFrame& frame)
      : Task(t.name),
        c_(m.course2),
        circling_(m.course2.circling),
        leg_(m.waypoints, to_route(t.waypoints, frame)),
        votes_{perception::MarkerVote(m.vision_vote), perception::MarkerVote(m.vision_vote),
               perception::MarkerVote(m.vision_vote), perception::MarkerVote(m.vision_vote),
               perception::MarkerVote(m.vision_vote), perception::MarkerVote(m.vision_vote),
               perception::MarkerVote(m.vision_vote), perception::MarkerVote(m.vision_vote)} {
    check(m.course2.circling.validate());
    colour_count_ = std::min<std::size_t>(m.course2.colours.size(), colours_.size());
    for (std::size_t i = 0; i < colour_count_; ++i) colours_[i] = m.course2.colours[i];
  }

  [[nodiscard]] std::uint8_t needs() const override { return kNeedGnss | kNeedImu; }

  ReasonText enter(const TaskContext& ctx) override {
    ReasonText r = need_position_heading(ctx);
    if (!r.empty()) return r;
    circling_.reset();
    for (auto& v : votes_) v.reset();
    phase_ = Phase::kCircling;
    set_phase("circling", "task entered");
    return {};
  }

  TaskResult step(const TaskContext& ctx, GuidanceRequest& out) override {
    switch (phase_) {
      case Phase::kCircling:
        return circle(ctx, out);
      case Phase::kSeekColour:
        return seek(ctx, out);
      case Phase::kToWaypoint:
        break;
    }
    const guidance::WaypointGuidance g = leg_.update(ctx);
    if (g.finished) {
      set_reason(reason_printf("reached the course 2 waypoint"));
      return TaskResult::kDone;
    }
    out.steer = true;
    out.desired_heading_deg = g.desired_heading_deg;
    out.schedule_distance_m = g.distance_to_go_m;
    return TaskResult::kRunning;
  }

 private:
  TaskResult circle(const TaskContext& ctx, GuidanceRequest& out) {
    guidance::BuoyObservation obs;
    // An old bearing steered on while the heading changes would overshoot: only recent frames.
    if (ctx.camera != nullptr &&
        core::ns_to_sec(ctx.now_ns - ctx.camera->stamp_ns) <= c_.buoy_memory_s) {
      if (const msg::Detection* d = largest_of(*ctx.camera, c_.buoy_colour)) {
        obs.bearing_deg = static_cast<double>(d->bearing_deg);
        if (ctx.lidar_fresh && ctx.profile != nullptr) {
          obs.range_m = range_near(*ctx.profile, *obs.bearing_deg, c_.buoy_range_window_deg);
        }
      }
    }
    const guidance::BuoyCirclingOutput o = circling_.update(ctx.pose.heading_deg, obs);
    if (o.done) {
      phase_ = Phase::kSeekColour;
      seek_since_ns_ = ctx.now_ns;
      set_phase("seek_colour",
                reason_printf("one full turn around the buoy (%.0f deg)", o.progress_deg).view());
      return seek(ctx, out);
    }
    out.steer = true;
    out.desired_heading_deg = o.desired_heading_deg;
    out.thrust_frac = c_.circling_thrust_frac;
    return TaskResult::kRunning;
  }

  TaskResult seek(const TaskContext& ctx, GuidanceRequest& out) {
    if (ctx.camera_new && ctx.camera != nullptr) {
      for (std::size_t i = 0; i < colour_count_; ++i) {
        const bool seen =
            colours_[i] != c_.buoy_colour && largest_of(*ctx.camera, colours_[i]) != nullptr;
        (void)votes_[i].add(ctx.camera->stamp_ns, seen);
      }
    }
    for (std::size_t i = 0; i < colour_count_; ++i) {
      const perception::VoteTally t = votes_[i].tally(ctx.now_ns);
      if (!t.decided) continue;
      ctx.status->identified_colour = colours_[i];
      out.led = led_for(colours_[i]);
      return to_waypoint(
          ctx,
          reason_printf("target colour %s (%zu of %zu frames)",
                        std::string_view(msg::colour_name(colours_[i])).data(), t.hits, t.frames),
          out);
    }
    if (core::ns_to_sec(ctx.now_ns - seek_since_ns_) >= c_.colour_timeout_s) {
      return to_waypoint(ctx, reason_printf("no colour within %.0f s", c_.colour_timeout_s), out);
    }
    out.steer = true;
    out.desired_heading_deg =
        control::true_from_course_deg(c_.exit_course_deg, ctx.course_zero_deg);
    out.thrust_frac = c_.seek_thrust_frac;
    return TaskResult::kRunning;
  }

  TaskResult to_waypoint(const TaskContext& ctx, const ReasonText& why, GuidanceRequest& out) {
    if (!leg_.start(ctx.antenna)) {
      set_reason(reason_printf("no waypoint after the colour"));
      return TaskResult::kDone;
    }
    phase_ = Phase::kToWaypoint;
    set_phase("to_waypoint", why.view());
    out.steer = false;
    return TaskResult::kRunning;
  }

  config::Course2Config c_;
  guidance::BuoyCircling circling_;
  RouteLeg leg_;
  std::array<perception::MarkerVote, 8> votes_;
  std::array<msg::Colour, 8> colours_{};
  std::size_t colour_count_ = 0;
  Phase phase_ = Phase::kCircling;
  core::TimeNs seek_since_ns_ = 0;
};

// ---- docking, KABOAT 2022 -----------------------------------------------------------------

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

// ---- docking, 2026 course 3 ---------------------------------------------------------------

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

std::unique_ptr<Task> make_task(const config::TaskConfig& task, const config::MissionConfig& m,
                                const config::DevicesConfig& devices,
                                const core::LocalFrame& frame) {
  (void)devices;
  switch (task.type) {
    case config::TaskType::kHopping:
      return std::make_unique<HoppingTask>(task, m, frame);
    case config::TaskType::kObstacleCourse:
      return std::make_unique<AvoidanceTask>(task, m, frame, false);
    case config::TaskType::kCourse1:
      return std::make_unique<AvoidanceTask>(task, m, frame, true);
    case config::TaskType::kCourse2:
      return std::make_unique<Course2Task>(task, m, frame);
    case config::TaskType::kDocking:
      if (task.docking_style == config::DockingStyle::kCourse3) {
        return std::make_unique<Course3Task>(task, m);
      }
      return std::make_unique<Docking2022Task>(task, m, frame);
  }
  throw std::invalid_argument("unknown task type");
}

}  // namespace coxswain::mission::detail
