// SPDX-License-Identifier: Apache-2.0
#include "coxswain/control/actuator_mixer.hpp"

#include <algorithm>
#include <cmath>

#include "coxswain/core/angles.hpp"

namespace coxswain::control {

namespace {

double clamp_unit(double x) { return std::isfinite(x) ? std::clamp(x, -1.0, 1.0) : 0.0; }

/// base + offset rounded half away from zero on the OFFSET, so +x and -x land equally far from
/// base (truncating base + offset would give the negative side one microsecond more).
std::uint16_t offset_pulse(std::uint16_t base, double offset_us, std::uint16_t lo,
                           std::uint16_t hi) {
  const long p = static_cast<long>(base) + std::lround(offset_us);
  return static_cast<std::uint16_t>(std::clamp<long>(p, lo, hi));
}

}  // namespace

std::optional<std::string> ThrusterConfig::validate() const {
  if (!(min_us <= reverse_max_us && reverse_max_us <= reverse_start_us &&
        reverse_start_us <= neutral_us && neutral_us <= forward_start_us &&
        forward_start_us <= forward_max_us && forward_max_us <= max_us)) {
    return "thruster pulses must satisfy min <= reverse_max <= reverse_start <= neutral <= "
           "forward_start <= forward_max <= max";
  }
  if (!(deadband_frac >= 0.0 && deadband_frac < 1.0)) return "deadband_frac must be in [0, 1)";
  return std::nullopt;
}

std::optional<std::string> ServoConfig::validate() const {
  if (!(min_us <= center_us && center_us <= max_us && min_us < max_us)) {
    return "servo pulses must satisfy min < max and min <= center <= max";
  }
  if (!(max_deflection_deg > 0.0 && max_deflection_deg < 90.0)) {
    return "servo max_deflection_deg must be in (0, 90)";
  }
  if (sign != 1 && sign != -1) return "servo sign must be +1 or -1";
  return std::nullopt;
}

std::optional<std::string> MixerConfig::validate() const {
  if (layout == msg::ActuatorLayout::kServoThruster) {
    if (auto e = servo.validate()) return "servo: " + *e;
    if (auto e = thruster.validate()) return "thruster: " + *e;
    return std::nullopt;
  }
  if (!(twin.track_width_m > 0.0)) return "twin: track_width_m must be > 0";
  if (!(twin.max_speed_mps > 0.0)) return "twin: max_speed_mps must be > 0";
  if (!(twin.max_yaw_rate_dps > 0.0)) return "twin: max_yaw_rate_dps must be > 0";
  if (auto e = twin.port.validate()) return "twin port: " + *e;
  if (auto e = twin.starboard.validate()) return "twin starboard: " + *e;
  return std::nullopt;
}

std::uint16_t ActuatorMixer::thruster_pulse_us(const ThrusterConfig& t, double frac) {
  const double f = clamp_unit(frac);
  if (std::abs(f) < t.deadband_frac || f == 0.0) return t.neutral_us;
  if (f > 0.0) {
    const double span = static_cast<double>(t.forward_max_us - t.forward_start_us);
    return offset_pulse(t.forward_start_us, f * span, t.min_us, t.max_us);
  }
  if (!t.reverse_allowed) return t.neutral_us;
  const double span = static_cast<double>(t.reverse_start_us - t.reverse_max_us);
  return offset_pulse(t.reverse_start_us, f * span, t.min_us, t.max_us);
}

std::uint16_t ActuatorMixer::servo_pulse_us(double deflection_deg) const {
  const ServoConfig& s = c_.servo;
  const double f = clamp_unit(deflection_deg / s.max_deflection_deg) * s.sign;
  const double span = f >= 0.0 ? static_cast<double>(s.max_us - s.center_us)
                               : static_cast<double>(s.center_us - s.min_us);
  return offset_pulse(s.center_us, f * span, s.min_us, s.max_us);
}

msg::ActuatorCommand ActuatorMixer::neutral(core::TimeNs stamp_ns) const {
  msg::ActuatorCommand cmd;
  cmd.stamp_ns = stamp_ns;
  cmd.active = false;
  if (c_.layout == msg::ActuatorLayout::kServoThruster) {
    cmd.pulse_us = {c_.servo.center_us, c_.thruster.neutral_us};
  } else {
    cmd.pulse_us = {c_.twin.port.neutral_us, c_.twin.starboard.neutral_us};
  }
  return cmd;
}

msg::ActuatorCommand ActuatorMixer::mix(MixDemand d, core::TimeNs stamp_ns,
                                        MixDetail* detail) const {
  const double turn = clamp_unit(d.turn);
  const double thrust = clamp_unit(d.thrust);
  msg::ActuatorCommand cmd;
  cmd.stamp_ns = stamp_ns;
  cmd.active = true;
  MixDetail det;
  det.saturated = turn != d.turn || thrust != d.thrust;

  if (c_.layout == msg::ActuatorLayout::kServoThruster) {
    // Astern the turned thruster pulls the stern the other way: the deflection is mirrored so
    // a turn demand keeps its sense (a heading held astern stays held).
    const double deflect = thrust < 0.0 ? -turn : turn;
    cmd.pulse_us = {servo_pulse_us(deflect * c_.servo.max_deflection_deg),
                    thruster_pulse_us(c_.thruster, thrust)};
    det.channel_frac = {deflect, thrust};
  } else {
    const TwinConfig& t = c_.twin;
    const double v_mps = thrust * t.max_speed_mps;
    const double r_rad_s = core::deg_to_rad(turn * t.max_yaw_rate_dps);
    const double half = 0.5 * t.track_width_m;
    double fp = (v_mps + r_rad_s * half) / t.max_speed_mps;  // port pushes harder to turn right
    double fs = (v_mps - r_rad_s * half) / t.max_speed_mps;
    const double lo_p = t.port.reverse_allowed ? -1.0 : 0.0;
    const double lo_s = t.starboard.reverse_allowed ? -1.0 : 0.0;
    // Desaturate keeping the difference (the turn) and giving up common thrust first: a turn
    // demand must not vanish because one side hit its limit.
    const double over = std::max(fp, fs) - 1.0;
    if (over > 0.0) {
      fp -= over;
      fs -= over;
      det.saturated = true;
    }
    const double under = std::min(fp - lo_p, fs - lo_s);
    if (under < 0.0) {
      fp -= under;
      fs -= under;
      det.saturated = true;
    }
    const double cp = std::clamp(fp, lo_p, 1.0);
    const double cs = std::clamp(fs, lo_s, 1.0);
    if (cp != fp || cs != fs) det.saturated = true;
    cmd.pulse_us = {thruster_pulse_us(t.port, cp), thruster_pulse_us(t.starboard, cs)};
    det.channel_frac = {cp, cs};
  }
  if (detail != nullptr) *detail = det;
  return cmd;
}

}  // namespace coxswain::control
