// SPDX-License-Identifier: Apache-2.0
#pragma once
// Camera frames for the people watching (the recording's and the live view's /camera/image):
// a thread takes the camera's newest frame at most `image_rate_hz`, scales it down to
// `image_max_width_px`, encodes it as JPEG at `image_jpeg_quality` and hands it, with the
// detections found in that very frame, to a sink. It never touches the camera thread beyond
// LatestFrame's one copy, so a slow encode costs the viewers a frame, never the detectors one.
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <opencv2/core.hpp>
#include <span>
#include <thread>
#include <vector>

#include "coxswain/config/devices_config.hpp"
#include "coxswain/core/time.hpp"
#include "coxswain/drivers/camera/camera_driver.hpp"
#include "coxswain/msg/camera_detections.hpp"

namespace coxswain::drivers::camera {

/// Scales `bgr` down to at most `max_width_px` (never up) and encodes it as JPEG into `out`.
/// Returns the scale applied (encoded width / frame width), 0 when the frame is empty or the
/// encoder failed.
double encode_viewer_jpeg(const cv::Mat& bgr, std::uint32_t max_width_px,
                          std::uint32_t jpeg_quality, std::vector<std::uint8_t>& out);

class ViewerImages {
 public:
  using Sink = std::function<void(core::TimeNs stamp_ns, std::span<const std::uint8_t> jpeg,
                                  const msg::CameraDetections& detections, double scale)>;
  /// `frames` must outlive this. Nothing runs while `config.image_rate_hz` is 0.
  ViewerImages(const config::CameraDeviceConfig& config, const LatestFrame& frames, Sink sink);
  ~ViewerImages();
  ViewerImages(const ViewerImages&) = delete;
  ViewerImages& operator=(const ViewerImages&) = delete;

  void start();
  /// Stops and joins the thread (at most one encode's wait). Idempotent.
  void stop();
  /// Images handed to the sink so far.
  [[nodiscard]] std::uint64_t sent() const;

 private:
  void run();

  config::CameraDeviceConfig config_;
  const LatestFrame& frames_;
  Sink sink_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_requested_ = false;
  std::uint64_t sent_ = 0;
  std::thread thread_;
};

}  // namespace coxswain::drivers::camera
