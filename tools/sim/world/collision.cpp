// SPDX-License-Identifier: Apache-2.0
#include "sim/world/collision.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/world/geometry.hpp"

namespace coxswain::sim::world {
namespace {

using core::NavPoint;

struct Interval {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
};

Interval project(const std::array<NavPoint, 5>& pts, NavPoint axis) {
  Interval i;
  for (const NavPoint& p : pts) i.add(dot(p, axis));
  return i;
}

}  // namespace

std::array<core::BodyPoint, 5> hull_outline_body(const config::HullConfig& hull) {
  const double bow = hull.bow_overhang_m;
  const double stern = hull.bow_overhang_m - hull.length_m;
  const double shoulder = bow - 0.25 * hull.length_m;
  const double hb = 0.5 * hull.beam_m;
  return {{{bow, 0.0}, {shoulder, hb}, {stern, hb}, {stern, -hb}, {shoulder, -hb}}};
}

bool outline_segment_penetration(const std::array<NavPoint, 5>& outline, NavPoint a, NavPoint b,
                                 Penetration& out) {
  // Separating axes of two convex shapes: the outline's edge normals and the segment's normal.
  // On each, the shorter of the two pushes that separate; the smallest over all axes wins.
  const NavPoint ab = sub(b, a);
  const double len = std::hypot(ab.north_m, ab.east_m);
  if (len <= 0.0) return false;
  std::array<NavPoint, 6> axes{};
  axes[0] = {-ab.east_m / len, ab.north_m / len};
  for (std::size_t i = 0; i < 5; ++i) {
    const NavPoint e = sub(outline[(i + 1) % 5], outline[i]);
    const double l = std::hypot(e.north_m, e.east_m);
    axes[i + 1] = l > 0.0 ? NavPoint{-e.east_m / l, e.north_m / l} : axes[0];
  }
  double best = std::numeric_limits<double>::infinity();
  NavPoint best_normal{};
  bool segment_axis = false;
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const NavPoint n = axes[k];
    const Interval h = project(outline, n);
    Interval s;
    s.add(dot(a, n));
    s.add(dot(b, n));
    const double push_up = s.hi - h.lo;                    // move the hull along +n
    const double push_down = h.hi - s.lo;                  // move the hull along -n
    if (push_up <= 0.0 || push_down <= 0.0) return false;  // a separating axis
    const double push = std::min(push_up, push_down);
    if (push < best) {
      best = push;
      best_normal = push_up <= push_down ? n : scale(n, -1.0);
      segment_axis = k == 0;
    }
  }
  out.normal = best_normal;
  out.depth_m = best;
  if (segment_axis) {
    // The outline's vertex deepest behind the segment.
    const NavPoint* deepest = &outline[0];
    for (const NavPoint& p : outline) {
      if (dot(p, best_normal) < dot(*deepest, best_normal)) deepest = &p;
    }
    out.point = *deepest;
  } else {
    // The segment's end deepest inside the outline.
    out.point = dot(a, best_normal) > dot(b, best_normal) ? a : b;
  }
  return true;
}

bool outline_circle_penetration(const std::array<NavPoint, 5>& outline, NavPoint center,
                                double radius_m, Penetration& out) {
  NavPoint nearest{};
  double d_min = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < 5; ++i) {
    const NavPoint a = outline[i];
    const NavPoint ab = sub(outline[(i + 1) % 5], a);
    const double len2 = dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(dot(sub(center, a), ab) / len2, 0.0, 1.0) : 0.0;
    const NavPoint q = add(a, scale(ab, t));
    const double d = core::distance_m(q, center);
    if (d < d_min) {
      d_min = d;
      nearest = q;
    }
  }
  const bool inside = point_in_polygon(center, outline);
  if (!inside && d_min >= radius_m) return false;
  NavPoint dir = sub(nearest, center);  // from the centre through the nearest hull point
  const double l = std::hypot(dir.north_m, dir.east_m);
  if (l < 1e-12) return false;  // centre exactly on the outline: next step decides
  dir = scale(dir, 1.0 / l);
  // Centre inside the hull: the hull must move so its nearest edge passes the far side.
  out.normal = dir;
  out.depth_m = inside ? radius_m + l : radius_m - l;
  out.point = add(center, scale(dir, radius_m));
  return true;
}

CollisionResponse::CollisionResponse(const World& world, const config::HullConfig& hull,
                                     CollisionParams params)
    : outline_body_(hull_outline_body(hull)), params_(params) {
  auto add_wall = [this](const Wall& wall) {
    for (std::size_t k = 1; k < wall.points.size(); ++k) {
      segments_.emplace_back(wall.points[k - 1], wall.points[k]);
    }
  };
  for (const Wall& wall : world.walls) add_wall(wall);
  for (const Dock& d : world.docks) {
    for (const Wall& wall : d.walls) add_wall(wall);
  }
  for (const Buoy& b : world.buoys) circles_.emplace_back(b.center, b.radius_m);
  for (const core::BodyPoint& p : outline_body_) {
    reach_m_ = std::max(reach_m_, std::hypot(p.forward_m, p.starboard_m));
  }
  reach2_m2_ = reach_m_ * reach_m_ * (1.0 + 1e-9) + 1e-12;
}

int CollisionResponse::resolve(dynamics::BoatModel& model) const {
  int resolved = 0;
  for (int pass = 0; pass < params_.passes; ++pass) {
    bool any = false;
    // The pose moves only when a contact is resolved: taken again then, not per obstacle.
    core::NavPose pose = model.truth().pose;
    for (std::size_t i = 0; i < segments_.size() + circles_.size(); ++i) {
      Penetration p;
      bool hit = false;
      if (i < segments_.size()) {
        const auto& [a, b] = segments_[i];
        // Squared first (no square root for the far ones), a margin over the exact test's edge.
        if (point_segment_distance2(pose.position, a, b) > reach2_m2_) continue;
        if (point_segment_distance(pose.position, a, b) > reach_m_) continue;
        std::array<NavPoint, 5> outline{};
        for (std::size_t k = 0; k < 5; ++k) outline[k] = core::body_to_nav(pose, outline_body_[k]);
        hit = outline_segment_penetration(outline, a, b, p);
      } else {
        const auto& [c, r] = circles_[i - segments_.size()];
        if (core::distance_m(pose.position, c) > reach_m_ + r) continue;
        std::array<NavPoint, 5> outline{};
        for (std::size_t k = 0; k < 5; ++k) outline[k] = core::body_to_nav(pose, outline_body_[k]);
        hit = outline_circle_penetration(outline, c, r, p);
      }
      if (!hit) continue;
      (void)model.resolve_contact(p.normal, p.point, p.depth_m, params_.restitution);
      pose = model.truth().pose;
      any = true;
      ++resolved;
    }
    if (!any) break;
  }
  return resolved;
}

}  // namespace coxswain::sim::world
