// SPDX-License-Identifier: Apache-2.0
// Buoys by colour (including purple, the course-1/2 buoy) with bearing, largest first.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "coxswain/perception/buoy_detector.hpp"
#include "vision_scene.hpp"

namespace coxswain::perception {
namespace {

using msg::Colour;
namespace gen = testing;

TEST(BuoyDetector, EachColourWithBearing) {
  BuoyDetector det;
  msg::CameraDetections out;
  for (const Colour c : {Colour::kRed, Colour::kGreen, Colour::kYellow, Colour::kOrange,
                         Colour::kPurple, Colour::kBlue}) {
    for (const cv::Size size : {cv::Size(320, 240), cv::Size(640, 480), cv::Size(1280, 720)}) {
      cv::Mat img = gen::water_background(size.width, size.height);
      const float x = 0.7F * static_cast<float>(size.width);
      const float y = 0.6F * static_cast<float>(size.height);
      gen::draw_shape(img, msg::Shape::kCircle, {x, y}, 0.12F * static_cast<float>(size.height), 0,
                      gen::paint_bgr(c));
      gen::add_noise(img, 8.0, 3);
      ASSERT_TRUE(det.detect(img, 42, out));
      ASSERT_EQ(out.count, 1U) << colour_name(c) << " " << size;
      const msg::Detection& d = out.detections[0];
      EXPECT_EQ(d.colour, c);
      EXPECT_EQ(d.shape, msg::Shape::kBuoy);
      EXPECT_NEAR(d.bearing_deg, camera_bearing_deg(x, size.width, 80.0), 0.5);
      EXPECT_EQ(out.stamp_ns, 42);
    }
  }
}

TEST(BuoyDetector, LargestFirstAndPurpleLookup) {
  BuoyDetector det;
  msg::CameraDetections out;
  cv::Mat img = gen::water_background(640, 480);
  gen::draw_shape(img, msg::Shape::kCircle, {100, 300}, 30, 0, gen::paint_bgr(Colour::kRed));
  gen::draw_shape(img, msg::Shape::kCircle, {300, 300}, 90, 0, gen::paint_bgr(Colour::kGreen));
  gen::draw_shape(img, msg::Shape::kCircle, {500, 300}, 50, 0, gen::paint_bgr(Colour::kPurple));
  gen::draw_shape(img, msg::Shape::kCircle, {560, 120}, 20, 0, gen::paint_bgr(Colour::kPurple));
  ASSERT_TRUE(det.detect(img, 0, out));
  ASSERT_EQ(out.count, 4U);
  for (std::size_t i = 1; i < out.count; ++i) {
    EXPECT_GE(out.detections[i - 1].area_px, out.detections[i].area_px);
  }
  EXPECT_EQ(out.detections[0].colour, Colour::kGreen);
  const msg::Detection* purple = BuoyDetector::largest(out, Colour::kPurple);
  ASSERT_NE(purple, nullptr);
  EXPECT_NEAR(purple->center_x_px, 500.0F, 2.0F);
  EXPECT_EQ(BuoyDetector::largest(out, Colour::kYellow), nullptr);
}

TEST(BuoyDetector, PortCameraAndEdgeBuoys) {
  VisionParams p = VisionParams::defaults();
  p.mount_yaw_deg = -90.0;  // course 2: camera looks to port
  BuoyDetector det(p);
  msg::CameraDetections out;
  cv::Mat img = gen::water_background(640, 480);
  // Half out of the left edge: kept by default, its bearing still points the right way.
  gen::draw_shape(img, msg::Shape::kCircle, {10, 240}, 80, 0, gen::paint_bgr(Colour::kPurple));
  ASSERT_TRUE(det.detect(img, 0, out));
  ASSERT_EQ(out.count, 1U);
  EXPECT_LT(out.detections[0].bearing_deg, -90.0F - 30.0F);
  p.buoy_reject_edge = true;
  BuoyDetector strict(p);
  ASSERT_TRUE(strict.detect(img, 0, out));
  EXPECT_EQ(out.count, 0U);
}

TEST(BuoyDetector, IgnoresSpeckleAndStreaks) {
  BuoyDetector det;
  msg::CameraDetections out;
  cv::Mat img = gen::water_background(640, 480);
  cv::circle(img, {100, 100}, 3, gen::paint_bgr(Colour::kRed), cv::FILLED);  // below min area
  // A thin red zig-zag: large extent, low solidity (a rope or a reflection, not a buoy).
  const std::vector<cv::Point> zig{{200, 400}, {260, 300}, {320, 400}, {380, 300}, {440, 400}};
  cv::polylines(img, zig, false, gen::paint_bgr(Colour::kRed), 9);
  ASSERT_TRUE(det.detect(img, 0, out));
  EXPECT_EQ(out.count, 0U);
}

}  // namespace
}  // namespace coxswain::perception
