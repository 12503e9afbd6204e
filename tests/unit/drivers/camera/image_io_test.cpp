// SPDX-License-Identifier: Apache-2.0
// The image-I/O module: found and used from the build tree, and a clear error naming where it
// looked when it is missing. The loader remembers its first answer for the life of the process,
// so the missing case runs in a fresh process (a re-executed death test).
#include "coxswain/drivers/camera/image_io.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <string>

namespace coxswain::drivers::camera {
namespace {

TEST(ImageIo, TheModuleLoadsReadsAnImageAndEncodesAJpeg) {
  std::string error;
  ASSERT_TRUE(image_io_installed(&error)) << error;
  const ImageIoModule* io = image_io(&error);
  ASSERT_NE(io, nullptr) << error;
  cv::Mat img(48, 64, CV_8UC3, cv::Scalar(10, 200, 30));
  cv::circle(img, {32, 24}, 10, cv::Scalar(0, 0, 255), -1);
  const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                     ("coxswain_image_io_" + std::to_string(::getpid()) + ".png");
  ASSERT_TRUE(cv::imwrite(file.string(), img));
  const cv::Mat back = read_image(file.string(), &error);
  std::filesystem::remove(file);
  ASSERT_FALSE(back.empty()) << error;
  EXPECT_EQ(cv::norm(back, img, cv::NORM_INF), 0.0);
  EXPECT_TRUE(read_image("/nonexistent/frame.png").empty());
  std::vector<std::uint8_t> jpeg;
  ASSERT_TRUE(io->encode_jpeg(img, 80, jpeg));
  ASSERT_GT(jpeg.size(), 4U);
  EXPECT_EQ(jpeg[0], 0xFF);
  EXPECT_EQ(jpeg[1], 0xD8);  // a JPEG's start-of-image marker
  auto cap = make_capture(error);
  ASSERT_NE(cap, nullptr) << error;
  EXPECT_FALSE(cap->is_opened());
  // One named backend: with every backend, some probe the USB bus and never free what they list.
  EXPECT_FALSE(cap->open_path("/nonexistent/video.avi", cv::CAP_FFMPEG));
  EXPECT_FALSE(cap->is_opened());
}

void load_a_missing_module() {
  ::setenv("COXSWAIN_IMAGE_IO_MODULE", "/nonexistent/libcoxswain_image_io.so", 1);
  std::string error;
  const bool installed = image_io_installed(&error);
  const cv::Mat img = read_image("/nonexistent/frame.png", &error);
  std::cerr << "installed=" << installed << " empty=" << img.empty() << " error=" << error;
  std::exit(installed || !img.empty() ? 1 : 0);
}

TEST(ImageIoDeathTest, AMissingModuleIsAClearErrorNamingWhereItLooked) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");  // a fresh process: the loader answers once
  EXPECT_EXIT(load_a_missing_module(), ::testing::ExitedWithCode(0),
              "installed=0 empty=1 error=the image-I/O module libcoxswain_image_io.so is not "
              "installed \\(looked at /nonexistent/libcoxswain_image_io.so; "
              "COXSWAIN_IMAGE_IO_MODULE names it\\)");
}

}  // namespace
}  // namespace coxswain::drivers::camera
