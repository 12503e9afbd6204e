// SPDX-License-Identifier: Apache-2.0
#include "coxswain/perception/marker_detector.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>

namespace coxswain::perception {
namespace {

bool touches_edge(const cv::Rect& box, int width, int height, int margin_px) {
  return box.x <= margin_px || box.y <= margin_px || box.x + box.width >= width - margin_px ||
         box.y + box.height >= height - margin_px;
}

}  // namespace

bool insert_by_area(msg::CameraDetections& out, const msg::Detection& d) {
  constexpr std::size_t kMax = msg::CameraDetections::kMaxDetections;
  bool kept_all = true;
  std::size_t n = out.count;
  if (n >= kMax) {
    if (d.area_px <= out.detections[kMax - 1].area_px) return false;
    n = kMax - 1;  // the smallest entry makes room
    kept_all = false;
  }
  std::size_t pos = n;
  while (pos > 0 && out.detections[pos - 1].area_px < d.area_px) {
    out.detections[pos] = out.detections[pos - 1];
    --pos;
  }
  out.detections[pos] = d;
  out.count = static_cast<std::uint32_t>(n + 1);
  return kept_all;
}

std::optional<msg::Detection> find_target(const msg::CameraDetections& detections,
                                          msg::Colour colour, msg::Shape shape) {
  std::optional<msg::Detection> best;
  const std::size_t n = std::min<std::size_t>(detections.count, detections.detections.size());
  for (std::size_t i = 0; i < n; ++i) {
    const msg::Detection& d = detections.detections[i];
    if (colour != msg::Colour::kUnknown && d.colour != colour) continue;
    if (shape != msg::Shape::kUnknown && d.shape != shape) continue;
    if (!best || d.area_px > best->area_px) best = d;
  }
  return best;
}

MarkerDetector::MarkerDetector(const VisionParams& params) : params_(params), masker_(params) {
  contours_.reserve(256);
  hierarchy_.reserve(256);
}

bool MarkerDetector::detect(const cv::Mat& bgr, core::TimeNs stamp_ns, msg::CameraDetections& out) {
  out.count = 0;
  out.stamp_ns = stamp_ns;
  ++out.frame_index;
  stats_ = {};
  if (!masker_.set_frame(bgr)) {
    out.image_width_px = 0;
    out.image_height_px = 0;
    return false;
  }
  out.image_width_px = static_cast<std::uint16_t>(std::min(bgr.cols, 65535));
  out.image_height_px = static_cast<std::uint16_t>(std::min(bgr.rows, 65535));
  for (std::size_t c = 0; c < params_.colour_count; ++c) {
    const ColourRange& range = params_.colours[c];
    if (!range.markers) continue;
    const ColourMasker::MaskView view = masker_.mask(c);
    if (!view.mask.empty())
      scan_mask(range.colour, view.mask, view.offset, bgr.cols, bgr.rows, out);
  }
  return true;
}

bool MarkerDetector::placard_island(std::size_t island, int root, int width, int height) const {
  // The blob around reaches the frame border, as water does ...
  if (!touches_edge(cv::boundingRect(contours_[static_cast<std::size_t>(root)]), width, height,
                    params_.edge_margin_px)) {
    return false;
  }
  // ... and the hole (the placard) holds this one island, filling a fair part of it (a placard
  // carries one glyph; a letter's bowls come in twos or are small).
  const int hole = hierarchy_[island][3];
  if (hierarchy_[island][0] >= 0 || hierarchy_[island][1] >= 0) return false;
  const double hole_px = cv::contourArea(contours_[static_cast<std::size_t>(hole)]);
  return hole_px > 0.0 &&
         cv::contourArea(contours_[island]) >= params_.shape.island_min_hole_fraction * hole_px;
}

void MarkerDetector::scan_mask(msg::Colour colour, const cv::Mat& mask, cv::Point offset, int width,
                               int height, msg::CameraDetections& out) {
  // RETR_TREE gives each outer contour its holes, so the filled area (and with it the fill
  // ratio that tells a solid shape from an outline ring) is exact. An island inside a hole is a
  // marker when it looks like a glyph on a placard floating in water the background model did
  // not fully take out (see placard_island); otherwise (the bowls of a letter B in a blue disc)
  // it is a glyph artefact.
  cv::findContours(mask, contours_, hierarchy_, cv::RETR_TREE, cv::CHAIN_APPROX_SIMPLE, offset);
  const double frame_area_px = static_cast<double>(width) * static_cast<double>(height);
  const double min_area_px = params_.min_area_fraction * frame_area_px;
  for (std::size_t i = 0; i < contours_.size(); ++i) {
    int depth = 0;
    int root = static_cast<int>(i);
    while (hierarchy_[static_cast<std::size_t>(root)][3] >= 0) {
      root = hierarchy_[static_cast<std::size_t>(root)][3];
      ++depth;
    }
    if (depth % 2 == 1) continue;  // a hole, handled with its parent
    if (depth > 0 && !placard_island(i, root, width, height)) continue;
    ++stats_.contours;
    const std::vector<cv::Point>& contour = contours_[i];
    const double outer_area_px = cv::contourArea(contour);
    if (outer_area_px < min_area_px) {
      ++stats_.too_small;
      continue;
    }
    const cv::Rect box = cv::boundingRect(contour);
    if (touches_edge(box, width, height, params_.edge_margin_px)) {
      ++stats_.cut_by_edge;
      continue;
    }
    double holes_px = 0.0;
    for (int h = hierarchy_[i][2]; h >= 0; h = hierarchy_[static_cast<std::size_t>(h)][0]) {
      holes_px += cv::contourArea(contours_[static_cast<std::size_t>(h)]);
    }
    const double filled_px = outer_area_px - holes_px;
    const double fill_ratio = filled_px / outer_area_px;
    if (fill_ratio < params_.shape.min_fill_ratio) {
      ++stats_.outline_only;
      continue;
    }
    const ShapeFeatures features = analyzer_.measure(contour, params_.shape);
    const auto [shape, shape_score] = classify_shape(features, params_.shape);
    if (shape == msg::Shape::kUnknown) {
      ++stats_.unknown_shape;
      continue;
    }
    const cv::Moments m = cv::moments(contour);
    // Contour points are pixel indices; +0.5 moves to the continuous frame where the left image
    // edge is x = 0 and the right edge is x = width (the bearing model's convention).
    const double cx_px = m.m10 / m.m00 + 0.5;
    const double cy_px = m.m01 / m.m00 + 0.5;
    msg::Detection d;
    d.colour = colour;
    d.shape = shape;
    d.bearing_deg =
        static_cast<float>(body_bearing_deg(cx_px, width, params_.hfov_deg, params_.mount_yaw_deg));
    d.center_x_px = static_cast<float>(cx_px);
    d.center_y_px = static_cast<float>(cy_px);
    d.width_px = static_cast<float>(box.width);
    d.height_px = static_cast<float>(box.height);
    d.area_px = static_cast<float>(filled_px);
    d.score = shape_score * static_cast<float>(std::min(1.0, fill_ratio));
    if (!insert_by_area(out, d)) ++stats_.dropped;
  }
}

}  // namespace coxswain::perception
