// SPDX-License-Identifier: Apache-2.0
#pragma once
// myAHRS+ attitude -> navigation heading. Protocol facts: docs/protocols.md section
// 2.6.
//
// Frames:
// - board (sensor) frame: x forward along the board's arrow, y right, z down (at rest az ~ -1 g
//   because the accelerometer measures the reaction to gravity). Euler angles are Z-Y-X
//   (yaw, then pitch, then roll); yaw grows clockwise seen from above, like a compass, and is
//   MAGNETIC (0 = magnetic north once the magnetometer is calibrated).
// - body frame: x forward (bow), y starboard, z down. The board's x axis is turned
//   `mount_yaw_deg` clockwise from the bow (same meaning as core::MountTransform::yaw_deg).
// - navigation frame: X north, Y east; heading 0 = true north, clockwise positive, (-180, 180].
#include <optional>
#include <string>

namespace coxswain::drivers::myahrs {

/// How the sensor sits on the hull and where it is used. From config (boat.yaml / devices.yaml).
struct HeadingConfig {
  /// Board x axis turned this far clockwise from the bow, degrees. Default 0 (arrow to the bow).
  double mount_yaw_deg = 0.0;
  /// Magnetic declination at the venue, degrees, east positive (true = magnetic + declination).
  /// Default 0; e.g. about -9 in Korea.
  double declination_deg = 0.0;

  /// Empty when valid; otherwise what is wrong (non-finite or outside [-360, 360] / [-90, 90]).
  [[nodiscard]] std::optional<std::string> validate() const;
};

/// Roll, pitch, yaw in degrees (Z-Y-X order), the sensor's convention.
struct EulerDeg {
  double roll_deg = 0.0;
  double pitch_deg = 0.0;
  double yaw_deg = 0.0;
};

/// True heading of the bow in the navigation convention, (-180, 180]:
///   wrap(sensor_yaw - mount_yaw + declination).
/// This is the ONE place the myAHRS+ yaw is turned into a heading.
[[nodiscard]] double true_heading_deg(double sensor_yaw_magnetic_deg, const HeadingConfig& config);

/// Z-Y-X Euler angles of the unit quaternion (x, y, z, w) the sensor outputs (w last, rotation
/// board -> navigation frame). The quaternion is normalised first; nullopt when its norm is below
/// 1e-6 or not finite. Pitch is clamped at +-90 so rounding never produces NaN.
[[nodiscard]] std::optional<EulerDeg> quaternion_to_euler_deg(double x, double y, double z,
                                                              double w);

}  // namespace coxswain::drivers::myahrs
