// SPDX-License-Identifier: Apache-2.0
#pragma once
// Hard- and soft-iron calibration of the magnetometer from a slow turn in place: the horizontal
// field samples of a full turn lie on an ellipse (hard iron shifts its centre, soft iron
// stretches and turns it); a least-squares conic fit gives the centre and the linear map that
// turns the ellipse back into a circle. Level approximation (the boat's roll and pitch are a
// few degrees). Pure; allocation only in the fit (a desk tool, never the tick).
#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>

namespace coxswain::guidance {

struct MagCalibration {
  double hard_iron_x_ut = 0.0;  // board x (forward) and y (starboard) offsets, microtesla
  double hard_iron_y_ut = 0.0;
  /// Row-major 2x2 map applied after removing the hard iron: xx, xy, yx, yy.
  std::array<double, 4> soft_iron{1.0, 0.0, 0.0, 1.0};
  double radius_ut = 0.0;        // the corrected circle's radius
  double residual_rms_ut = 0.0;  // of the corrected samples from that circle
  double coverage_deg = 0.0;     // heading range the samples span
  std::size_t samples = 0;

  /// The corrected horizontal field (x forward, y starboard).
  [[nodiscard]] std::array<double, 2> correct(double x_ut, double y_ut) const;
  /// Magnetic heading of the board's x axis (deg, clockwise from magnetic north, level).
  [[nodiscard]] double heading_deg(double x_ut, double y_ut) const;
};

/// Fits the calibration to horizontal field samples (x, y in microtesla). Empty with the reason
/// in `why` when the samples are too few, cover too little of a turn (< 300 deg) or do not form
/// an ellipse.
[[nodiscard]] std::optional<MagCalibration> fit_mag_calibration(
    std::span<const std::array<double, 2>> samples, std::string& why);

}  // namespace coxswain::guidance
