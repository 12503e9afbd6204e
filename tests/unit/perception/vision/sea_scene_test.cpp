// SPDX-License-Identifier: Apache-2.0
// Colour at sea: blue-green water inside the blue box, a blue sky, a low sun's orange sky. The
// per-strip background model takes the water and sky out of every colour, and a marker on a
// placard inside a border-touching blob of its colour is still found.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "coxswain/perception/camera_pipeline.hpp"
#include "coxswain/perception/vision_colour_mask.hpp"
#include "vision_scene.hpp"

namespace coxswain::perception {
namespace {

namespace gen = testing;
using msg::Colour;
using msg::Shape;

cv::Mat harbour(std::uint64_t seed) { return gen::harbour_scene(seed); }

void placard(cv::Mat& img, Shape shape, Colour colour, cv::Point2f c, float size_px) {
  const float b = 0.7F * size_px;
  cv::rectangle(img, cv::Point2f(c.x - b, c.y - b), cv::Point2f(c.x + b, c.y + b),
                cv::Scalar(245, 245, 245), cv::FILLED);
  gen::draw_shape(img, shape, c, size_px, 0.0F, gen::paint_bgr(colour));
}

int count_except(const msg::CameraDetections& out, Colour colour) {
  int n = 0;
  for (std::uint32_t i = 0; i < out.count; ++i) n += out.detections[i].colour != colour ? 1 : 0;
  return n;
}

// The water model's grid is capped per strip: a 640 x 480 frame in 8 strips at 4 px holds
// exactly the default cap, so its fit is the uncapped one; a 1280 x 720 frame samples a coarser
// grid (every 7th pixel) and its blue-green sea is still no colour.
TEST(SeaScene, TheSampleCapLeavesA640FrameAsItWasAndStillTakesOutALargeFramesSea) {
  BackgroundParams capped;
  BackgroundParams uncapped = capped;
  uncapped.max_samples = 1000000;
  const cv::Mat small = gen::harbour_scene(5);
  for (int k = 0; k < capped.strips; ++k) {
    const int r0 = k * small.rows / capped.strips;
    const int r1 = (k + 1) * small.rows / capped.strips;
    const ColourGaussian a = fit_dominant_colour(small, r0, r1, capped);
    const ColourGaussian b = fit_dominant_colour(small, r0, r1, uncapped);
    EXPECT_EQ(a.valid, b.valid) << "strip " << k;
    EXPECT_EQ(a.mean_bgr, b.mean_bgr) << "strip " << k;
    EXPECT_EQ(a.share, b.share) << "strip " << k;
  }
  CameraPipeline pipeline;
  msg::CameraDetections out;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    ASSERT_TRUE(pipeline.process(gen::harbour_scene(seed, 1280, 720), 0, out));
    EXPECT_EQ(out.count, 0U) << "seed " << seed;
  }
}

TEST(SeaScene, BlueSeaFallsInsideTheBlueBoxYetIsNoColour) {
  const VisionParams p = VisionParams::defaults();
  const cv::Vec3b water(120, 100, 50);
  const int blue = p.find_colour(Colour::kBlue);
  ASSERT_GE(blue, 0);
  cv::Mat px(1, 1, CV_8UC3, cv::Scalar(water[0], water[1], water[2]));
  cv::cvtColor(px, px, cv::COLOR_BGR2HSV);
  const cv::Vec3b hsv = px.at<cv::Vec3b>(0, 0);
  ASSERT_TRUE(p.colours[static_cast<std::size_t>(blue)].hsv.contains(hsv[0], hsv[1], hsv[2]));

  CameraPipeline pipeline(p);
  msg::CameraDetections out;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    ASSERT_TRUE(pipeline.process(harbour(seed), 0, out));
    EXPECT_EQ(out.count, 0U) << "seed " << seed << ": "
                             << msg::colour_name(out.detections[0].colour) << "/"
                             << msg::shape_name(out.detections[0].shape);
  }
}

TEST(SeaScene, EveryMarkerColourIsFoundOnBlueGreenSea) {
  CameraPipeline pipeline;
  msg::CameraDetections out;
  for (const Colour c : {Colour::kRed, Colour::kOrange, Colour::kYellow, Colour::kGreen,
                         Colour::kBlue, Colour::kPurple, Colour::kBlack}) {
    for (const Shape s : {Shape::kTriangle, Shape::kRectangle, Shape::kCross, Shape::kCircle}) {
      cv::Mat img = harbour(7);
      placard(img, s, c, {400.0F, 215.0F}, 50.0F);  // about 5 m away, at the horizon
      ASSERT_TRUE(pipeline.process(img, 0, out));
      std::string got;
      for (std::uint32_t i = 0; i < out.count; ++i) {
        got += " " + std::string(msg::colour_name(out.detections[i].colour)) + "/" +
               std::string(msg::shape_name(out.detections[i].shape));
      }
      EXPECT_TRUE(find_target(out, c, s).has_value())
          << msg::colour_name(c) << "/" << msg::shape_name(s) << " got:" << got << " stats "
          << pipeline.last_stats().markers.unknown_shape << " unknown, "
          << pipeline.last_stats().markers.too_small << " small";
      EXPECT_EQ(count_except(out, c), 0) << msg::colour_name(c) << "/" << msg::shape_name(s);
    }
  }
}

TEST(SeaScene, LowSunOrangeSkyIsNoColour) {
  // The sky near the horizon: hue about 13, saturation 160, inside the orange box.
  const cv::Mat img = gen::low_sun_scene(3);
  CameraPipeline pipeline;
  msg::CameraDetections out;
  ASSERT_TRUE(pipeline.process(img, 0, out));
  EXPECT_EQ(out.count, 0U);
}

TEST(SeaScene, MarkerOnPlacardInsideBorderTouchingBlobOfItsColourIsFound) {
  // The background model off: the blue water is one frame-wide blue blob and the placard a hole
  // in it; the blue cross is an island in that hole.
  VisionParams p = VisionParams::defaults();
  p.background.enabled = false;
  cv::Mat img(480, 640, CV_8UC3, gen::paint_bgr(Colour::kBlue));
  placard(img, Shape::kCross, Colour::kBlue, {320.0F, 240.0F}, 60.0F);
  CameraPipeline pipeline(p);
  msg::CameraDetections out;
  ASSERT_TRUE(pipeline.process(img, 0, out));
  EXPECT_TRUE(find_target(out, Colour::kBlue, Shape::kCross).has_value());
}

TEST(SeaScene, TwoIslandsInOneHoleAreGlyphArtefactsNotMarkers) {
  // A letter's two bowls in a blob touching the border (a page-filling blue shape with a white
  // B): neither is a marker.
  VisionParams p = VisionParams::defaults();
  p.background.enabled = false;
  cv::Mat img(480, 640, CV_8UC3, gen::paint_bgr(Colour::kBlue));
  cv::rectangle(img, cv::Rect(260, 160, 120, 160), cv::Scalar(245, 245, 245), cv::FILLED);
  cv::rectangle(img, cv::Rect(285, 180, 60, 50), gen::paint_bgr(Colour::kBlue), cv::FILLED);
  cv::rectangle(img, cv::Rect(285, 250, 60, 50), gen::paint_bgr(Colour::kBlue), cv::FILLED);
  CameraPipeline pipeline(p);
  msg::CameraDetections out;
  ASSERT_TRUE(pipeline.process(img, 0, out));
  EXPECT_FALSE(find_target(out, Colour::kBlue, Shape::kRectangle).has_value());
}

}  // namespace
}  // namespace coxswain::perception
