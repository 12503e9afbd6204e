// SPDX-License-Identifier: Apache-2.0
#pragma once
// Distance to go -> forward thrust setpoint, rate limited (the KABOAT 2022 report, 5.1.2: after a
// waypoint switch the distance jumps and the thrust went from minimum to maximum at once; the boat
// lurched).
#include <optional>
#include <string>

#include "coxswain/control/filters.hpp"
#include "coxswain/core/time.hpp"

namespace coxswain::control {

/// Thrust is a fraction of the forward range (0 = neutral, 1 = the ESC's forward maximum).
struct SpeedScheduleParams {
  double min_thrust_frac = 0.3;  // at or inside slow_distance_m
  double max_thrust_frac = 1.0;  // at or beyond fast_distance_m
  double slow_distance_m = 2.0;
  double fast_distance_m = 12.0;
  double rise_per_s = 0.2;          // thrust increase limit, fraction per second
  double fall_per_s = 0.5;          // thrust decrease limit, fraction per second
  double cruise_thrust_frac = 0.7;  // avoidance tasks, before the avoidance speed factor

  [[nodiscard]] std::optional<std::string> validate() const;
};

/// Linear schedule between (slow_distance, min) and (fast_distance, max), then a rise/fall rate
/// limit on the output. Plain value, no allocation, not thread-safe.
class SpeedSchedule {
 public:
  explicit SpeedSchedule(SpeedScheduleParams p = {});
  /// The unlimited setpoint for a distance (exposed for tests and the live view).
  [[nodiscard]] double scheduled(double distance_m) const;
  /// Rate-limited thrust fraction for this step.
  double update(double distance_m, core::TimeNs stamp_ns);
  /// Start from a known thrust (0 when the boat is still).
  void reset(double thrust_frac = 0.0) { limiter_.reset(thrust_frac); }

 private:
  SpeedScheduleParams p_;
  RateLimiter limiter_;
};

}  // namespace coxswain::control
