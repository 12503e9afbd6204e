// SPDX-License-Identifier: Apache-2.0
#include <opencv2/imgproc.hpp>

#include "coxswain/perception/vision_colour_mask.hpp"

namespace coxswain::perception {
namespace {

cv::Mat make_kernel(int size_px) {
  if (size_px <= 1) return {};
  return cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(size_px, size_px));
}

}  // namespace

ColourMasker::ColourMasker(const VisionParams& params)
    : blur_kernel_px_(params.blur_kernel_px),
      open_kernel_(make_kernel(params.open_kernel_px)),
      close_kernel_(make_kernel(params.close_kernel_px)) {}

bool ColourMasker::set_frame(const cv::Mat& bgr) {
  if (bgr.empty() || bgr.type() != CV_8UC3) return false;
  if (blur_kernel_px_ >= 3) {
    cv::GaussianBlur(bgr, blurred_, cv::Size(blur_kernel_px_, blur_kernel_px_), 0.0);
    cv::cvtColor(blurred_, hsv_, cv::COLOR_BGR2HSV);
  } else {
    cv::cvtColor(bgr, hsv_, cv::COLOR_BGR2HSV);
  }
  return true;
}

const cv::Mat& ColourMasker::mask(const HsvRange& r) {
  if (r.wraps()) {
    // Red straddles hue 0/180: two boxes, [h_min, 179] and [0, h_max], OR-ed.
    cv::inRange(hsv_, cv::Scalar(r.h_min, r.s_min, r.v_min), cv::Scalar(179, r.s_max, r.v_max),
                mask_);
    cv::inRange(hsv_, cv::Scalar(0, r.s_min, r.v_min), cv::Scalar(r.h_max, r.s_max, r.v_max),
                mask_wrap_);
    cv::bitwise_or(mask_, mask_wrap_, mask_);
  } else {
    cv::inRange(hsv_, cv::Scalar(r.h_min, r.s_min, r.v_min), cv::Scalar(r.h_max, r.s_max, r.v_max),
                mask_);
  }
  if (!open_kernel_.empty()) {
    cv::morphologyEx(mask_, morph_, cv::MORPH_OPEN, open_kernel_);
    cv::swap(mask_, morph_);
  }
  if (!close_kernel_.empty()) {
    cv::morphologyEx(mask_, morph_, cv::MORPH_CLOSE, close_kernel_);
    cv::swap(mask_, morph_);
  }
  return mask_;
}

}  // namespace coxswain::perception
