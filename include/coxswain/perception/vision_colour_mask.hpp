// SPDX-License-Identifier: Apache-2.0
#pragma once
// BGR frame -> HSV once, then a cleaned binary mask per colour range. Shared by the marker and
// buoy detectors. Buffers are members, reused frame to frame (OpenCV reallocates only when the
// image size changes). Not thread-safe: one instance per detector.
#include <opencv2/core.hpp>

#include "coxswain/perception/vision_params.hpp"

namespace coxswain::perception {

class ColourMasker {
 public:
  explicit ColourMasker(const VisionParams& params);

  /// Blurs and converts `bgr` (CV_8UC3) to HSV. Returns false for an empty or non-BGR image.
  [[nodiscard]] bool set_frame(const cv::Mat& bgr);

  /// Mask (CV_8UC1, 255 = in range) of `range` over the current frame, after opening and
  /// closing. Valid until the next call.
  const cv::Mat& mask(const HsvRange& range);

  [[nodiscard]] const cv::Mat& hsv() const { return hsv_; }

 private:
  int blur_kernel_px_;
  cv::Mat open_kernel_;
  cv::Mat close_kernel_;
  cv::Mat blurred_;
  cv::Mat hsv_;
  cv::Mat mask_;
  cv::Mat mask_wrap_;
  cv::Mat morph_;
};

}  // namespace coxswain::perception
