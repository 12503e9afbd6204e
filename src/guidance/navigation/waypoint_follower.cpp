// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/waypoint_follower.hpp"

#include <algorithm>
#include <cmath>

#include "coxswain/core/angles.hpp"

namespace coxswain::guidance {

std::optional<std::string> WaypointFollowerParams::validate() const {
  if (!(arrival_radius_m > 0.0)) return "waypoints: arrival_radius_m must be > 0";
  if (!(slip_radius_m >= arrival_radius_m)) {
    return "waypoints: slip_radius_m must be >= arrival_radius_m";
  }
  if (!(arrival_confidence >= 0.0 && arrival_confidence < 1.0)) {
    return "waypoints: arrival_confidence must be in [0, 1)";
  }
  if (arrival_confidence > 0.0 && !(arrival_confidence >= 0.5)) {
    return "waypoints: arrival_confidence must be 0 or >= 0.5";
  }
  if (!(rule_radius_m > 0.0)) return "waypoints: rule_radius_m must be > 0";
  if (auto e = line.validate()) return e;
  return std::nullopt;
}

WaypointFollower::WaypointFollower(WaypointFollowerParams p)
    : p_(p),
      k_sigma_(p.arrival_confidence > 0.0 ? normal_quantile(p.arrival_confidence) : 0.0),
      line_(p.line) {}

bool WaypointFollower::set_route(std::span<const core::NavPoint> points) {
  if (points.empty() || points.size() > kMaxWaypoints) return false;
  std::copy(points.begin(), points.end(), route_.begin());
  count_ = points.size();
  index_ = 0;
  has_leg_start_ = false;
  last_ns_ = core::kNeverNs;
  arrived_ = 0;
  missed_ = 0;
  line_.reset();
  return true;
}

void WaypointFollower::advance(core::NavPoint position) {
  // The next leg starts at the point just visited (the planned leg), not where the boat happens
  // to be, so a boat that arrived off-centre still converges to the organisers' straight line.
  leg_start_ = index_ < count_ ? route_[index_] : position;
  ++index_;
  line_.reset();
}

WaypointGuidance WaypointFollower::update(core::NavPoint position, core::TimeNs stamp_ns,
                                          const PositionCovariance* covariance) {
  WaypointGuidance g;
  if (count_ == 0 || finished()) {
    g.finished = true;
    g.index = index_;
    return g;
  }
  if (!has_leg_start_) {
    leg_start_ = position;
    has_leg_start_ = true;
  }
  double dt_s = 0.0;
  if (last_ns_ != core::kNeverNs && stamp_ns > last_ns_)
    dt_s = core::ns_to_sec(stamp_ns - last_ns_);
  last_ns_ = stamp_ns;

  // Arrival / slip check on the current point (at most one advance per step).
  const core::NavPoint target = route_[index_];
  const double dist = core::distance_m(position, target);
  const LineFollowOutput geo = line_.geometry(leg_start_, target, position);
  const bool passed_abeam = geo.leg_length_m > 1e-6 && geo.along_track_m >= geo.leg_length_m;
  const bool by_confidence = covariance != nullptr && p_.arrival_confidence > 0.0;
  // By confidence, the slip circle is judged the same way: confidently inside it.
  const double margin_m =
      by_confidence ? k_sigma_ * covariance->sigma_toward_m(position, target) : 0.0;
  const bool arrived =
      by_confidence ? dist + margin_m <= p_.rule_radius_m : dist <= p_.arrival_radius_m;
  if (arrived) {
    g.event = WaypointEvent::kArrived;
    ++arrived_;
  } else if (passed_abeam && dist + margin_m <= p_.slip_radius_m) {
    g.event = WaypointEvent::kMissed;
    ++missed_;
  }
  if (g.event != WaypointEvent::kNone) {
    g.event_index = index_;
    advance(position);
    dt_s = 0.0;
    if (finished()) {
      g.finished = true;
      g.index = index_;
      g.target = target;
      return g;
    }
  }

  g.index = index_;
  g.target = route_[index_];
  g.distance_to_go_m = core::distance_m(position, g.target);
  g.reach_m = by_confidence
                  ? std::max(0.0, p_.rule_radius_m -
                                      k_sigma_ * covariance->sigma_toward_m(position, g.target))
                  : p_.arrival_radius_m;
  const LineFollowOutput lf = line_.update(leg_start_, g.target, position, dt_s);
  g.cross_track_m = lf.cross_track_m;
  g.leg_progress = lf.progress;
  const bool beyond = lf.leg_length_m > 1e-6 && lf.along_track_m >= lf.leg_length_m;
  // Beyond the point but outside the slip radius: turn back for it by bearing.
  if (p_.line_following && !beyond) {
    g.desired_heading_deg = lf.desired_heading_deg;
  } else {
    g.desired_heading_deg = core::bearing_deg(position, g.target);
  }
  return g;
}

}  // namespace coxswain::guidance
