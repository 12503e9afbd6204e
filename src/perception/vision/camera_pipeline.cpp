// SPDX-License-Identifier: Apache-2.0
#include "coxswain/perception/camera_pipeline.hpp"

#include <algorithm>

namespace coxswain::perception {

VisionParams camera_vision_params(const VisionParams& vision, double hfov_deg,
                                  const core::MountTransform& mount) {
  VisionParams p = vision;
  p.hfov_deg = hfov_deg;
  p.mount_yaw_deg = mount.yaw_deg;
  return p;
}

CameraPipeline::CameraPipeline(const VisionParams& params)
    : params_(params), masker_(params), markers_(params), buoys_(params) {}

CameraPipeline::CameraPipeline(const VisionParams& vision, double hfov_deg,
                               const core::MountTransform& mount)
    : CameraPipeline(camera_vision_params(vision, hfov_deg, mount)) {}

bool CameraPipeline::process(const cv::Mat& bgr, core::TimeNs stamp_ns,
                             msg::CameraDetections& out) {
  ++frames_;
  out.count = 0;
  out.stamp_ns = stamp_ns;
  out.frame_index = frames_;
  stats_ = {};
  markers_.reset_stats();
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
    if (!range.markers && !range.buoys) continue;
    const ColourMasker::MaskView view = masker_.mask(c);
    if (view.mask.empty()) continue;
    if (range.markers) markers_.scan_mask(range.colour, view.mask, view.offset, width, height, out);
    if (range.buoys) buoys_.scan_mask(range.colour, view.mask, view.offset, width, height, out);
  }
  stats_.markers = markers_.last_stats();
  return true;
}

}  // namespace coxswain::perception
