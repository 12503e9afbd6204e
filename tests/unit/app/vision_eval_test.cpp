// SPDX-License-Identifier: Apache-2.0
// Scoring of `coxswain vision eval`: labels parsing (malformed rows refused with their line),
// recall, false reports and the confusions on hand-made detections; the colour boxes fitted
// from labelled pixels.
#include "coxswain/app/vision_eval.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <sstream>

namespace coxswain::app {
namespace {

using msg::Colour;
using msg::Shape;

std::vector<LabelledFrame> parse(const std::string& text) {
  std::istringstream in(text);
  std::string error;
  auto frames = read_labels(in, error);
  EXPECT_TRUE(frames.has_value()) << error;
  return frames.value_or(std::vector<LabelledFrame>{});
}

msg::Detection det(Colour c, Shape s, float x, float y) {
  msg::Detection d;
  d.colour = c;
  d.shape = s;
  d.center_x_px = x;
  d.center_y_px = y;
  d.area_px = 100.0F;
  return d;
}

TEST(VisionEval, LabelsGroupObjectsByFileAndKeepEmptyFrames) {
  const auto frames = parse(
      "file,colour,shape,x_px,y_px,width_px,height_px,flags\n"
      "a.png,blue,cross,10,20,30,40,\n"
      "a.png,red,buoy,100,20,10,12,partial\n"
      "b.png,none,none,,,,,\n");
  ASSERT_EQ(frames.size(), 2U);
  ASSERT_EQ(frames[0].objects.size(), 2U);
  EXPECT_EQ(frames[0].objects[0].shape, Shape::kCross);
  EXPECT_TRUE(frames[0].objects[1].partial);
  EXPECT_TRUE(frames[1].objects.empty());
}

TEST(VisionEval, MalformedLabelsAreRefusedWithTheirLine) {
  for (const std::string bad :
       {"a.png,blue,hexagon,1,2,3,4\n", "a.png,blue,cross,1,2\n", "a.png,blue,cross,1,2,-3,4\n",
        "../x.png,none,none\n", "a.png,blue,cross,1,2,3,nan\n"}) {
    std::istringstream in("file,colour,shape\n" + bad);
    std::string error;
    EXPECT_FALSE(read_labels(in, error).has_value()) << bad;
    EXPECT_NE(error.find("line 2"), std::string::npos) << error;
  }
}

TEST(VisionEval, CountsHitsMissesWrongShapesAndFalseReports) {
  const auto frames = parse(
      "f1.png,blue,cross,100,100,40,40,\n"
      "f2.png,green,triangle,100,100,40,40,\n"
      "f3.png,none,none,,,,,\n");
  EvalTally t;
  msg::CameraDetections d;
  d.count = 2;  // the cross found, plus the buoy reading of its blob (not a false report)
  d.detections[0] = det(Colour::kBlue, Shape::kCross, 120, 120);
  d.detections[1] = det(Colour::kBlue, Shape::kBuoy, 120, 120);
  t.add(frames[0], d);
  d.count = 1;  // the triangle read as a rectangle: a miss and a false report
  d.detections[0] = det(Colour::kGreen, Shape::kRectangle, 120, 120);
  t.add(frames[1], d);
  d.count = 1;  // something reported on an empty frame
  d.detections[0] = det(Colour::kRed, Shape::kCircle, 300, 300);
  t.add(frames[2], d);

  EXPECT_EQ(t.frames, 3);
  EXPECT_DOUBLE_EQ(t.recall_colour(Colour::kBlue), 1.0);
  EXPECT_DOUBLE_EQ(t.recall_colour(Colour::kGreen), 0.0);
  EXPECT_DOUBLE_EQ(t.recall_shape(Shape::kCross), 1.0);
  EXPECT_DOUBLE_EQ(t.min_recall(), 0.0);
  EXPECT_EQ(t.false_reports, 2);
  EXPECT_EQ(t.frames_with_false_report, 2);
  EXPECT_EQ(t.shape_confusion[static_cast<std::size_t>(Shape::kTriangle)]
                             [static_cast<std::size_t>(Shape::kRectangle)],
            1);
  EXPECT_NE(t.report().find("recall"), std::string::npos);
  // The one hit's centre, 120, against its box's, 100 + 40 / 2: the bearing's error in pixels.
  ASSERT_EQ(t.centre_dx_px.size(), 1U);
  EXPECT_DOUBLE_EQ(t.centre_dx_px[0], 0.0);
  EXPECT_NE(t.report().find("horizontal centre"), std::string::npos);
}

TEST(VisionEval, AHitOffItsBoxCentreIsABearingError) {
  const auto frames = parse("f1.png,red,circle,100,100,40,40,\n");
  EvalTally t;
  msg::CameraDetections d;
  d.count = 1;
  d.detections[0] = det(Colour::kRed, Shape::kCircle, 113, 120);
  t.add(frames[0], d);
  ASSERT_EQ(t.centre_dx_px.size(), 1U);
  EXPECT_DOUBLE_EQ(t.centre_dx_px[0], -7.0);
  EXPECT_NE(t.report().find("mean -7.00 px"), std::string::npos) << t.report();
}

TEST(VisionEval, CalibrationFitsTheBoxAroundTheLabelledPixels) {
  // A teal-ish blue placard glyph (hue 100) the default blue box (95..127) holds only at its
  // edge: the fitted box centres on it.
  cv::Mat img(200, 200, CV_8UC3, cv::Scalar(240, 240, 240));
  cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(100, 200, 180));
  cv::cvtColor(hsv, hsv, cv::COLOR_HSV2BGR);
  const cv::Vec3b bgr = hsv.at<cv::Vec3b>(0, 0);
  cv::rectangle(img, cv::Rect(50, 50, 100, 100), cv::Scalar(bgr[0], bgr[1], bgr[2]), cv::FILLED);
  const auto frames = parse("a.png,blue,rectangle,50,50,100,100,\n");
  CalibrationSamples samples;
  add_calibration_samples(img, frames[0], samples);
  const perception::VisionParams p =
      fit_colour_boxes(samples, perception::VisionParams::defaults());
  const perception::HsvRange& blue =
      p.colours[static_cast<std::size_t>(p.find_colour(Colour::kBlue))].hsv;
  EXPECT_LE(blue.h_min, 100);
  EXPECT_GE(blue.h_max, 100);
  EXPECT_LE(blue.h_max - blue.h_min, 12);
  EXPECT_LE(blue.s_min, 200);
  EXPECT_GE(blue.s_min, 150);
  EXPECT_FALSE(p.validate().has_value()) << *p.validate();
}

}  // namespace
}  // namespace coxswain::app
