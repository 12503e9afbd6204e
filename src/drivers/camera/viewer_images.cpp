// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/camera/viewer_images.hpp"

#include "coxswain/drivers/camera/image_io.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <utility>

namespace coxswain::drivers::camera {

double encode_viewer_jpeg(const cv::Mat& bgr, std::uint32_t max_width_px,
                          std::uint32_t jpeg_quality, std::vector<std::uint8_t>& out) {
  out.clear();
  if (bgr.empty() || bgr.cols <= 0 || max_width_px == 0) return 0.0;
  double scale = 1.0;
  const cv::Mat* image = &bgr;
  cv::Mat scaled;
  if (static_cast<std::uint32_t>(bgr.cols) > max_width_px) {
    scale = static_cast<double>(max_width_px) / static_cast<double>(bgr.cols);
    const int height = std::max(1, static_cast<int>(std::lround(bgr.rows * scale)));
    cv::resize(bgr, scaled, cv::Size(static_cast<int>(max_width_px), height), 0.0, 0.0,
               cv::INTER_AREA);
    image = &scaled;
  }
  const ImageIoModule* io = image_io();
  if (io == nullptr ||
      !io->encode_jpeg(*image, static_cast<int>(std::clamp<std::uint32_t>(jpeg_quality, 1, 100)),
                       out)) {
    out.clear();
    return 0.0;
  }
  return scale;
}

ViewerImages::ViewerImages(const config::CameraDeviceConfig& config, const LatestFrame& frames,
                           Sink sink)
    : config_(config), frames_(frames), sink_(std::move(sink)) {}

ViewerImages::~ViewerImages() { stop(); }

void ViewerImages::start() {
  if (thread_.joinable() || !(config_.image_rate_hz > 0.0) || !sink_) return;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_requested_ = false;
  }
  thread_ = std::thread([this] { run(); });
}

void ViewerImages::stop() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_requested_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

std::uint64_t ViewerImages::sent() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return sent_;
}

void ViewerImages::run() {
  const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
      std::chrono::duration<double>(1.0 / config_.image_rate_hz));
  cv::Mat frame;
  msg::CameraDetections detections;
  std::vector<std::uint8_t> jpeg;
  std::uint64_t seen = 0;
  auto next = std::chrono::steady_clock::now();
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      if (wake_.wait_until(lock, next, [this] { return stop_requested_; })) return;
    }
    next += period;
    // Fell behind (a slow encode): start the cadence again from now, no burst to catch up.
    if (const auto now = std::chrono::steady_clock::now(); next < now) next = now + period;
    core::TimeNs stamp_ns = 0;
    std::uint64_t sequence = 0;
    if (frames_.sequence() == seen || !frames_.read(frame, stamp_ns, sequence, &detections)) {
      continue;
    }
    seen = sequence;
    const double scale =
        encode_viewer_jpeg(frame, config_.image_max_width_px, config_.image_jpeg_quality, jpeg);
    if (scale <= 0.0) continue;
    sink_(stamp_ns, jpeg, detections, scale);
    const std::lock_guard<std::mutex> lock(mutex_);
    ++sent_;
  }
}

}  // namespace coxswain::drivers::camera
