// SPDX-License-Identifier: Apache-2.0
#include "sim/scoring/scorer.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "coxswain/core/angles.hpp"
#include "coxswain/core/time.hpp"
#include "sim/world/collision.hpp"
#include "sim/world/geometry.hpp"

namespace coxswain::sim::scoring {
namespace {

using core::NavPoint;
using world::add;
using world::cross;
using world::scale;
using world::sub;

double collision_penalty_s(Rules rules) {
  switch (rules) {
    case Rules::k2022Hopping:
      return 30.0;
    case Rules::k2022Obstacle:
    case Rules::k2022Docking:
      return 60.0;
    case Rules::k2026:
      return 10.0;
  }
  return 0.0;
}

bool colour_matches(msg::LedColour led, msg::Colour colour) {
  switch (led) {
    case msg::LedColour::kRed:
      return colour == msg::Colour::kRed;
    case msg::LedColour::kGreen:
      return colour == msg::Colour::kGreen;
    case msg::LedColour::kBlue:
      return colour == msg::Colour::kBlue;
    case msg::LedColour::kYellow:
      return colour == msg::Colour::kYellow;
    case msg::LedColour::kPurple:
      return colour == msg::Colour::kPurple;
    case msg::LedColour::kWhite:
      return colour == msg::Colour::kWhite;
    case msg::LedColour::kOff:
      return false;
  }
  return false;
}

// Distance from a convex-or-not outline to a segment (0 when they touch or the segment is inside).
double outline_segment_distance(const std::array<NavPoint, 5>& hull, NavPoint a, NavPoint b) {
  if (world::point_in_polygon(a, hull) || world::point_in_polygon(b, hull)) return 0.0;
  double d = 1e300;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    d = std::min(d, world::segment_segment_distance(hull[i], hull[(i + 1) % hull.size()], a, b));
  }
  return d;
}

double outline_circle_distance(const std::array<NavPoint, 5>& hull, NavPoint c, double r) {
  if (world::point_in_polygon(c, hull)) return -r;
  double d = 1e300;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    d = std::min(d, world::point_segment_distance(c, hull[i], hull[(i + 1) % hull.size()]));
  }
  return d - r;
}

}  // namespace

Rules rules_for(world::CourseKind kind) {
  switch (kind) {
    case world::CourseKind::kHopping:
      return Rules::k2022Hopping;
    case world::CourseKind::kObstacle:
      return Rules::k2022Obstacle;
    case world::CourseKind::kDocking:
      return Rules::k2022Docking;
    case world::CourseKind::kKaboat2026:
      return Rules::k2026;
  }
  return Rules::k2022Hopping;
}

std::string_view rules_name(Rules rules) {
  switch (rules) {
    case Rules::k2022Hopping:
      return "kaboat2022-hopping";
    case Rules::k2022Obstacle:
      return "kaboat2022-obstacle";
    case Rules::k2022Docking:
      return "kaboat2022-docking";
    case Rules::k2026:
      return "kaboat2026";
  }
  return "unknown";
}

std::array<core::BodyPoint, 5> hull_outline_body(const config::HullConfig& hull) {
  return world::hull_outline_body(hull);
}

std::array<NavPoint, 5> hull_outline(const config::HullConfig& hull, const core::NavPose& pose) {
  const auto body = hull_outline_body(hull);
  std::array<NavPoint, 5> out{};
  for (std::size_t i = 0; i < body.size(); ++i) out[i] = core::body_to_nav(pose, body[i]);
  return out;
}

Scorer::Scorer(const world::World& world, const config::HullConfig& hull, ScoringOptions options)
    : world_(&world), hull_(hull), options_(options) {
  result_.course = world.name;
  result_.rules = rules_for(world.kind);
  for (std::size_t i = 0; i < world.walls.size(); ++i) {
    Obstacle o{
        "wall " + std::to_string(i), ObstacleKind::kWall, {}, {}, 0.0, false, {}, 0.0, {}, 0.0};
    const auto& pts = world.walls[i].points;
    for (std::size_t k = 1; k < pts.size(); ++k) o.segments.emplace_back(pts[k - 1], pts[k]);
    obstacles_.push_back(std::move(o));
  }
  for (std::size_t i = 0; i < world.buoys.size(); ++i) {
    const auto& b = world.buoys[i];
    obstacles_.push_back(
        {"buoy " + std::to_string(i) + " (" + std::string(msg::colour_name(b.colour)) + ")",
         ObstacleKind::kBuoy,
         {},
         b.center,
         b.radius_m,
         false,
         {},
         0.0,
         {},
         0.0});
  }
  for (const auto& d : world.docks) {
    Obstacle o{"dock " + d.name, ObstacleKind::kDock, {}, {}, 0.0, false, {}, 0.0, {}, 0.0};
    for (const auto& w : d.walls) {
      for (std::size_t k = 1; k < w.points.size(); ++k) {
        o.segments.emplace_back(w.points[k - 1], w.points[k]);
      }
    }
    obstacles_.push_back(std::move(o));
  }
  // Area samples: an 11 x 5 grid over the hull's bounding box, kept where inside the outline.
  const auto outline = hull_outline_body(hull);
  std::vector<NavPoint> poly;
  poly.reserve(outline.size());
  for (const auto& p : outline) poly.push_back({p.forward_m, p.starboard_m});
  for (Obstacle& o : obstacles_) {
    if (o.segments.empty()) continue;
    NavPoint lo = o.segments.front().first;
    NavPoint hi = lo;
    for (const auto& s : o.segments) {
      for (const NavPoint& p : {s.first, s.second}) {
        lo = {std::min(lo.north_m, p.north_m), std::min(lo.east_m, p.east_m)};
        hi = {std::max(hi.north_m, p.north_m), std::max(hi.east_m, p.east_m)};
      }
    }
    o.bound_center = {0.5 * (lo.north_m + hi.north_m), 0.5 * (lo.east_m + hi.east_m)};
    for (const auto& s : o.segments) {
      for (const NavPoint& p : {s.first, s.second}) {
        o.bound_radius_m = std::max(o.bound_radius_m, core::distance_m(o.bound_center, p));
      }
    }
  }
  for (const core::BodyPoint& p : hull_outline_body(hull)) {
    outline_radius_m_ = std::max(outline_radius_m_, std::hypot(p.forward_m, p.starboard_m));
  }
  const double bow = hull.bow_overhang_m;
  for (int i = 0; i < 21; ++i) {
    for (int j = 0; j < 9; ++j) {
      const core::BodyPoint p{bow - hull.length_m * (i + 0.5) / 21.0,
                              hull.beam_m * ((j + 0.5) / 9.0 - 0.5)};
      if (world::point_in_polygon({p.forward_m, p.starboard_m}, poly)) samples_.push_back(p);
    }
  }
  for (const core::BodyPoint& p : samples_) {
    samples_radius_m_ = std::max(samples_radius_m_, std::hypot(p.forward_m, p.starboard_m));
  }
  for (std::size_t i = 0; i < world.buoys.size() && result_.rules == Rules::k2026; ++i) {
    if (world.buoys[i].colour == msg::Colour::kPurple) {
      purple_ = static_cast<int>(i);
      break;
    }
  }
  if (world.regions.empty()) {
    result_.courses.push_back({world.name, 0.0, -1.0, 0.0, false, 0, 0.0});
  } else {
    for (const auto& r : world.regions) {
      result_.courses.push_back({r.name, -1.0, -1.0, r.time_limit_s, false, 0, 0.0});
    }
    result_.courses[0].start_s = 0.0;
  }
}

double Scorer::clearance_m(std::size_t obstacle, const core::NavPose& pose) const {
  const auto outline = hull_outline(hull_, pose);
  const Obstacle& o = obstacles_[obstacle];
  if (o.kind == ObstacleKind::kBuoy) return outline_circle_distance(outline, o.center, o.radius_m);
  double d = 1e300;
  for (const auto& s : o.segments)
    d = std::min(d, outline_segment_distance(outline, s.first, s.second));
  return d;
}

double Scorer::fraction_inside(const core::NavPose& pose, const auto& inside) const {
  // body_to_nav() for each sample with the heading's cosine and sine taken once (the same
  // arithmetic, so the same points).
  const double c = std::cos(core::deg_to_rad(pose.heading_deg));
  const double sn = std::sin(core::deg_to_rad(pose.heading_deg));
  std::size_t count = 0;
  for (const auto& s : samples_) {
    const NavPoint p{pose.position.north_m + (c * s.forward_m - sn * s.starboard_m),
                     pose.position.east_m + (sn * s.forward_m + c * s.starboard_m)};
    if (inside(p)) ++count;
  }
  return samples_.empty() ? 0.0 : static_cast<double>(count) / static_cast<double>(samples_.size());
}

void Scorer::finish_course(std::size_t index, double t_s) {
  CourseResult& c = result_.courses[index];
  if (c.end_s < 0.0) c.end_s = t_s;
}

std::string Scorer::pending_goal() const {
  const world::World& w = *world_;
  switch (result_.rules) {
    case Rules::k2022Hopping:
      if (next_waypoint_ < w.waypoints.size())
        return "waypoint " + w.waypoints[next_waypoint_].name;
      return w.waypoints.empty() ? "a waypoint" : "";
    case Rules::k2022Obstacle:
      if (next_gate_ < w.gates.size()) return "gate " + w.gates[next_gate_].name;
      return w.gates.empty() ? "a gate" : "";
    case Rules::k2022Docking:
      return result_.docked ? "" : "the target dock";
    case Rules::k2026:
      if (!result_.docked) return "the dock";
      return result_.circled ? "" : "the circle round the purple buoy";
  }
  return "";
}

void Scorer::conclude(double t_s) {
  done_ = true;
  result_.pending = pending_goal();
  result_.elapsed_s = t_s;
  for (std::size_t i = 0; i < result_.courses.size(); ++i) {
    if (result_.courses[i].start_s >= 0.0) finish_course(i, t_s);
  }
  result_.score_s = result_.elapsed_s + result_.penalty_s;
  if (result_.rules == Rules::k2026) {
    result_.bonus_points = (result_.recognised ? 30.0 : 0.0) + (result_.docked ? 50.0 : 0.0);
  }
}

void Scorer::update(const dynamics::TruthState& truth, msg::LedColour led) {
  if (done_) return;
  const double t = core::ns_to_sec(truth.stamp_ns);
  const world::World& w = *world_;
  const NavPoint cg = truth.cg;

  // Course regions (2026): the boat moves on to course k+1 when it first enters its region.
  if (w.regions.size() > 1) {
    for (std::size_t k = course_ + 1; k < w.regions.size(); ++k) {
      if (world::point_in_polygon(cg, w.regions[k].polygon)) {
        for (std::size_t j = course_; j < k; ++j) finish_course(j, t);
        course_ = k;
        result_.courses[k].start_s = t;
        break;
      }
    }
  }

  // Collisions.
  const auto outline = hull_outline(hull_, truth.pose);
  // The outline lies within outline_radius_m_ of the body origin: an obstacle not in contact
  // whose distance from the origin exceeds that by more than the touch distance cannot be
  // touched now, and then nothing below depends on its exact distance.
  const NavPoint origin = truth.pose.position;
  const double far_m = outline_radius_m_ + options_.touch_m + 1e-6;
  const auto far_from = [&](const Obstacle& o) {
    if (o.kind == ObstacleKind::kBuoy)
      return core::distance_m(origin, o.center) - o.radius_m > far_m;
    if (core::distance_m(origin, o.bound_center) - o.bound_radius_m > far_m) return true;
    for (const auto& s : o.segments) {
      if (world::point_segment_distance(origin, s.first, s.second) <= far_m) return false;
    }
    return true;
  };
  for (Obstacle& o : obstacles_) {
    if (!o.in_contact && far_from(o)) continue;
    double d = 0.0;
    if (o.kind == ObstacleKind::kBuoy) {
      d = outline_circle_distance(outline, o.center, o.radius_m);
    } else {
      d = 1e300;
      for (const auto& s : o.segments) {
        d = std::min(d, outline_segment_distance(outline, s.first, s.second));
      }
    }
    if (!o.in_contact && d <= options_.touch_m) {
      o.in_contact = true;
      o.anchor = cg;
      o.anchor_s = t;
      // Hitting the dock is not penalised (2022 docking rule, kept for 2026 course 3).
      const bool penalised = o.kind != ObstacleKind::kDock;
      NavPoint nearest = o.center;
      if (o.kind != ObstacleKind::kBuoy) {
        double best = 1e300;
        for (const auto& sgm : o.segments) {
          const NavPoint q = world::nearest_on_segment(cg, sgm.first, sgm.second);
          const double dq = core::distance_m(cg, q);
          if (dq < best) {
            best = dq;
            nearest = q;
          }
        }
      }
      const double bearing_body_deg =
          core::angle_diff_deg(core::bearing_deg(cg, nearest), truth.pose.heading_deg);
      result_.contacts.push_back({t, cg, o.name, o.kind, course_, penalised, truth.pose.heading_deg,
                                  truth.u_mps, bearing_body_deg});
      if (penalised) {
        const double p = collision_penalty_s(result_.rules);
        ++result_.collisions;
        result_.penalty_s += p;
        ++result_.courses[course_].collisions;
        result_.courses[course_].penalty_s += p;
      }
    } else if (o.in_contact && d > options_.release_m) {
      o.in_contact = false;
    } else if (o.in_contact && core::distance_m(cg, o.anchor) > options_.pinned_radius_m) {
      o.anchor = cg;  // sliding along it: still getting somewhere
      o.anchor_s = t;
    }
  }

  // Waypoints: half the hull inside the circle.
  const bool ordered = result_.rules != Rules::k2022Docking;
  for (std::size_t i = 0; i < w.waypoints.size(); ++i) {
    if (ordered && i != next_waypoint_) continue;
    const auto& wp = w.waypoints[i];
    const bool already = std::any_of(result_.waypoints.begin(), result_.waypoints.end(),
                                     [&](const Passage& p) { return p.name == wp.name; });
    if (already) continue;
    // No sample lies within samples_radius_m_ of the body origin: a circle farther than that
    // holds none of them.
    if (core::distance_m(truth.pose.position, wp.position) >
        wp.radius_m + samples_radius_m_ + 1e-6) {
      continue;
    }
    const double f = fraction_inside(
        truth.pose, [&](NavPoint p) { return core::distance_m(p, wp.position) <= wp.radius_m; });
    if (f >= 0.5) {
      result_.waypoints.push_back({wp.name, t, true});
      if (ordered) ++next_waypoint_;
    }
  }

  // Gates: the CG's motion this step crosses the gate segment.
  if (have_prev_ && next_gate_ < w.gates.size()) {
    const auto& g = w.gates[next_gate_];
    if (world::segments_intersect(prev_cg_, cg, g.left, g.right)) {
      // Left -> right seen from a boat moving along `motion`: (right - left) x motion < 0.
      const bool right_way = cross(sub(g.right, g.left), sub(cg, prev_cg_)) < 0.0;
      result_.gates.push_back({g.name, t, right_way});
      if (right_way) ++next_gate_;
    }
  }
  prev_cg_ = cg;
  have_prev_ = true;

  // Docks: half the hull inside the slip.
  for (const auto& d : w.docks) {
    const bool already = std::any_of(result_.docks.begin(), result_.docks.end(),
                                     [&](const Passage& p) { return p.name == d.name; });
    if (already) continue;
    // The slip lies within its half diagonal of its centre: farther than that plus the samples'
    // reach, no sample is in it.
    const NavPoint fwd = world::heading_unit(d.entry_heading_deg);
    const NavPoint right = world::heading_unit(d.entry_heading_deg + 90.0);
    const NavPoint slip_center{d.entrance.north_m + 0.5 * d.depth_m * fwd.north_m,
                               d.entrance.east_m + 0.5 * d.depth_m * fwd.east_m};
    if (core::distance_m(truth.pose.position, slip_center) >
        0.5 * std::hypot(d.depth_m, d.width_m) + samples_radius_m_ + 1e-6) {
      continue;
    }
    const double f = fraction_inside(truth.pose, [&](NavPoint p) {
      const NavPoint rel = sub(p, d.entrance);
      const double along = world::dot(rel, fwd);
      const double across = world::dot(rel, right);
      return along >= 0.0 && along <= d.depth_m && std::abs(across) <= 0.5 * d.width_m;
    });
    if (f >= 0.5) {
      const bool target = result_.rules == Rules::k2026 ||
                          (d.marker.colour == w.target_colour && d.marker.shape == w.target_shape);
      result_.docks.push_back({d.name, t, target});
      if (target) result_.docked = true;
    }
  }

  // 2026 buoy circling: sum the turns of the bearing from the buoy to the boat.
  if (purple_ >= 0) {
    const double bearing = core::bearing_deg(w.buoys[static_cast<std::size_t>(purple_)].center, cg);
    if (have_bearing_) {
      result_.buoy_circled_deg += core::angle_diff_deg(bearing, purple_bearing_deg_);
      if (std::abs(result_.buoy_circled_deg) >= 360.0) result_.circled = true;
    }
    purple_bearing_deg_ = bearing;
    have_bearing_ = true;
  }

  // 2026 object recognition: the first colour the LED shows decides.
  if (result_.rules == Rules::k2026 && !led_decided_ && led != msg::LedColour::kOff) {
    led_decided_ = true;
    result_.recognised = colour_matches(led, w.target_colour);
  }

  // Completion.
  bool complete = false;
  switch (result_.rules) {
    case Rules::k2022Hopping:
      complete = !w.waypoints.empty() && next_waypoint_ == w.waypoints.size();
      break;
    case Rules::k2022Obstacle:
      complete = !w.gates.empty() && next_gate_ == w.gates.size();
      break;
    case Rules::k2022Docking:
    case Rules::k2026:
      complete = result_.docked;
      break;
  }
  if (complete) {
    result_.completed = true;
    conclude(t);
    return;
  }
  if (options_.pinned_s > 0.0) {
    for (const Obstacle& o : obstacles_) {
      if (o.in_contact && t - o.anchor_s >= options_.pinned_s) {
        result_.pinned = true;
        result_.pinned_to = o.name;
        result_.pinned_since_s = o.anchor_s;
        conclude(t);
        return;
      }
    }
  }
  // Time limit of the current course (or of the whole single course).
  CourseResult& c = result_.courses[course_];
  if (c.time_limit_s > 0.0 && c.start_s >= 0.0 && t - c.start_s >= c.time_limit_s) {
    c.timed_out = true;
    result_.timed_out = true;
    conclude(t);
  }
}

std::string failure_reason(const ScoreResult& r, bool mission_finished) {
  const bool rules_met = r.completed && (r.rules != Rules::k2026 || r.circled);
  if (rules_met && !r.timed_out) return "";
  std::ostringstream o;
  o.precision(1);
  o << std::fixed;
  if (r.pinned) {
    o << "pinned against " << r.pinned_to << " from " << r.pinned_since_s << " s to " << r.elapsed_s
      << " s";
  } else if (r.timed_out) {
    std::string course;
    for (const auto& c : r.courses) {
      if (c.timed_out) course = c.name;
    }
    o << "out of time in " << course;
  } else if (r.rules == Rules::k2022Docking && !r.docked && !r.docks.empty() &&
             !r.docks.back().ok) {
    o << "entered dock " << r.docks.back().name << ", not the target";
  } else if (mission_finished && !r.pending.empty()) {
    o << "the mission finished but the judge, on the true track, never saw " << r.pending
      << " passed";
  } else if (!r.pending.empty()) {
    o << "the run ended before " << r.pending;
  } else {
    o << "not completed";
  }
  if (!r.pending.empty() && (r.pinned || r.timed_out)) o << " (next: " << r.pending << ")";
  return o.str();
}

nlohmann::json to_json(const ScoreResult& r) {
  using nlohmann::json;
  json j;
  j["course"] = r.course;
  j["rules"] = std::string(rules_name(r.rules));
  j["elapsed_s"] = r.elapsed_s;
  j["completed"] = r.completed;
  j["timed_out"] = r.timed_out;
  j["collisions"] = r.collisions;
  j["penalty_s"] = r.penalty_s;
  j["score_s"] = r.score_s;
  j["recognised"] = r.recognised;
  j["circled"] = r.circled;
  j["buoy_circled_deg"] = r.buoy_circled_deg;
  j["docked"] = r.docked;
  j["bonus_points"] = r.bonus_points;
  j["pinned"] = r.pinned;
  if (r.pinned) {
    j["pinned_to"] = r.pinned_to;
    j["pinned_since_s"] = r.pinned_since_s;
  }
  j["pending"] = r.pending;
  auto kind_name = [](ObstacleKind k) {
    return k == ObstacleKind::kWall ? "wall" : k == ObstacleKind::kBuoy ? "buoy" : "dock";
  };
  j["contacts"] = json::array();
  for (const auto& c : r.contacts) {
    j["contacts"].push_back({{"t_s", c.t_s},
                             {"north_m", c.at.north_m},
                             {"east_m", c.at.east_m},
                             {"obstacle", c.obstacle},
                             {"kind", kind_name(c.kind)},
                             {"course", c.course},
                             {"penalised", c.penalised},
                             {"heading_deg", c.heading_deg},
                             {"surge_mps", c.surge_mps},
                             {"bearing_body_deg", c.bearing_body_deg}});
  }
  auto passages = [](const std::vector<Passage>& v) {
    json a = json::array();
    for (const auto& p : v) a.push_back({{"name", p.name}, {"t_s", p.t_s}, {"ok", p.ok}});
    return a;
  };
  j["waypoints"] = passages(r.waypoints);
  j["gates"] = passages(r.gates);
  j["docks"] = passages(r.docks);
  j["courses"] = json::array();
  for (const auto& c : r.courses) {
    j["courses"].push_back({{"name", c.name},
                            {"start_s", c.start_s},
                            {"end_s", c.end_s},
                            {"time_limit_s", c.time_limit_s},
                            {"timed_out", c.timed_out},
                            {"collisions", c.collisions},
                            {"penalty_s", c.penalty_s}});
  }
  return j;
}

}  // namespace coxswain::sim::scoring
