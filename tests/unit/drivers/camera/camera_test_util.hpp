// SPDX-License-Identifier: Apache-2.0
#pragma once
// Shared by the camera driver tests: a scratch directory removed at the end, generated frames with
// a buoy at a known column, and polling for a condition with a generous deadline.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <functional>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <thread>

#include "vision_scene.hpp"

namespace coxswain::drivers::camera::testing {

/// A fresh directory under the system temp folder, deleted with everything in it on destruction.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& tag) {
    static std::atomic<int> counter{0};
    path_ = std::filesystem::temp_directory_path() /
            ("coxswain_camera_" + tag + "_" + std::to_string(::getpid()) + "_" +
             std::to_string(counter.fetch_add(1)));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// Water with one purple buoy centred at column `x_px` (diameter a fifth of the height).
inline cv::Mat buoy_frame(int width, int height, float x_px) {
  namespace gen = perception::testing;
  cv::Mat img = gen::water_background(width, height);
  gen::draw_shape(img, msg::Shape::kCircle, {x_px, 0.5F * static_cast<float>(height)},
                  0.2F * static_cast<float>(height), 0, gen::paint_bgr(msg::Colour::kPurple));
  return img;
}

/// Polls `condition` every 5 ms until it holds or `timeout_s` passes; returns its last value.
inline bool wait_until(const std::function<bool()>& condition, double timeout_s = 10.0) {
  const auto deadline = std::chrono::steady_clock::now() +
                        std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>(timeout_s));
  while (std::chrono::steady_clock::now() < deadline) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return condition();
}

/// Writes `frames` as an MJPG .avi with cv::VideoWriter; false when this OpenCV cannot.
bool write_mjpg_avi(const std::filesystem::path& file, const std::vector<cv::Mat>& frames,
                    double fps);

}  // namespace coxswain::drivers::camera::testing
