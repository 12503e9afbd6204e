// SPDX-License-Identifier: Apache-2.0
#include "coxswain/control/filters.hpp"

#include <algorithm>
#include <cmath>

#include "coxswain/core/angles.hpp"

namespace coxswain::control {

double dt_between_s(core::TimeNs earlier_ns, core::TimeNs later_ns) {
  if (earlier_ns == core::kNeverNs || later_ns <= earlier_ns) return 0.0;
  return core::ns_to_sec(later_ns - earlier_ns);
}

namespace {
double blend(double tau_s, double dt_s) {
  if (tau_s <= 0.0) return 1.0;
  return dt_s / (tau_s + dt_s);
}
std::size_t clamp_window(std::size_t w) { return std::clamp<std::size_t>(w, 1, kMaxWindow); }
}  // namespace

double LowPass::update(double x, core::TimeNs stamp_ns) {
  if (!std::isfinite(x)) return y_;
  if (!has_) {
    y_ = x;
    has_ = true;
  } else {
    y_ += blend(p_.tau_s, dt_between_s(last_ns_, stamp_ns)) * (x - y_);
  }
  last_ns_ = stamp_ns;
  return y_;
}

double AngleLowPass::update(double angle_deg, core::TimeNs stamp_ns) {
  if (!std::isfinite(angle_deg)) return value_deg();
  const double a = core::deg_to_rad(angle_deg);
  if (!has_) {
    s_ = std::sin(a);
    c_ = std::cos(a);
    has_ = true;
  } else {
    const double k = blend(p_.tau_s, dt_between_s(last_ns_, stamp_ns));
    s_ += k * (std::sin(a) - s_);
    c_ += k * (std::cos(a) - c_);
  }
  last_ns_ = stamp_ns;
  return value_deg();
}

double AngleLowPass::value_deg() const {
  if (s_ == 0.0 && c_ == 0.0) return 0.0;
  return core::wrap_deg(core::rad_to_deg(std::atan2(s_, c_)));
}

MovingAverage::MovingAverage(std::size_t window) : window_(clamp_window(window)) {}

double MovingAverage::update(double x) {
  if (std::isfinite(x)) {
    buf_[head_] = x;
    head_ = (head_ + 1) % window_;
    count_ = std::min(count_ + 1, window_);
  }
  if (count_ == 0) return 0.0;
  double sum = 0.0;
  for (std::size_t i = 0; i < count_; ++i) sum += buf_[i];
  return sum / static_cast<double>(count_);
}

AngleMovingAverage::AngleMovingAverage(std::size_t window) : window_(clamp_window(window)) {}

double AngleMovingAverage::update(double angle_deg) {
  if (!std::isfinite(angle_deg)) return mean_deg_;
  buf_[head_] = angle_deg;
  head_ = (head_ + 1) % window_;
  count_ = std::min(count_ + 1, window_);
  core::CircularMean m;
  for (std::size_t i = 0; i < count_; ++i) m.add(buf_[i]);
  // Vectors that cancel exactly have no mean: keep the last one rather than jump to 0.
  if (m.concentration() > 1e-9) mean_deg_ = m.mean_deg();
  concentration_ = m.concentration();
  return mean_deg_;
}

double RateLimiter::update(double target, core::TimeNs stamp_ns) {
  if (!std::isfinite(target)) return y_;
  const double dt = dt_between_s(last_ns_, stamp_ns);
  last_ns_ = stamp_ns;
  const double up = p_.rise_per_s * dt;
  const double down = p_.fall_per_s * dt;
  y_ = std::clamp(target, y_ - down, y_ + up);
  return y_;
}

std::optional<std::string> RateLimiter::validate() const {
  if (!(p_.rise_per_s > 0.0) || !(p_.fall_per_s > 0.0)) return "rate limits must be > 0";
  return std::nullopt;
}

}  // namespace coxswain::control
