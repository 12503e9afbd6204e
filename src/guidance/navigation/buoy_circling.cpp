// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/buoy_circling.hpp"

#include <algorithm>
#include <cmath>

#include "coxswain/core/angles.hpp"

namespace coxswain::guidance {

std::optional<std::string> BuoyCirclingParams::validate() const {
  if (!(std::abs(target_bearing_deg) > 10.0 && std::abs(target_bearing_deg) < 170.0)) {
    return "buoy circling: |target_bearing_deg| must be in (10, 170)";
  }
  if (!(target_distance_m > 0.0)) return "buoy circling: target_distance_m must be > 0";
  if (!(bearing_gain > 0.0)) return "buoy circling: bearing_gain must be > 0";
  if (!(distance_gain_deg_per_m >= 0.0)) return "buoy circling: distance gain must be >= 0";
  if (!(max_turn_deg > 0.0)) return "buoy circling: max_turn_deg must be > 0";
  if (!(complete_turn_deg > 0.0)) return "buoy circling: complete_turn_deg must be > 0";
  if (!(max_heading_step_deg > 0.0 && max_heading_step_deg < 180.0)) {
    return "buoy circling: max_heading_step_deg must be in (0, 180)";
  }
  return std::nullopt;
}

void BuoyCircling::reset() {
  turned_deg_ = 0.0;
  last_heading_deg_ = 0.0;
  has_heading_ = false;
  done_ = false;
}

double BuoyCircling::progress_deg() const {
  // Buoy to port (-90): the boat circles counter-clockwise, heading decreasing.
  return p_.target_bearing_deg < 0.0 ? -turned_deg_ : turned_deg_;
}

BuoyCirclingOutput BuoyCircling::update(double heading_deg, const BuoyObservation& obs) {
  BuoyCirclingOutput out;
  if (!std::isfinite(heading_deg)) {
    out.desired_heading_deg = last_heading_deg_;
    out.turned_deg = turned_deg_;
    out.progress_deg = progress_deg();
    out.done = done_;
    return out;
  }
  const bool seen = obs.bearing_deg && std::isfinite(*obs.bearing_deg);
  if (has_heading_ && (seen || !p_.count_only_seen)) {
    const double step = core::angle_diff_deg(heading_deg, last_heading_deg_);
    // A jump bigger than the boat can turn in one sample is a compass glitch: not counted.
    if (std::abs(step) <= p_.max_heading_step_deg) turned_deg_ += step;
  }
  last_heading_deg_ = heading_deg;
  has_heading_ = true;
  if (progress_deg() >= p_.complete_turn_deg) done_ = true;

  const double side = p_.target_bearing_deg < 0.0 ? -1.0 : 1.0;  // toward the buoy's side
  double turn = side * p_.search_turn_deg;
  if (seen) {
    out.buoy_seen = true;
    // Buoy drifted aft of the target bearing (e.g. -110 for -90): turn toward it by that much.
    out.bearing_error_deg = core::angle_diff_deg(*obs.bearing_deg, p_.target_bearing_deg);
    turn = p_.bearing_gain * out.bearing_error_deg;
    if (obs.range_m && std::isfinite(*obs.range_m) && *obs.range_m > 0.0) {
      const double corr =
          std::clamp(p_.distance_gain_deg_per_m * (*obs.range_m - p_.target_distance_m),
                     -p_.max_distance_correction_deg, p_.max_distance_correction_deg);
      turn += side * corr;  // too far: turn toward the buoy; too close: away
    }
  }
  turn = std::clamp(turn, -p_.max_turn_deg, p_.max_turn_deg);
  out.desired_heading_deg = core::wrap_deg(heading_deg + turn);
  out.turned_deg = turned_deg_;
  out.progress_deg = progress_deg();
  out.done = done_;
  return out;
}

}  // namespace coxswain::guidance
