// SPDX-License-Identifier: Apache-2.0
#pragma once
// Tunables of the camera detectors (markers and buoys) and the pinhole bearing model.
// Plain data with documented defaults; YAML loading lives elsewhere. Hue uses OpenCV's 8-bit
// convention: 0..179 (degrees / 2); saturation and value 0..255.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "coxswain/msg/camera_detections.hpp"

namespace coxswain::perception {

/// One HSV box. `h_min > h_max` means the range wraps through 180/0 (red): h >= h_min OR
/// h <= h_max. A black marker is a value-only range (any hue, any saturation, low V).
struct HsvRange {
  std::uint8_t h_min = 0;
  std::uint8_t h_max = 179;
  std::uint8_t s_min = 0;
  std::uint8_t s_max = 255;
  std::uint8_t v_min = 0;
  std::uint8_t v_max = 255;

  [[nodiscard]] bool wraps() const { return h_min > h_max; }
  /// True when the pixel (OpenCV 8-bit HSV) lies in the range; the reference the masks follow.
  [[nodiscard]] bool contains(int h, int s, int v) const;
};

/// A colour the detectors look for, and which detector uses it.
struct ColourRange {
  msg::Colour colour = msg::Colour::kUnknown;
  HsvRange hsv;
  bool markers = true;  // searched by MarkerDetector
  bool buoys = true;    // searched by BuoyDetector
};

/// Thresholds for telling triangle, rectangle, cross and circle apart (see vision_shape.hpp).
struct ShapeParams {
  double approx_epsilon_fraction = 0.02;  // approxPolyDP epsilon as a fraction of the perimeter
  double convex_min_solidity = 0.90;      // area / hull area for triangle, rectangle, circle
  double cross_max_solidity = 0.86;  // plus, arms 1/3 wide: 5/9 = 0.56; closing lifts small ones
  double cross_min_solidity = 0.35;
  double cross_min_defect_depth = 0.12;  // deep concavity, fraction of sqrt(area); plus = 0.32
  double triangle_max_extent = 0.62;     // area / min-area rectangle: any triangle = 0.5
  double rectangle_min_extent = 0.86;    // square = 1.0, circle = pi/4 = 0.785
  double circle_min_circularity = 0.82;  // 4 pi A / P^2 on the hull; semicircle 0.75, square 0.785
  double circle_max_extent = 0.85;       // a circle or ellipse fills pi/4 of its rectangle
  double min_fill_ratio = 0.60;          // mask pixels / outer-contour area: rejects outline rings
  // A marker inside a hole of a larger blob (a placard in water of the marker's colour) must fill
  // this share of the hole: glyphs on the mission's placards fill 0.22 (triangle) to 0.51.
  double island_min_hole_fraction = 0.15;
};

/// The per-frame background model: the frame is cut into horizontal strips and the dominant
/// colour of each (sky, far water, near water: they change with the row) is fitted as a
/// Gaussian in BGR; every colour mask rejects pixels within `reject_sigma` of any of them.
/// Blue-green sea falls inside the blue box and a low sun's sky inside the orange one; a marker
/// is a minority of any strip, so it never becomes the background.
struct BackgroundParams {
  static constexpr int kMaxStrips = 16;
  bool enabled = true;
  int strips = 8;             // horizontal strips, each with its own model
  int sample_step_px = 4;     // sampling grid pitch in both directions
  int max_samples = 2400;     // per strip: a larger frame's grid is coarsened to stay within this
                              // (640 x 480 in 8 strips at 4 px holds exactly 2400)
  double min_share = 0.50;    // the dominant colour must hold this share of a strip's samples
  double reject_sigma = 4.5;  // Mahalanobis radius rejected around the background colour
  double min_sigma = 5.0;     // grey levels: floor of each axis' spread (flat, noiseless water)
  double max_sigma = 40.0;    // grey levels: cap, so a mottled band cannot swallow the markers
  int max_saturation = 190;   // 0..255: a more saturated dominant colour is a marker filling the
                              // view (a placard up close), never water or sky
};

/// Every tunable of the camera detectors. Units in names; defaults suit the marker test images
/// (white placards, saturated fills) and the 80-deg USB camera of docs/missions.md.
struct VisionParams {
  static constexpr std::size_t kMaxColours = 10;

  std::array<ColourRange, kMaxColours> colours{};
  std::size_t colour_count = 0;

  int blur_kernel_px = 3;                // Gaussian pre-blur against sensor noise; 0 = off; odd
  int open_kernel_px = 3;                // morphological opening removes specks; 0 = off
  int close_kernel_px = 5;               // closing fills glyph holes and pinholes; 0 = off
  double min_area_fraction = 5e-4;       // smallest marker, fraction of the frame area
  double buoy_min_area_fraction = 2e-4;  // smallest buoy, fraction of the frame area
  double buoy_min_solidity = 0.70;       // buoys are round-ish blobs; spray and glare are not
  int edge_margin_px = 2;  // contours whose bounding box comes this close to the border are cut
  bool buoy_reject_edge = false;  // a buoy half out of the frame still gives a useful bearing
  double hfov_deg = 80.0;         // camera horizontal field of view
  double mount_yaw_deg = 0.0;     // camera optical axis in the body frame, + starboard
  ShapeParams shape;
  BackgroundParams background;

  /// Defaults: red (wrapping), orange, yellow, green, blue, purple, black (markers and buoys as
  /// docs/missions.md uses them). White is not searched: it is the placard background.
  [[nodiscard]] static VisionParams defaults();

  [[nodiscard]] bool add_colour(const ColourRange& c);
  /// Index of `colour` in `colours`, or -1.
  [[nodiscard]] int find_colour(msg::Colour colour) const;

  /// Empty when valid, else the first problem found.
  [[nodiscard]] std::optional<std::string> validate() const;
};

/// Bearing of image column `x_px` (0 = left edge of the image, width = right edge) in the camera
/// frame, through the pinhole model: f = (width/2) / tan(hfov/2), bearing = atan((x - width/2)/f).
/// Positive to the right (starboard for a forward camera). Degrees.
[[nodiscard]] double camera_bearing_deg(double x_px, int image_width_px, double hfov_deg);

/// Same, then rotated by the mount yaw into the body frame and wrapped to (-180, 180].
[[nodiscard]] double body_bearing_deg(double x_px, int image_width_px, double hfov_deg,
                                      double mount_yaw_deg);

}  // namespace coxswain::perception
