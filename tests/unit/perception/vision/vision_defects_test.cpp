// SPDX-License-Identifier: Apache-2.0
// Each vision defect of the 2022 code: a case the naive pipeline fails and ours passes.
// The naive pipeline is the one docs/missions.md describes and the source team wrote: one HSV
// box per colour (cv::inRange, so no hue wrap), opening and closing, the largest contour of the
// colour whatever its shape, the shape from the vertex count alone (3 triangle, 4 rectangle, 12
// cross, anything else circle), and the bearing from a hard-coded 640-pixel image width.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "coxswain/perception/marker_detector.hpp"
#include "coxswain/perception/vision_params.hpp"
#include "vision_scene.hpp"

namespace coxswain::perception {
namespace {

using msg::Colour;
using msg::Shape;
namespace gen = testing;

struct NaiveDetection {
  bool found = false;
  Shape shape = Shape::kUnknown;
  double center_x_px = 0.0;
  double bearing_deg = 0.0;
};

NaiveDetection naive_2022(const cv::Mat& bgr, const HsvRange& box, double hfov_deg) {
  cv::Mat hsv;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  cv::Mat mask;
  cv::inRange(hsv, cv::Scalar(box.h_min, box.s_min, box.v_min),
              cv::Scalar(box.h_max, box.s_max, box.v_max), mask);
  cv::morphologyEx(mask, mask, cv::MORPH_OPEN,
                   cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
  cv::morphologyEx(mask, mask, cv::MORPH_CLOSE,
                   cv::getStructuringElement(cv::MORPH_RECT, cv::Size(5, 5)));
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  NaiveDetection d;
  double best_area = 50.0;  // specks
  for (const auto& c : contours) {
    const double area = cv::contourArea(c);
    if (area <= best_area) continue;
    best_area = area;
    std::vector<cv::Point> approx;
    cv::approxPolyDP(c, approx, 0.02 * cv::arcLength(c, true), true);
    switch (approx.size()) {
      case 3:
        d.shape = Shape::kTriangle;
        break;
      case 4:
        d.shape = Shape::kRectangle;
        break;
      case 12:
        d.shape = Shape::kCross;
        break;
      default:
        d.shape = Shape::kCircle;
        break;
    }
    const cv::Moments m = cv::moments(c);
    d.center_x_px = m.m10 / m.m00;
    d.found = true;
  }
  d.bearing_deg = (d.center_x_px - 320.0) / 640.0 * hfov_deg;  // defect: the frame is 640 wide
  return d;
}

HsvRange range_of(Colour colour) {
  const VisionParams p = VisionParams::defaults();
  return p.colours[static_cast<std::size_t>(p.find_colour(colour))].hsv;
}

/// What a one-box pipeline can express of a wrapping red: the low side of the hue circle.
HsvRange naive_red() {
  HsvRange r = range_of(Colour::kRed);
  r.h_min = 0;
  return r;
}

TEST(VisionDefects, RedHueWrapsThrough180) {
  ASSERT_TRUE(range_of(Colour::kRed).wraps());
  MarkerDetector ours;
  msg::CameraDetections out;
  for (const int hue : {174, 177, 179, 3}) {
    cv::Mat img = gen::water_background(640, 480);
    cv::rectangle(img, cv::Rect(200, 120, 240, 240), gen::paint_bgr(Colour::kWhite), cv::FILLED);
    gen::draw_shape(img, Shape::kTriangle, {320, 250}, 150, 0, gen::hsv_to_bgr(hue, 220, 230));
    const NaiveDetection n = naive_2022(img, naive_red(), 80.0);
    if (hue < 90) {
      EXPECT_TRUE(n.found) << "hue " << hue;  // the naive box does see the low side
    } else {
      EXPECT_FALSE(n.found) << "hue " << hue;  // defect: red above 170 is not red
    }
    ASSERT_TRUE(ours.detect(img, 0, out));
    EXPECT_TRUE(find_target(out, Colour::kRed, Shape::kTriangle).has_value()) << "hue " << hue;
  }
}

TEST(VisionDefects, SquareIsNotACircle) {
  // A far, slightly blurred square (16-20 px across, as a marker looks from the decision point
  // with a wide lens): the rounded corners give the polygon approximation six or eight vertices,
  // which the vertex-count rule calls a circle.
  MarkerDetector ours;
  msg::CameraDetections out;
  int naive_circles = 0;
  int ours_wrong = 0;
  int cases = 0;
  for (const float size_px : {16.0F, 20.0F}) {
    for (const float rot : {10.0F, 30.0F, 45.0F}) {
      for (const int blur : {5, 7}) {
        cv::Mat img = gen::water_background(640, 480);
        gen::draw_marker(img, Shape::kRectangle, Colour::kBlue, {320, 240}, size_px, rot);
        cv::GaussianBlur(img, img, cv::Size(blur, blur), 0.0);
        ++cases;
        const NaiveDetection n = naive_2022(img, range_of(Colour::kBlue), 80.0);
        if (n.found && n.shape == Shape::kCircle) ++naive_circles;
        ASSERT_TRUE(ours.detect(img, 0, out));
        const auto hit = find_target(out, Colour::kBlue, Shape::kRectangle);
        const auto circle = find_target(out, Colour::kBlue, Shape::kCircle);
        if (!hit.has_value() || circle.has_value()) {
          ++ours_wrong;
          ADD_FAILURE() << "ours: size " << size_px << " rot " << rot << " blur " << blur;
        }
      }
    }
  }
  EXPECT_GE(naive_circles, 3) << "of " << cases;  // defect: squares called circles
  EXPECT_EQ(ours_wrong, 0) << "of " << cases;
}

TEST(VisionDefects, LargerNonTargetDoesNotReplaceTheTarget) {
  // Target: a small green triangle. Beside it a much larger green circle.
  cv::Mat img = gen::water_background(640, 480);
  gen::draw_marker(img, Shape::kTriangle, Colour::kGreen, {110, 240}, 60, 0);
  gen::draw_marker(img, Shape::kCircle, Colour::kGreen, {400, 240}, 150, 0);
  const NaiveDetection n = naive_2022(img, range_of(Colour::kGreen), 80.0);
  ASSERT_TRUE(n.found);
  EXPECT_EQ(n.shape, Shape::kCircle);  // defect: the green marker "is" the big circle
  EXPECT_NEAR(n.center_x_px, 400.0, 5.0);
  MarkerDetector ours;
  msg::CameraDetections out;
  ASSERT_TRUE(ours.detect(img, 0, out));
  const auto target = find_target(out, Colour::kGreen, Shape::kTriangle);
  ASSERT_TRUE(target.has_value());
  EXPECT_NEAR(target->center_x_px, 110.0F, 3.0F);
}

TEST(VisionDefects, ImageSizeIsTakenFromTheFrame) {
  // A 1920x1080 camera, marker at column 1440: the pinhole bearing is about 19 deg to starboard.
  constexpr double kHfovDeg = 80.0;
  cv::Mat img = gen::water_background(1920, 1080);
  gen::draw_marker(img, Shape::kCross, Colour::kGreen, {1440, 540}, 300, 0);
  const double truth_deg = camera_bearing_deg(1440.0, 1920, kHfovDeg);
  ASSERT_NEAR(truth_deg, std::atan(480.0 / (960.0 / std::tan(40.0 * M_PI / 180.0))) * 180.0 / M_PI,
              1e-9);
  const NaiveDetection n = naive_2022(img, range_of(Colour::kGreen), kHfovDeg);
  ASSERT_TRUE(n.found);
  EXPECT_GT(std::abs(n.bearing_deg - truth_deg), 60.0);  // defect: 140 deg, behind the beam
  MarkerDetector ours;
  msg::CameraDetections out;
  ASSERT_TRUE(ours.detect(img, 0, out));
  const auto hit = find_target(out, Colour::kGreen, Shape::kCross);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->bearing_deg, truth_deg, 0.5);
}

}  // namespace
}  // namespace coxswain::perception
