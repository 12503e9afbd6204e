// SPDX-License-Identifier: Apache-2.0
#include "coxswain/perception/vision_params.hpp"

#include <cmath>

#include "coxswain/core/angles.hpp"

namespace coxswain::perception {

bool HsvRange::contains(int h, int s, int v) const {
  const bool hue_ok = wraps() ? (h >= h_min || h <= h_max) : (h >= h_min && h <= h_max);
  return hue_ok && s >= s_min && s <= s_max && v >= v_min && v <= v_max;
}

VisionParams VisionParams::defaults() {
  using msg::Colour;
  VisionParams p;
  // Saturation floors are low enough for washed-out (over-exposed) colours; value floors keep
  // dark shadows out of the colour masks (they belong to black).
  (void)p.add_colour({Colour::kRed, {170, 8, 90, 255, 70, 255}, true, true});  // wraps at 180
  (void)p.add_colour({Colour::kOrange, {9, 20, 110, 255, 90, 255}, true, true});
  (void)p.add_colour({Colour::kYellow, {21, 34, 90, 255, 90, 255}, true, true});
  (void)p.add_colour({Colour::kGreen, {38, 88, 70, 255, 50, 255}, true, true});
  (void)p.add_colour({Colour::kBlue, {95, 127, 80, 255, 50, 255}, true, true});
  (void)p.add_colour({Colour::kPurple, {128, 162, 50, 255, 50, 255}, true, true});
  (void)p.add_colour({Colour::kBlack, {0, 179, 0, 255, 0, 75}, true, false});
  return p;
}

bool VisionParams::add_colour(const ColourRange& c) {
  if (colour_count >= kMaxColours) return false;
  colours[colour_count++] = c;
  return true;
}

int VisionParams::find_colour(msg::Colour colour) const {
  for (std::size_t i = 0; i < colour_count; ++i) {
    if (colours[i].colour == colour) return static_cast<int>(i);
  }
  return -1;
}

namespace {
bool kernel_ok(int k) { return k == 0 || (k >= 1 && k <= 31); }
}  // namespace

std::optional<std::string> VisionParams::validate() const {
  if (colour_count > kMaxColours) return "colour_count exceeds kMaxColours";
  for (std::size_t i = 0; i < colour_count; ++i) {
    const HsvRange& r = colours[i].hsv;
    if (r.h_min > 179 || r.h_max > 179) return "hue bounds must be 0..179 (OpenCV 8-bit hue)";
    if (r.s_min > r.s_max) return "s_min > s_max";
    if (r.v_min > r.v_max) return "v_min > v_max";
    if (colours[i].colour == msg::Colour::kUnknown) return "colour range without a colour";
  }
  if (!kernel_ok(open_kernel_px) || !kernel_ok(close_kernel_px)) {
    return "morphology kernels must be 0 (off) or 1..31 px";
  }
  if (blur_kernel_px != 0 &&
      (blur_kernel_px < 3 || blur_kernel_px % 2 == 0 || blur_kernel_px > 31)) {
    return "blur_kernel_px must be 0 (off) or odd 3..31";
  }
  if (!(min_area_fraction > 0.0 && min_area_fraction < 1.0)) return "min_area_fraction in (0,1)";
  if (!(buoy_min_area_fraction > 0.0 && buoy_min_area_fraction < 1.0)) {
    return "buoy_min_area_fraction in (0,1)";
  }
  if (!(buoy_min_solidity >= 0.0 && buoy_min_solidity <= 1.0)) return "buoy_min_solidity in [0,1]";
  if (edge_margin_px < 0) return "edge_margin_px must be >= 0";
  if (!(hfov_deg > 1.0 && hfov_deg < 179.0)) return "hfov_deg must be in (1, 179)";
  if (!std::isfinite(mount_yaw_deg)) return "mount_yaw_deg must be finite";
  const ShapeParams& s = shape;
  if (!(s.approx_epsilon_fraction > 0.0 && s.approx_epsilon_fraction < 0.2)) {
    return "approx_epsilon_fraction in (0, 0.2)";
  }
  if (!(s.cross_min_solidity < s.cross_max_solidity &&
        s.cross_max_solidity < s.convex_min_solidity)) {
    return "need cross_min_solidity < cross_max_solidity < convex_min_solidity";
  }
  if (!(s.triangle_max_extent < s.circle_max_extent &&
        s.circle_max_extent < s.rectangle_min_extent)) {
    return "need triangle_max_extent < circle_max_extent < rectangle_min_extent";
  }
  if (!(s.min_fill_ratio >= 0.0 && s.min_fill_ratio <= 1.0)) return "min_fill_ratio in [0,1]";
  if (!(s.island_min_hole_fraction >= 0.0 && s.island_min_hole_fraction <= 1.0)) {
    return "island_min_hole_fraction in [0,1]";
  }
  const BackgroundParams& b = background;
  if (b.strips < 1 || b.strips > BackgroundParams::kMaxStrips) {
    return "background.strips in 1..16";
  }
  if (b.sample_step_px < 1 || b.sample_step_px > 64) return "background.sample_step_px in 1..64";
  if (b.max_samples < 100 || b.max_samples > 1000000) {
    return "background.max_samples in 100..1000000";
  }
  if (!(b.min_share > 0.0 && b.min_share <= 1.0)) return "background.min_share in (0,1]";
  if (!(b.reject_sigma >= 0.0 && b.reject_sigma <= 10.0)) {
    return "background.reject_sigma in [0,10]";
  }
  if (!(b.min_sigma >= 0.0 && b.min_sigma <= b.max_sigma && b.max_sigma <= 128.0)) {
    return "need 0 <= background.min_sigma <= background.max_sigma <= 128";
  }
  if (b.max_saturation < 0 || b.max_saturation > 255) return "background.max_saturation in 0..255";
  return {};
}

double camera_bearing_deg(double x_px, int image_width_px, double hfov_deg) {
  const double half_width = 0.5 * static_cast<double>(image_width_px);
  const double focal_px = half_width / std::tan(core::deg_to_rad(0.5 * hfov_deg));
  return core::rad_to_deg(std::atan((x_px - half_width) / focal_px));
}

double body_bearing_deg(double x_px, int image_width_px, double hfov_deg, double mount_yaw_deg) {
  return core::wrap_deg(camera_bearing_deg(x_px, image_width_px, hfov_deg) + mount_yaw_deg);
}

}  // namespace coxswain::perception
