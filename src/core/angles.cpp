// SPDX-License-Identifier: Apache-2.0
#include "coxswain/core/angles.hpp"

#include <cmath>

namespace coxswain::core {

double wrap_deg(double angle_deg) {
  // Already in range (most calls): fmod would return it unchanged, exactly.
  if (angle_deg > -180.0 && angle_deg <= 180.0) return angle_deg;
  // One turn out (sums of two wrapped angles): a single exact step (Sterbenz), the value fmod
  // and the corrections below give.
  if (angle_deg > 180.0 && angle_deg <= 540.0) return angle_deg - 360.0;
  // (Not -360 itself: fmod gives -0 there, and the sign of a zero reaches atan2.)
  if (angle_deg > -540.0 && angle_deg <= -180.0 && angle_deg != -360.0) return angle_deg + 360.0;
  if (!std::isfinite(angle_deg)) return angle_deg;
  double r = std::fmod(angle_deg, 360.0);  // (-360, 360)
  if (r <= -180.0) r += 360.0;
  if (r > 180.0) r -= 360.0;
  return r;
}

double wrap_rad(double angle_rad) {
  if (!std::isfinite(angle_rad)) return angle_rad;
  double r = std::fmod(angle_rad, 2.0 * kPi);
  if (r <= -kPi) r += 2.0 * kPi;
  if (r > kPi) r -= 2.0 * kPi;
  return r;
}

double wrap_deg_360(double angle_deg) {
  if (angle_deg >= 0.0 && angle_deg < 360.0) return angle_deg;            // as fmod would return it
  if (angle_deg >= 360.0 && angle_deg < 720.0) return angle_deg - 360.0;  // exact, as fmod's
  if (angle_deg > -360.0 && angle_deg < 0.0) {  // (-360: fmod's -0, below)
    const double r = angle_deg + 360.0;
    return r >= 360.0 ? r - 360.0 : r;  // -1e-18 + 360 rounds to 360
  }
  if (!std::isfinite(angle_deg)) return angle_deg;
  double r = std::fmod(angle_deg, 360.0);
  if (r < 0.0) r += 360.0;
  if (r >= 360.0) r -= 360.0;  // -1e-18 + 360 rounds to 360
  return r;
}

void CircularMean::add(double angle_deg, double weight) {
  if (!(weight > 0.0) || !std::isfinite(angle_deg)) return;
  const double a = deg_to_rad(angle_deg);
  sum_sin_ += weight * std::sin(a);
  sum_cos_ += weight * std::cos(a);
  weight_sum_ += weight;
}

double CircularMean::mean_deg() const {
  if (empty() || (sum_sin_ == 0.0 && sum_cos_ == 0.0)) return 0.0;
  return wrap_deg(rad_to_deg(std::atan2(sum_sin_, sum_cos_)));
}

double CircularMean::concentration() const {
  if (empty()) return 0.0;
  return std::hypot(sum_sin_, sum_cos_) / weight_sum_;
}

}  // namespace coxswain::core
