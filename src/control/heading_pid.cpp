// SPDX-License-Identifier: Apache-2.0
#include "coxswain/control/heading_pid.hpp"

#include <algorithm>
#include <cmath>

#include "coxswain/control/filters.hpp"
#include "coxswain/core/angles.hpp"

namespace coxswain::control {

std::optional<std::string> HeadingPidParams::validate() const {
  if (!(kp_per_deg >= 0.0) || !(ki_per_deg_s >= 0.0) || !(kd_per_dps >= 0.0)) {
    return "heading PID gains must be >= 0";
  }
  if (!(output_limit > 0.0) || output_limit > 1.0) return "output_limit must be in (0, 1]";
  if (!(integral_limit >= 0.0)) return "integral_limit must be >= 0";
  if (!(integral_zone_deg > 0.0)) return "integral_zone_deg must be > 0";
  if (!(tracking_gain_per_s >= 0.0)) return "tracking_gain_per_s must be >= 0";
  if (!(derivative_tau_s >= 0.0)) return "derivative_tau_s must be >= 0";
  if (!(max_dt_s > 0.0)) return "max_dt_s must be > 0";
  if (!(reversal_hold_deg >= 0.0) || reversal_hold_deg >= 90.0) {
    return "reversal_hold_deg must be in [0, 90)";
  }
  return std::nullopt;
}

void HeadingPid::reset() {
  terms_ = {};
  integral_ = 0.0;
  rate_dps_ = 0.0;
  last_heading_deg_ = 0.0;
  last_ns_ = core::kNeverNs;
  held_sign_ = 0;
}

double HeadingPid::update(const HeadingPidInput& in) {
  if (!std::isfinite(in.desired_heading_deg) || !std::isfinite(in.heading_deg)) {
    return terms_.output;  // a bad sample changes nothing
  }
  const bool first = last_ns_ == core::kNeverNs;
  double dt = first ? 0.0 : dt_between_s(last_ns_, in.stamp_ns);
  if (dt > p_.max_dt_s) dt = 0.0;  // dropout: no integration, no derivative across the gap

  // psi_e, with the turn direction held near +-180 so noise cannot flip it side to side.
  double e = core::angle_diff_deg(in.desired_heading_deg, in.heading_deg);
  const double flip_zone = 180.0 - p_.reversal_hold_deg;
  if (held_sign_ != 0 && std::abs(e) > flip_zone && (e > 0.0 ? 1 : -1) != held_sign_) {
    e += 360.0 * held_sign_;
  }
  if (e != 0.0) held_sign_ = e > 0.0 ? 1 : -1;

  // Derivative on the measurement: a jump of psi_d (waypoint switch) causes no kick.
  if (in.yaw_rate_dps.has_value() && std::isfinite(*in.yaw_rate_dps)) {
    rate_dps_ = *in.yaw_rate_dps;
  } else if (dt > 0.0) {
    const double raw = core::angle_diff_deg(in.heading_deg, last_heading_deg_) / dt;
    const double k = p_.derivative_tau_s > 0.0 ? dt / (p_.derivative_tau_s + dt) : 1.0;
    rate_dps_ += k * (raw - rate_dps_);
  } else if (first) {
    rate_dps_ = 0.0;
  }

  if (dt > 0.0 && std::abs(e) < p_.integral_zone_deg) integral_ += p_.ki_per_deg_s * e * dt;
  integral_ = std::clamp(integral_, -p_.integral_limit, p_.integral_limit);

  const double pterm = p_.kp_per_deg * e;
  const double dterm = -p_.kd_per_dps * rate_dps_;
  const double unsat = pterm + integral_ + dterm;
  const double out = std::clamp(unsat, -p_.output_limit, p_.output_limit);
  // Back-calculation: while saturated, bleed the integral so it is not stored up against a turn
  // the actuator cannot deliver. It only shrinks toward zero: driving it past zero would store a
  // bias the other way whenever P alone saturates (every large turn).
  if (dt > 0.0 && out != unsat) {
    const double bleed = p_.tracking_gain_per_s * dt * (out - unsat);
    if (bleed < 0.0 && integral_ > 0.0) integral_ = std::max(0.0, integral_ + bleed);
    if (bleed > 0.0 && integral_ < 0.0) integral_ = std::min(0.0, integral_ + bleed);
  }

  last_heading_deg_ = in.heading_deg;
  last_ns_ = in.stamp_ns;
  terms_ = {e, pterm, integral_, dterm, unsat, out, out != unsat};
  return out;
}

}  // namespace coxswain::control
