// SPDX-License-Identifier: Apache-2.0
#pragma once
// Shape of one contour: measured features, then a rule set over them. Vertex count alone (the
// source team's method) confuses a blurred square with a circle and a cut shape with another, so
// the rules combine vertex count with convexity, solidity, extent, circularity and deep
// concavities.
#include <opencv2/core.hpp>
#include <utility>
#include <vector>

#include "coxswain/msg/camera_detections.hpp"
#include "coxswain/perception/vision_params.hpp"

namespace coxswain::perception {

/// What the rules look at. All ratios are dimensionless.
struct ShapeFeatures {
  double area_px = 0.0;         // contour area (holes not subtracted)
  int vertices = 0;             // after approxPolyDP with epsilon = fraction * perimeter
  bool convex_polygon = false;  // the approximated polygon is convex
  double solidity = 0.0;        // area / convex hull area
  double extent = 0.0;          // area / minimum-area (rotated) rectangle area
  double circularity = 0.0;     // 4 pi hull_area / hull_perimeter^2 (1 for a circle)
  int deep_defects = 0;         // convexity defects deeper than cross_min_defect_depth*sqrt(A)
};

/// Pure rule set. Returns the shape (kUnknown when nothing fits: pentagon, star, semicircle...)
/// and a score in 0..1 saying how well the features match the ideal of that shape.
[[nodiscard]] std::pair<msg::Shape, float> classify_shape(const ShapeFeatures& f,
                                                          const ShapeParams& p);

/// Measures ShapeFeatures of a contour. Keeps its scratch vectors between calls, so steady-state
/// use does not allocate. Not thread-safe (one per detector).
class ShapeAnalyzer {
 public:
  [[nodiscard]] ShapeFeatures measure(const std::vector<cv::Point>& contour, const ShapeParams& p);

 private:
  std::vector<cv::Point> approx_;
  std::vector<cv::Point> hull_;
  std::vector<int> hull_idx_;
  std::vector<cv::Vec4i> defects_;
};

}  // namespace coxswain::perception
