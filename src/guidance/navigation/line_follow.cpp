// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/line_follow.hpp"

#include <algorithm>
#include <cmath>

#include "coxswain/core/angles.hpp"

namespace coxswain::guidance {

std::optional<std::string> LineFollowParams::validate() const {
  if (!(lookahead_m > 0.0)) return "line: lookahead_m must be > 0";
  if (!(integral_gain >= 0.0)) return "line: integral_gain must be >= 0";
  if (!(max_integral_m >= 0.0)) return "line: max_integral_m must be >= 0";
  if (!(max_dt_s > 0.0)) return "line: max_dt_s must be > 0";
  if (!(integrate_within_m > 0.0)) return "line: integrate_within_m must be > 0";
  return std::nullopt;
}

LineFollowOutput LineFollower::geometry(core::NavPoint from, core::NavPoint to,
                                        core::NavPoint position) const {
  LineFollowOutput out;
  const double dn = to.north_m - from.north_m;
  const double de = to.east_m - from.east_m;
  out.leg_length_m = std::hypot(dn, de);
  if (out.leg_length_m < 1e-6) {  // degenerate leg: head for the point
    out.path_bearing_deg = core::bearing_deg(position, to);
    out.desired_heading_deg = out.path_bearing_deg;
    out.progress = 1.0;
    return out;
  }
  const double un = dn / out.leg_length_m;
  const double ue = de / out.leg_length_m;
  const double pn = position.north_m - from.north_m;
  const double pe = position.east_m - from.east_m;
  out.along_track_m = pn * un + pe * ue;
  // Starboard normal of direction (un, ue) in the (north, east) frame is (-ue, un).
  out.cross_track_m = -pn * ue + pe * un;
  out.path_bearing_deg = core::bearing_deg(from, to);
  out.progress = std::clamp(out.along_track_m / out.leg_length_m, 0.0, 1.0);
  out.desired_heading_deg = core::wrap_deg(
      out.path_bearing_deg - core::rad_to_deg(std::atan2(out.cross_track_m, p_.lookahead_m)));
  return out;
}

LineFollowOutput LineFollower::update(core::NavPoint from, core::NavPoint to,
                                      core::NavPoint position, double dt_s) {
  LineFollowOutput out = geometry(from, to, position);
  if (out.leg_length_m < 1e-6) return out;
  const double e = out.cross_track_m;
  const double delta = p_.lookahead_m;
  if (std::abs(e) > p_.integrate_within_m) y_int_m_ = 0.0;
  if (p_.integral_gain > 0.0 && dt_s > 0.0 && dt_s <= p_.max_dt_s) {
    // ILOS: y_int' = Delta e / (Delta^2 + (e + sigma y_int)^2), bounded for anti-windup.
    const double shifted = e + p_.integral_gain * y_int_m_;
    y_int_m_ += dt_s * delta * e / (delta * delta + shifted * shifted);
    const double lim = p_.max_integral_m / p_.integral_gain;
    y_int_m_ = std::clamp(y_int_m_, -lim, lim);
  }
  const double shifted = e + p_.integral_gain * y_int_m_;
  out.desired_heading_deg =
      core::wrap_deg(out.path_bearing_deg - core::rad_to_deg(std::atan2(shifted, delta)));
  return out;
}

}  // namespace coxswain::guidance
