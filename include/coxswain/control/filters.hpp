// SPDX-License-Identifier: Apache-2.0
#pragma once
// Filters for commands (plain values) and for angles (wrap-safe). The documents smoothed the
// heading with an arithmetic moving average, which averages 179 and -179 to 0 (due south becomes
// due north); every angle filter here works on unit vectors instead.
//
// All classes: plain values, no allocation (fixed-capacity ring buffers), not thread-safe (one
// owner). Time steps come from the callers' stamps (steady-clock ns); no clock is read.
#include <array>
#include <cstddef>
#include <optional>
#include <string>

#include "coxswain/core/time.hpp"

namespace coxswain::control {

/// Capacity of the fixed-window filters; a window is 1..kMaxWindow samples.
inline constexpr std::size_t kMaxWindow = 64;

/// First-order low-pass y += a (x - y), a = dt / (tau + dt), for plain values (servo command,
/// thrust). The first sample initialises the output. tau_s <= 0 passes input through.
struct LowPassParams {
  double tau_s = 0.3;  // time constant, seconds
};
class LowPass {
 public:
  explicit LowPass(LowPassParams p = {}) : p_(p) {}
  double update(double x, core::TimeNs stamp_ns);
  void reset() { has_ = false; }
  [[nodiscard]] double value() const { return y_; }

 private:
  LowPassParams p_;
  double y_ = 0.0;
  core::TimeNs last_ns_ = core::kNeverNs;
  bool has_ = false;
};

/// Unit-vector exponential low-pass for angles in degrees: filters sin and cos, returns the
/// angle of the filtered vector in (-180, 180]. 179 -> -179 stays near 180.
struct AngleLowPassParams {
  double tau_s = 0.3;  // time constant, seconds
};
class AngleLowPass {
 public:
  explicit AngleLowPass(AngleLowPassParams p = {}) : p_(p) {}
  double update(double angle_deg, core::TimeNs stamp_ns);
  void reset() { has_ = false; }
  [[nodiscard]] double value_deg() const;

 private:
  AngleLowPassParams p_;
  double s_ = 0.0;
  double c_ = 1.0;
  core::TimeNs last_ns_ = core::kNeverNs;
  bool has_ = false;
};

/// Fixed-window arithmetic mean of the last `window` samples (the documents' moving average),
/// for plain values only. The sum is recomputed each call (window <= 64) so it never drifts.
class MovingAverage {
 public:
  /// window is clamped to [1, kMaxWindow].
  explicit MovingAverage(std::size_t window = 5);
  double update(double x);
  void reset() {
    count_ = 0;
    head_ = 0;
  }
  [[nodiscard]] std::size_t size() const { return count_; }

 private:
  std::array<double, kMaxWindow> buf_{};
  std::size_t window_;
  std::size_t head_ = 0;
  std::size_t count_ = 0;
};

/// Fixed-window wrap-safe mean of angles (core::CircularMean over the last `window` samples).
class AngleMovingAverage {
 public:
  explicit AngleMovingAverage(std::size_t window = 5);
  /// Returns the circular mean in (-180, 180]. Non-finite samples are ignored.
  double update(double angle_deg);
  void reset() {
    count_ = 0;
    head_ = 0;
  }
  /// Mean resultant length of the window, 0..1 (1 = steady heading, low = noisy or turning).
  [[nodiscard]] double concentration() const { return concentration_; }

 private:
  std::array<double, kMaxWindow> buf_{};
  std::size_t window_;
  std::size_t head_ = 0;
  std::size_t count_ = 0;
  double mean_deg_ = 0.0;
  double concentration_ = 0.0;
};

/// Slew-rate limit with separate rise and fall rates (units of the value per second). The first
/// sample after reset() starts from reset's value. Used for thrust so a waypoint switch cannot
/// jump the ESC from slow to full.
struct RateLimiterParams {
  double rise_per_s = 0.25;  // max increase per second (> 0)
  double fall_per_s = 0.5;   // max decrease per second (> 0)
};
class RateLimiter {
 public:
  explicit RateLimiter(RateLimiterParams p = {}) : p_(p) {}
  double update(double target, core::TimeNs stamp_ns);
  void reset(double value) {
    y_ = value;
    last_ns_ = core::kNeverNs;
  }
  [[nodiscard]] double value() const { return y_; }
  /// Empty when valid, else what is wrong.
  [[nodiscard]] std::optional<std::string> validate() const;

 private:
  RateLimiterParams p_;
  double y_ = 0.0;
  core::TimeNs last_ns_ = core::kNeverNs;
};

/// Seconds between two stamps; 0 when the earlier is kNeverNs or time did not advance.
[[nodiscard]] double dt_between_s(core::TimeNs earlier_ns, core::TimeNs later_ns);

}  // namespace coxswain::control
