// SPDX-License-Identifier: Apache-2.0
#include "coxswain/perception/buoy_detector.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "coxswain/perception/marker_detector.hpp"

namespace coxswain::perception {

BuoyDetector::BuoyDetector(const VisionParams& params) : params_(params), masker_(params) {
  contours_.reserve(256);
  hierarchy_.reserve(256);
}

bool BuoyDetector::detect(const cv::Mat& bgr, core::TimeNs stamp_ns, msg::CameraDetections& out) {
  out.count = 0;
  out.stamp_ns = stamp_ns;
  ++out.frame_index;
  if (!masker_.set_frame(bgr)) {
    out.image_width_px = 0;
    out.image_height_px = 0;
    return false;
  }
  const int width = bgr.cols;
  const int height = bgr.rows;
  out.image_width_px = static_cast<std::uint16_t>(std::min(width, 65535));
  out.image_height_px = static_cast<std::uint16_t>(std::min(height, 65535));
  for (std::size_t c = 0; c < params_.colour_count; ++c) {
    const ColourRange& range = params_.colours[c];
    if (!range.buoys) continue;
    const ColourMasker::MaskView view = masker_.mask(c);
    if (!view.mask.empty()) scan_mask(range.colour, view.mask, view.offset, width, height, out);
  }
  return true;
}

void BuoyDetector::scan_mask(msg::Colour colour, const cv::Mat& mask, cv::Point offset, int width,
                             int height, msg::CameraDetections& out) {
  const double min_area_px =
      params_.buoy_min_area_fraction * static_cast<double>(width) * static_cast<double>(height);
  const int margin = params_.edge_margin_px;
  // Outer boundaries of every component, islands in holes included (a buoy in front of a larger
  // blob of its colour).
  cv::findContours(mask, contours_, hierarchy_, cv::RETR_CCOMP, cv::CHAIN_APPROX_SIMPLE, offset);
  for (std::size_t i = 0; i < contours_.size(); ++i) {
    if (hierarchy_[i][3] >= 0) continue;
    const std::vector<cv::Point>& contour = contours_[i];
    const double area_px = cv::contourArea(contour);
    if (area_px < min_area_px) continue;
    const cv::Rect box = cv::boundingRect(contour);
    if (params_.buoy_reject_edge &&
        (box.x <= margin || box.y <= margin || box.x + box.width >= width - margin ||
         box.y + box.height >= height - margin)) {
      continue;
    }
    cv::convexHull(contour, hull_);
    const double hull_area_px = cv::contourArea(hull_);
    const double solidity = hull_area_px > 0.0 ? area_px / hull_area_px : 0.0;
    if (solidity < params_.buoy_min_solidity) continue;
    const cv::Moments m = cv::moments(contour);
    const double cx_px = m.m10 / m.m00 + 0.5;  // continuous coordinates, see MarkerDetector
    const double cy_px = m.m01 / m.m00 + 0.5;
    msg::Detection d;
    d.colour = colour;
    d.shape = msg::Shape::kBuoy;
    d.bearing_deg =
        static_cast<float>(body_bearing_deg(cx_px, width, params_.hfov_deg, params_.mount_yaw_deg));
    d.center_x_px = static_cast<float>(cx_px);
    d.center_y_px = static_cast<float>(cy_px);
    d.width_px = static_cast<float>(box.width);
    d.height_px = static_cast<float>(box.height);
    d.area_px = static_cast<float>(area_px);
    d.score = static_cast<float>(solidity);
    (void)insert_by_area(out, d);
  }
}

const msg::Detection* BuoyDetector::largest(const msg::CameraDetections& detections,
                                            msg::Colour colour) {
  const msg::Detection* best = nullptr;
  const std::size_t n = std::min<std::size_t>(detections.count, detections.detections.size());
  for (std::size_t i = 0; i < n; ++i) {
    const msg::Detection& d = detections.detections[i];
    if (d.colour != colour) continue;
    if (best == nullptr || d.area_px > best->area_px) best = &d;
  }
  return best;
}

}  // namespace coxswain::perception
