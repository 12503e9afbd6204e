// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/docking_approach.hpp"

#include <algorithm>
#include <cmath>

#include "coxswain/core/angles.hpp"

namespace coxswain::guidance {

std::optional<std::string> DockingApproachParams::validate() const {
  if (!(lookahead_m > 0.0)) return "docking: lookahead_m must be > 0";
  if (!(stop_range_m > 0.0)) return "docking: stop_range_m must be > 0";
  if (!(marker_gain > 0.0)) return "docking: marker_gain must be > 0";
  if (!(max_marker_turn_deg > 0.0)) return "docking: max_marker_turn_deg must be > 0";
  if (!(ahead_half_angle_deg > 0.0 && ahead_half_angle_deg <= 90.0)) {
    return "docking: ahead_half_angle_deg must be in (0, 90]";
  }
  return std::nullopt;
}

std::optional<double> min_range_ahead_m(const perception::RangeProfile& profile,
                                        double half_angle_deg) {
  const std::size_t bins = std::min<std::size_t>(profile.bin_count, profile.closest_range_m.size());
  const double w = static_cast<double>(profile.bin_width_deg);
  if (!(w > 0.0)) return std::nullopt;
  std::optional<double> best;
  for (std::size_t i = 0; i < bins; ++i) {
    const double centre_deg = -180.0 + (static_cast<double>(i) + 0.5) * w;
    if (std::abs(centre_deg) > half_angle_deg + 0.5 * w) continue;
    const float r = profile.closest_range_m[i];
    if (!(r > 0.0F) || r >= perception::RangeProfile::kNoReturn) continue;
    const double rd = static_cast<double>(r);
    if (!best || rd < *best) best = rd;
  }
  return best;
}

bool DockingApproach::set_ray(core::NavPoint decision_point, core::NavPoint dock_point) {
  if (core::distance_m(decision_point, dock_point) < 0.1) return false;
  origin_ = decision_point;
  ray_bearing_deg_ = core::bearing_deg(decision_point, dock_point);
  has_ray_ = true;
  stopped_ = false;
  return true;
}

bool DockingApproach::check_stop(std::optional<double> range_ahead_m) {
  if (range_ahead_m && std::isfinite(*range_ahead_m) && *range_ahead_m < p_.stop_range_m) {
    stopped_ = true;
  }
  return stopped_;
}

DockingCommand DockingApproach::pursue(const core::NavPose& pose,
                                       std::optional<double> range_ahead_m) {
  DockingCommand c;
  c.stop = check_stop(range_ahead_m);
  c.desired_heading_deg = pose.heading_deg;
  if (!has_ray_) return c;
  const double a = core::deg_to_rad(ray_bearing_deg_);
  const double un = std::cos(a);
  const double ue = std::sin(a);
  const double pn = pose.position.north_m - origin_.north_m;
  const double pe = pose.position.east_m - origin_.east_m;
  c.along_ray_m = pn * un + pe * ue;
  c.cross_ray_m = -pn * ue + pe * un;
  // A ray, not a line: a boat still behind the decision point aims at the first metres of it.
  const double s = std::max(c.along_ray_m, 0.0) + p_.lookahead_m;
  c.aim = {origin_.north_m + s * un, origin_.east_m + s * ue};
  c.desired_heading_deg = core::bearing_deg(pose.position, c.aim);
  return c;
}

DockingCommand DockingApproach::hold_marker(double heading_deg,
                                            std::optional<double> marker_bearing_deg,
                                            std::optional<double> range_ahead_m) {
  DockingCommand c;
  c.stop = check_stop(range_ahead_m);
  double turn = 0.0;
  if (marker_bearing_deg && std::isfinite(*marker_bearing_deg)) {
    turn = std::clamp(p_.marker_gain * core::wrap_deg(*marker_bearing_deg), -p_.max_marker_turn_deg,
                      p_.max_marker_turn_deg);
  }
  c.desired_heading_deg = core::wrap_deg(heading_deg + turn);
  return c;
}

}  // namespace coxswain::guidance
