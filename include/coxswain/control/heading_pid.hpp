// SPDX-License-Identifier: Apache-2.0
#pragma once
// Heading PID: desired true heading -> turn command in [-output_limit, output_limit]
// (+ = to starboard; the ActuatorMixer turns it into servo or differential pulses).
#include <optional>
#include <string>

#include "coxswain/core/time.hpp"

namespace coxswain::control {

/// Tunables; gains are per degree of heading error (psi_e) so the output is a unitless turn
/// command (1 = full rudder / full yaw-rate demand).
struct HeadingPidParams {
  double kp_per_deg = 1.0 / 45.0;  // full turn command at 45 deg of error
  double ki_per_deg_s = 0.002;     // integral gain, per (deg * s)
  double kd_per_dps = 0.01;        // derivative gain, per deg/s of measured yaw rate
  double output_limit = 1.0;       // |turn command| limit, 0 < limit <= 1
  /// The integral only trims a steady bias (an asymmetric hull or thrust), so it integrates only
  /// while |psi_e| is below this; large turns are P/D work and would wind it up.
  double integral_zone_deg = 10.0;
  double integral_limit = 0.3;       // hard clamp on the integral term's contribution
  double tracking_gain_per_s = 2.0;  // back-calculation gain: bleeds the integral when saturated
  double derivative_tau_s = 0.2;     // low-pass on the heading-difference rate (unused with gyro)
  double max_dt_s = 0.5;  // a gap longer than this (dropout) skips integration and derivative
  /// Near +-180 deg of error the shortest-turn sign flips with noise; once a turn direction is
  /// chosen it is kept while |psi_e| > 180 - reversal_hold_deg (no side-to-side flipping).
  double reversal_hold_deg = 25.0;

  /// Empty when valid, else what is wrong.
  [[nodiscard]] std::optional<std::string> validate() const;
};

/// One control step's inputs. Headings are TRUE (navigation convention), never magnetic.
struct HeadingPidInput {
  double desired_heading_deg = 0.0;  // psi_d
  double heading_deg = 0.0;          // psi
  core::TimeNs stamp_ns = 0;         // stamp of the heading measurement
  /// Measured yaw rate (gyro z, body z down: + = turning to starboard); empty = differentiate the
  /// heading instead.
  std::optional<double> yaw_rate_dps;
};

/// Terms of the last update, for the recorder and the live view.
struct HeadingPidTerms {
  double error_deg = 0.0;  // psi_e as used (may exceed 180 while a reversal is held)
  double p = 0.0;
  double i = 0.0;
  double d = 0.0;
  double unsaturated = 0.0;
  double output = 0.0;
  bool saturated = false;
};

/// PID on psi_e = angle_diff(psi_d, psi) with anti-windup (clamped integral plus back-calculation),
/// derivative on the measurement (gyro rate when given, so a step in psi_d causes no derivative
/// kick), output limits, dt from the stamps. Plain value, no allocation, not thread-safe.
class HeadingPid {
 public:
  explicit HeadingPid(HeadingPidParams p = {}) : p_(p) {}
  /// Returns the turn command; + = turn to starboard.
  double update(const HeadingPidInput& in);
  void reset();
  [[nodiscard]] const HeadingPidTerms& terms() const { return terms_; }
  [[nodiscard]] const HeadingPidParams& params() const { return p_; }

 private:
  HeadingPidParams p_;
  HeadingPidTerms terms_;
  double integral_ = 0.0;  // integral term contribution (already times ki)
  double rate_dps_ = 0.0;  // filtered heading-difference rate
  double last_heading_deg_ = 0.0;
  core::TimeNs last_ns_ = core::kNeverNs;
  int held_sign_ = 0;  // turn direction kept near +-180
};

}  // namespace coxswain::control
