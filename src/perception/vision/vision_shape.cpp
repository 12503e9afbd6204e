// SPDX-License-Identifier: Apache-2.0
#include "coxswain/perception/vision_shape.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "coxswain/core/angles.hpp"

namespace coxswain::perception {
namespace {

float clamp01(double x) { return static_cast<float>(std::clamp(x, 0.0, 1.0)); }

}  // namespace

ShapeFeatures ShapeAnalyzer::measure(const std::vector<cv::Point>& contour, const ShapeParams& p) {
  ShapeFeatures f;
  if (contour.size() < 3) return f;
  f.area_px = cv::contourArea(contour);
  if (f.area_px <= 0.0) return f;
  const double perimeter_px = cv::arcLength(contour, true);
  cv::approxPolyDP(contour, approx_, p.approx_epsilon_fraction * perimeter_px, true);
  f.vertices = static_cast<int>(approx_.size());
  f.convex_polygon = approx_.size() >= 3 && cv::isContourConvex(approx_);

  cv::convexHull(contour, hull_);
  const double hull_area_px = cv::contourArea(hull_);
  const double hull_perimeter_px = cv::arcLength(hull_, true);
  if (hull_area_px > 0.0) f.solidity = f.area_px / hull_area_px;
  // The hull's perimeter, unlike the pixel chain's, is not inflated by staircase steps, so a
  // digitised circle scores close to 1 and a square close to pi/4.
  if (hull_perimeter_px > 0.0) {
    f.circularity = 4.0 * core::kPi * hull_area_px / (hull_perimeter_px * hull_perimeter_px);
  }
  const cv::RotatedRect box = cv::minAreaRect(contour);
  const double box_area_px =
      static_cast<double>(box.size.width) * static_cast<double>(box.size.height);
  if (box_area_px > 0.0) f.extent = f.area_px / box_area_px;

  // Deep concavities: a plus-shaped cross has exactly four, a star five, a convex shape none.
  if (contour.size() > 3 && f.solidity < p.convex_min_solidity) {
    cv::convexHull(contour, hull_idx_, false, false);
    defects_.clear();
    try {
      if (hull_idx_.size() > 3) cv::convexityDefects(contour, hull_idx_, defects_);
    } catch (const cv::Exception&) {
      // Non-monotonic hull indices on a self-touching contour: leave the count at zero, which
      // makes the contour "not a cross" rather than failing the frame.
      defects_.clear();
    }
    const double min_depth_px = p.cross_min_defect_depth * std::sqrt(f.area_px);
    for (const cv::Vec4i& d : defects_) {
      // convexityDefects reports depth in 1/256 px fixed point.
      if (static_cast<double>(d[3]) / 256.0 >= min_depth_px) ++f.deep_defects;
    }
  }
  return f;
}

std::pair<msg::Shape, float> classify_shape(const ShapeFeatures& f, const ShapeParams& p) {
  using msg::Shape;
  if (f.area_px <= 0.0 || f.vertices < 3) return {Shape::kUnknown, 0.0F};

  // Cross: concave, about 5/9 solid, four deep notches (one between each pair of arms).
  if (f.solidity >= p.cross_min_solidity && f.solidity <= p.cross_max_solidity &&
      f.deep_defects == 4 && !f.convex_polygon) {
    const double vertex_fit = 1.0 - std::abs(f.vertices - 12) / 12.0;
    return {Shape::kCross, clamp01((1.0 - std::abs(f.solidity - 0.556) * 2.0) * vertex_fit)};
  }
  if (f.solidity < p.convex_min_solidity) return {Shape::kUnknown, 0.0F};

  // Any triangle fills exactly half of its minimum-area rectangle; blur rounds the corners and
  // may add a vertex or two but keeps the extent.
  if (f.extent <= p.triangle_max_extent && f.vertices <= 5) {
    return {Shape::kTriangle, clamp01((1.0 - std::abs(f.extent - 0.5) * 4.0) * f.solidity)};
  }
  // Quadrilateral: exactly four convex corners (a perspective-warped square is a trapezoid with a
  // lower extent), or a square whose blurred corners add vertices but which still fills its box.
  const bool quad = f.vertices == 4 && f.convex_polygon && f.extent >= 0.70;
  const bool boxy = f.vertices >= 4 && f.vertices <= 8 && f.extent >= p.rectangle_min_extent;
  if (quad || boxy) return {Shape::kRectangle, clamp01(f.extent * f.solidity)};

  // Circle (or the ellipse a circle becomes under perspective): round hull, pi/4 of its box,
  // many vertices. A semicircle (0.75) and a quarter disc (0.77) fail the circularity floor.
  if (f.circularity >= p.circle_min_circularity && f.extent <= p.circle_max_extent &&
      f.extent >= 0.70 && f.vertices >= 6) {
    return {Shape::kCircle, clamp01(f.circularity * f.solidity)};
  }
  return {Shape::kUnknown, 0.0F};
}

}  // namespace coxswain::perception
