// SPDX-License-Identifier: Apache-2.0
// The viewers' camera images: scaled down (never up), JPEG that decodes back, the detections of
// the very frame passed along, nothing at all when the rate is 0.
#include "coxswain/drivers/camera/viewer_images.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <thread>

namespace coxswain::drivers::camera {
namespace {

cv::Mat test_frame(int width, int height) {
  cv::Mat frame(height, width, CV_8UC3, cv::Scalar(40, 120, 200));
  frame(cv::Rect(width / 4, height / 4, width / 2, height / 2)).setTo(cv::Scalar(0, 0, 255));
  return frame;
}

TEST(ViewerJpeg, ScalesDownToTheWidthAndDecodesBack) {
  std::vector<std::uint8_t> jpeg;
  EXPECT_DOUBLE_EQ(encode_viewer_jpeg(test_frame(1280, 960), 640, 75, jpeg), 0.5);
  ASSERT_GT(jpeg.size(), 4U);
  EXPECT_EQ(jpeg[0], 0xFF);
  EXPECT_EQ(jpeg[1], 0xD8);  // a JPEG start-of-image
  const cv::Mat back = cv::imdecode(jpeg, cv::IMREAD_COLOR);
  EXPECT_EQ(back.cols, 640);
  EXPECT_EQ(back.rows, 480);
  // The red square is still red in the middle.
  const cv::Vec3b mid = back.at<cv::Vec3b>(240, 320);
  EXPECT_GT(mid[2], 200);
  EXPECT_LT(mid[0], 60);

  // Smaller than the limit: kept as it is, never scaled up.
  EXPECT_DOUBLE_EQ(encode_viewer_jpeg(test_frame(320, 240), 640, 75, jpeg), 1.0);
  EXPECT_EQ(cv::imdecode(jpeg, cv::IMREAD_COLOR).cols, 320);
  // A lower quality is a smaller file.
  std::vector<std::uint8_t> low;
  std::vector<std::uint8_t> high;
  (void)encode_viewer_jpeg(test_frame(640, 480), 640, 10, low);
  (void)encode_viewer_jpeg(test_frame(640, 480), 640, 95, high);
  EXPECT_LT(low.size(), high.size());
  // Nothing to encode.
  EXPECT_DOUBLE_EQ(encode_viewer_jpeg(cv::Mat(), 640, 75, jpeg), 0.0);
  EXPECT_TRUE(jpeg.empty());
}

TEST(ViewerImages, TheNewestFrameGoesToTheSinkWithItsOwnDetections) {
  LatestFrame frames;
  config::CameraDeviceConfig config;
  config.image_rate_hz = 50.0;
  config.image_max_width_px = 320;
  std::mutex mutex;
  std::vector<core::TimeNs> stamps;
  std::vector<std::uint32_t> counts;
  std::vector<double> scales;
  ViewerImages images(config, frames,
                      [&](core::TimeNs stamp_ns, std::span<const std::uint8_t> jpeg,
                          const msg::CameraDetections& d, double scale) {
                        const std::lock_guard<std::mutex> lock(mutex);
                        EXPECT_FALSE(jpeg.empty());
                        stamps.push_back(stamp_ns);
                        counts.push_back(d.count);
                        scales.push_back(scale);
                      });
  images.start();
  msg::CameraDetections d;
  d.frame_index = 7;
  ASSERT_TRUE(
      d.push({msg::Colour::kRed, msg::Shape::kBuoy, 0.0F, 1.0F, 1.0F, 1.0F, 1.0F, 1.0F, 1.0F}));
  frames.publish(test_frame(640, 480), 1234, &d);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (images.sent() == 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  // The same frame is never sent twice: wait a few periods with no new frame.
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  images.stop();
  const std::lock_guard<std::mutex> lock(mutex);
  ASSERT_EQ(stamps.size(), 1U);
  EXPECT_EQ(stamps[0], 1234);
  EXPECT_EQ(counts[0], 1U);
  EXPECT_DOUBLE_EQ(scales[0], 0.5);
  EXPECT_EQ(images.sent(), 1U);
}

TEST(ViewerImages, RateZeroSendsNothing) {
  LatestFrame frames;
  config::CameraDeviceConfig config;
  config.image_rate_hz = 0.0;
  std::atomic<int> calls{0};
  ViewerImages images(config, frames,
                      [&](core::TimeNs, std::span<const std::uint8_t>, const msg::CameraDetections&,
                          double) { ++calls; });
  images.start();
  frames.publish(test_frame(64, 48), 1);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  images.stop();
  EXPECT_EQ(calls.load(), 0);
  EXPECT_EQ(images.sent(), 0U);
}

}  // namespace
}  // namespace coxswain::drivers::camera
