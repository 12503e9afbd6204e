// SPDX-License-Identifier: Apache-2.0
// Bearing model, HSV ranges (including the red wrap), parameter validation, shape rules on
// ideal features.
#include <gtest/gtest.h>

#include <cmath>

#include "coxswain/core/angles.hpp"
#include "coxswain/perception/vision_params.hpp"
#include "coxswain/perception/vision_shape.hpp"

namespace coxswain::perception {
namespace {

TEST(VisionBearing, EdgesAndCentreForAnyWidth) {
  for (const int width : {320, 640, 1280, 1606}) {
    for (const double fov : {60.0, 80.0, 100.0}) {
      EXPECT_NEAR(camera_bearing_deg(0.0, width, fov), -fov / 2.0, 1e-9) << width;
      EXPECT_NEAR(camera_bearing_deg(width / 2.0, width, fov), 0.0, 1e-9) << width;
      EXPECT_NEAR(camera_bearing_deg(width, width, fov), fov / 2.0, 1e-9) << width;
    }
  }
  // Pinhole, not linear: a quarter of the way across is more than a quarter of the FOV off
  // (the image plane is compressed towards the centre).
  EXPECT_NEAR(camera_bearing_deg(160.0, 640, 80.0),
              -core::rad_to_deg(std::atan(0.5 * std::tan(core::deg_to_rad(40.0)))), 1e-9);
  EXPECT_LT(camera_bearing_deg(160.0, 640, 80.0), -20.0);
}

TEST(VisionBearing, MountYawIntoBodyFrameWraps) {
  EXPECT_NEAR(body_bearing_deg(0.0, 640, 80.0, -90.0), -130.0, 1e-9);
  EXPECT_NEAR(body_bearing_deg(640.0, 640, 80.0, 170.0), -150.0, 1e-9);  // 210 wraps
  EXPECT_NEAR(body_bearing_deg(320.0, 640, 80.0, 180.0), 180.0, 1e-9);
}

TEST(HsvRange, RedWrapsThrough180) {
  const VisionParams p = VisionParams::defaults();
  const int i = p.find_colour(msg::Colour::kRed);
  ASSERT_GE(i, 0);
  const HsvRange red = p.colours[static_cast<std::size_t>(i)].hsv;
  EXPECT_TRUE(red.wraps());
  for (const int h : {170, 175, 179, 0, 4, 8}) EXPECT_TRUE(red.contains(h, 200, 200)) << h;
  for (const int h : {30, 60, 120, 160}) EXPECT_FALSE(red.contains(h, 200, 200)) << h;
  EXPECT_FALSE(red.contains(0, 20, 200));  // grey is not red
  const HsvRange green =
      p.colours[static_cast<std::size_t>(p.find_colour(msg::Colour::kGreen))].hsv;
  EXPECT_FALSE(green.wraps());
  EXPECT_TRUE(green.contains(69, 206, 177));  // #22B14C
}

TEST(VisionParams, DefaultsValidAndValidateCatchesErrors) {
  VisionParams p = VisionParams::defaults();
  EXPECT_FALSE(p.validate().has_value());
  EXPECT_GE(p.find_colour(msg::Colour::kPurple), 0);
  EXPECT_GE(p.find_colour(msg::Colour::kBlack), 0);
  EXPECT_EQ(p.find_colour(msg::Colour::kWhite), -1);
  VisionParams bad = p;
  bad.hfov_deg = 0.0;
  EXPECT_TRUE(bad.validate().has_value());
  bad = p;
  bad.colours[0].hsv.h_max = 200;
  EXPECT_TRUE(bad.validate().has_value());
  bad = p;
  bad.blur_kernel_px = 4;
  EXPECT_TRUE(bad.validate().has_value());
  bad = p;
  bad.min_area_fraction = 0.0;
  EXPECT_TRUE(bad.validate().has_value());
  bad = p;
  bad.shape.rectangle_min_extent = 0.5;
  EXPECT_TRUE(bad.validate().has_value());
  while (p.add_colour({msg::Colour::kWhite, {}, true, true})) {
  }
  EXPECT_EQ(p.colour_count, VisionParams::kMaxColours);
}

ShapeFeatures features(int vertices, bool convex, double solidity, double extent, double circ,
                       int defects) {
  ShapeFeatures f;
  f.area_px = 1000.0;
  f.vertices = vertices;
  f.convex_polygon = convex;
  f.solidity = solidity;
  f.extent = extent;
  f.circularity = circ;
  f.deep_defects = defects;
  return f;
}

TEST(ShapeRules, IdealFeatures) {
  const ShapeParams p;
  using msg::Shape;
  EXPECT_EQ(classify_shape(features(3, true, 1.0, 0.5, 0.6, 0), p).first, Shape::kTriangle);
  EXPECT_EQ(classify_shape(features(4, true, 1.0, 1.0, 0.785, 0), p).first, Shape::kRectangle);
  EXPECT_EQ(classify_shape(features(12, false, 0.556, 0.556, 0.9, 4), p).first, Shape::kCross);
  EXPECT_EQ(classify_shape(features(12, true, 1.0, 0.785, 0.99, 0), p).first, Shape::kCircle);
  // Blurred square: rounded corners add vertices and lift circularity, but it still fills its box.
  EXPECT_EQ(classify_shape(features(8, true, 0.99, 0.95, 0.83, 0), p).first, Shape::kRectangle);
  // Perspective: a trapezoid with four corners.
  EXPECT_EQ(classify_shape(features(4, true, 1.0, 0.82, 0.8, 0), p).first, Shape::kRectangle);
  // Distractors: pentagon, semicircle, quarter disc, five-pointed star.
  EXPECT_EQ(classify_shape(features(5, true, 1.0, 0.69, 0.87, 0), p).first, Shape::kUnknown);
  EXPECT_EQ(classify_shape(features(7, true, 1.0, 0.785, 0.75, 0), p).first, Shape::kUnknown);
  EXPECT_EQ(classify_shape(features(6, true, 1.0, 0.785, 0.77, 0), p).first, Shape::kUnknown);
  EXPECT_EQ(classify_shape(features(10, false, 0.5, 0.4, 0.8, 5), p).first, Shape::kUnknown);
  EXPECT_EQ(classify_shape(ShapeFeatures{}, p).first, Shape::kUnknown);
}

}  // namespace
}  // namespace coxswain::perception
