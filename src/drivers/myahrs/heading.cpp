// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/myahrs/heading.hpp"

#include <algorithm>
#include <cmath>

#include "coxswain/core/angles.hpp"

namespace coxswain::drivers::myahrs {

std::optional<std::string> HeadingConfig::validate() const {
  if (!std::isfinite(mount_yaw_deg) || std::abs(mount_yaw_deg) > 360.0) {
    return std::string("mount_yaw_deg must be finite and within [-360, 360]");
  }
  if (!std::isfinite(declination_deg) || std::abs(declination_deg) > 90.0) {
    return std::string("declination_deg must be finite and within [-90, 90]");
  }
  return std::nullopt;
}

double true_heading_deg(double sensor_yaw_magnetic_deg, const HeadingConfig& config) {
  // The board's heading is the bow's heading plus the mount yaw, so the bow's is the difference.
  return core::wrap_deg(sensor_yaw_magnetic_deg - config.mount_yaw_deg + config.declination_deg);
}

std::optional<EulerDeg> quaternion_to_euler_deg(double x, double y, double z, double w) {
  const double norm = std::sqrt(x * x + y * y + z * z + w * w);
  if (!std::isfinite(norm) || norm < 1e-6) return std::nullopt;
  x /= norm;
  y /= norm;
  z /= norm;
  w /= norm;
  EulerDeg e;
  e.roll_deg = core::rad_to_deg(std::atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y)));
  const double s = std::clamp(2.0 * (w * y - z * x), -1.0, 1.0);
  e.pitch_deg = core::rad_to_deg(std::asin(s));
  e.yaw_deg = core::rad_to_deg(std::atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z)));
  return e;
}

}  // namespace coxswain::drivers::myahrs
