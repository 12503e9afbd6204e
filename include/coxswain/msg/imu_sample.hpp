// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <array>

#include "coxswain/core/time.hpp"

namespace coxswain::msg {

/// One AHRS output. Attitude in degrees; heading in the navigation convention (true north,
/// clockwise positive, (-180, 180]) after mount yaw and magnetic declination are applied.
/// Body axes: x forward, y starboard, z down.
struct ImuSample {
  core::TimeNs stamp_ns = core::kNeverNs;
  double roll_deg = 0.0;
  double pitch_deg = 0.0;
  double yaw_magnetic_deg = 0.0;  // as the sensor reported it (magnetic, sensor frame)
  double heading_deg = 0.0;       // true heading of the bow, navigation convention
  std::array<double, 3> accel_g{};
  std::array<double, 3> gyro_dps{};
  std::array<double, 3> mag_ut{};
  double temperature_c = 0.0;
  bool has_inertial = false;  // accel/gyro/mag fields valid
  unsigned sequence = 0;      // the sensor's own counter
};

}  // namespace coxswain::msg
