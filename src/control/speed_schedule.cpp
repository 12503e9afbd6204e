// SPDX-License-Identifier: Apache-2.0
#include "coxswain/control/speed_schedule.hpp"

#include <algorithm>
#include <cmath>

namespace coxswain::control {

std::optional<std::string> SpeedScheduleParams::validate() const {
  if (!(min_thrust_frac >= 0.0) || !(max_thrust_frac <= 1.0) ||
      !(min_thrust_frac <= max_thrust_frac)) {
    return "need 0 <= min_thrust_frac <= max_thrust_frac <= 1";
  }
  if (!(slow_distance_m >= 0.0) || !(fast_distance_m > slow_distance_m)) {
    return "need 0 <= slow_distance_m < fast_distance_m";
  }
  if (!(rise_per_s > 0.0) || !(fall_per_s > 0.0)) return "rise_per_s and fall_per_s must be > 0";
  return std::nullopt;
}

SpeedSchedule::SpeedSchedule(SpeedScheduleParams p)
    : p_(p), limiter_(RateLimiterParams{p.rise_per_s, p.fall_per_s}) {}

double SpeedSchedule::scheduled(double distance_m) const {
  if (!std::isfinite(distance_m)) return p_.min_thrust_frac;
  const double span = p_.fast_distance_m - p_.slow_distance_m;
  const double t = span > 0.0 ? std::clamp((distance_m - p_.slow_distance_m) / span, 0.0, 1.0)
                              : (distance_m > p_.slow_distance_m ? 1.0 : 0.0);
  return p_.min_thrust_frac + t * (p_.max_thrust_frac - p_.min_thrust_frac);
}

double SpeedSchedule::update(double distance_m, core::TimeNs stamp_ns) {
  return limiter_.update(scheduled(distance_m), stamp_ns);
}

}  // namespace coxswain::control
