// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/pure_pursuit.hpp"

#include <algorithm>
#include <cmath>

#include "coxswain/core/angles.hpp"

namespace coxswain::guidance {
namespace {

struct Projection {
  double t = 0.0;       // along the segment, [0, 1]
  double dist_m = 0.0;  // from the point to the segment
};

Projection project(core::NavPoint p, core::NavPoint a, core::NavPoint b) {
  const double dn = b.north_m - a.north_m;
  const double de = b.east_m - a.east_m;
  const double len2 = dn * dn + de * de;
  double t = 0.0;
  if (len2 > 1e-12) {
    t = std::clamp(((p.north_m - a.north_m) * dn + (p.east_m - a.east_m) * de) / len2, 0.0, 1.0);
  }
  return {t, core::distance_m(p, {a.north_m + t * dn, a.east_m + t * de})};
}

}  // namespace

std::optional<std::string> PurePursuitParams::validate() const {
  if (!std::isfinite(lookahead_m) || !(lookahead_m > 0.0)) return "lookahead_m must be > 0";
  if (!std::isfinite(arrive_radius_m) || arrive_radius_m < 0.0) return "arrive_radius_m >= 0";
  return {};
}

PursuitCommand PurePursuit::update(std::span<const core::NavPoint> path,
                                   const core::NavPose& pose) {
  PursuitCommand out;
  if (path.empty()) return out;
  out.valid = true;
  const core::NavPoint p = pose.position;
  const core::NavPoint last = path.back();
  out.at_end = core::distance_m(p, last) <= params_.arrive_radius_m;

  core::NavPoint target = last;
  if (path.size() >= 2) {
    const std::size_t segs = path.size() - 1;
    progress_ = std::min(progress_, segs - 1);
    // The closest segment from where we are onward (first of equals).
    std::size_t best = progress_;
    Projection best_proj = project(p, path[best], path[best + 1]);
    for (std::size_t i = progress_ + 1; i < segs; ++i) {
      const Projection pr = project(p, path[i], path[i + 1]);
      if (pr.dist_m < best_proj.dist_m) {
        best = i;
        best_proj = pr;
      }
    }
    progress_ = best;
    out.segment = best;

    // The first point past the projection where the path leaves the look-ahead circle.
    const double ld = params_.lookahead_m;
    bool found = false;
    for (std::size_t i = best; i < segs && !found; ++i) {
      const core::NavPoint a = path[i];
      const core::NavPoint b = path[i + 1];
      const double dn = b.north_m - a.north_m;
      const double de = b.east_m - a.east_m;
      const double fn = a.north_m - p.north_m;
      const double fe = a.east_m - p.east_m;
      const double qa = dn * dn + de * de;
      if (qa < 1e-12) continue;
      const double qb = 2.0 * (fn * dn + fe * de);
      const double qc = fn * fn + fe * fe - ld * ld;
      const double disc = qb * qb - 4.0 * qa * qc;
      if (disc < 0.0) continue;
      const double t = (-qb + std::sqrt(disc)) / (2.0 * qa);  // the exiting intersection
      const double t_min = i == best ? best_proj.t : 0.0;
      if (t >= t_min && t <= 1.0) {
        target = {a.north_m + t * dn, a.east_m + t * de};
        found = true;
      }
    }
    if (!found && best_proj.dist_m > ld &&
        core::distance_m(p, last) > ld) {  // far off the path: head back to it first
      const core::NavPoint a = path[best];
      const core::NavPoint b = path[best + 1];
      target = {a.north_m + best_proj.t * (b.north_m - a.north_m),
                a.east_m + best_proj.t * (b.east_m - a.east_m)};
    }
  }

  out.target = target;
  const double dist = core::distance_m(p, target);
  if (dist < 1e-9) {
    out.heading_deg = core::wrap_deg(pose.heading_deg);
    return out;
  }
  out.heading_deg = core::bearing_deg(p, target);
  out.alpha_deg = core::angle_diff_deg(out.heading_deg, pose.heading_deg);
  out.curvature_per_m = 2.0 * std::sin(core::deg_to_rad(out.alpha_deg)) / dist;
  return out;
}

}  // namespace coxswain::guidance
