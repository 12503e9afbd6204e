// SPDX-License-Identifier: Apache-2.0
#pragma once
// Coloured buoys (red, green, yellow, orange, purple...) as blobs with a body-frame bearing.
// Course 1 and 2 of docs/missions.md track a purple buoy by its bearing only, so shape is not
// judged beyond a solidity floor; a buoy half out of the frame is kept unless buoy_reject_edge is
// set.
#include <opencv2/core.hpp>
#include <vector>

#include "coxswain/core/time.hpp"
#include "coxswain/msg/camera_detections.hpp"
#include "coxswain/perception/vision_colour_mask.hpp"
#include "coxswain/perception/vision_params.hpp"

namespace coxswain::perception {

/// Detections have shape kBuoy, sorted by area (largest first). Not thread-safe.
class BuoyDetector {
 public:
  explicit BuoyDetector(const VisionParams& params = VisionParams::defaults());

  /// Fills `out` (cleared first) from `bgr` (CV_8UC3). Returns false for an unusable image.
  [[nodiscard]] bool detect(const cv::Mat& bgr, core::TimeNs stamp_ns, msg::CameraDetections& out);

  /// Scans one colour's ready-made mask (CV_8UC1 of a `width` x `height` frame, e.g. from a
  /// ColourMasker shared with the marker detector) and adds its buoys to `out` without clearing
  /// it. For CameraPipeline, which builds each mask once for both detectors.
  /// `offset` places the mask's top-left pixel in the frame (ColourMasker::MaskView).
  void scan_mask(msg::Colour colour, const cv::Mat& mask, cv::Point offset, int width, int height,
                 msg::CameraDetections& out);

  /// The largest buoy of `colour`, if any, from a filled detection list.
  [[nodiscard]] static const msg::Detection* largest(const msg::CameraDetections& detections,
                                                     msg::Colour colour);

 private:
  VisionParams params_;
  ColourMasker masker_;
  std::vector<std::vector<cv::Point>> contours_;
  std::vector<cv::Vec4i> hierarchy_;
  std::vector<cv::Point> hull_;
};

}  // namespace coxswain::perception
