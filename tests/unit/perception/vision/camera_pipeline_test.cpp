// SPDX-License-Identifier: Apache-2.0
// CameraPipeline: the union of what MarkerDetector and BuoyDetector find, from one shared set of
// colour masks, with bearings through the configured field of view and camera mount, at any
// frame size; deterministic; on the shared marker images when present.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <tuple>
#include <vector>

#include "coxswain/perception/camera_pipeline.hpp"
#include "support/testdata.hpp"
#include "vision_scene.hpp"

namespace coxswain::perception {
namespace {

using msg::Colour;
using msg::Shape;
namespace gen = testing;

cv::Mat dock_scene(int width, int height, std::uint64_t seed) {
  cv::Mat img = gen::water_background(width, height);
  const auto w = static_cast<float>(width);
  const auto h = static_cast<float>(height);
  gen::draw_marker(img, Shape::kCircle, Colour::kGreen, {0.2F * w, 0.45F * h}, 0.15F * h, 0);
  gen::draw_marker(img, Shape::kCross, Colour::kBlue, {0.5F * w, 0.45F * h}, 0.15F * h, 20);
  gen::draw_marker(img, Shape::kTriangle, Colour::kBlack, {0.8F * w, 0.45F * h}, 0.15F * h, 0);
  gen::draw_shape(img, Shape::kCircle, {0.35F * w, 0.85F * h}, 0.06F * h, 0,
                  gen::paint_bgr(Colour::kPurple));
  gen::draw_shape(img, Shape::kCircle, {0.9F * w, 0.8F * h}, 0.09F * h, 0,
                  gen::paint_bgr(Colour::kRed));
  gen::add_noise(img, 6.0, seed);
  return img;
}

using Key = std::tuple<float, int, int, float, float, float>;

std::vector<Key> keys(const msg::CameraDetections& out) {
  std::vector<Key> k;
  for (std::uint32_t i = 0; i < out.count; ++i) {
    const msg::Detection& d = out.detections[i];
    k.emplace_back(d.area_px, static_cast<int>(d.colour), static_cast<int>(d.shape), d.center_x_px,
                   d.center_y_px, d.bearing_deg);
  }
  std::sort(k.begin(), k.end());
  return k;
}

/// What the two detectors find on their own, merged the way the pipeline merges.
msg::CameraDetections reference(const VisionParams& p, const cv::Mat& img) {
  MarkerDetector markers(p);
  BuoyDetector buoys(p);
  msg::CameraDetections m;
  msg::CameraDetections b;
  EXPECT_TRUE(markers.detect(img, 0, m));
  EXPECT_TRUE(buoys.detect(img, 0, b));
  for (std::uint32_t i = 0; i < b.count; ++i) (void)insert_by_area(m, b.detections[i]);
  return m;
}

TEST(CameraPipeline, SameAsBothDetectors) {
  const VisionParams p = VisionParams::defaults();
  CameraPipeline pipeline(p);
  msg::CameraDetections out;
  for (const std::uint64_t seed : {1U, 2U, 3U}) {
    const cv::Mat img = dock_scene(640, 480, seed);
    ASSERT_TRUE(pipeline.process(img, 7, out));
    const msg::CameraDetections ref = reference(p, img);
    EXPECT_EQ(keys(out), keys(ref)) << "seed " << seed;
    // Markers and buoys are both there, largest first.
    EXPECT_TRUE(find_target(out, Colour::kGreen, Shape::kCircle).has_value());
    EXPECT_TRUE(find_target(out, Colour::kBlue, Shape::kCross).has_value());
    EXPECT_TRUE(find_target(out, Colour::kBlack, Shape::kTriangle).has_value());
    EXPECT_NE(BuoyDetector::largest(out, Colour::kPurple), nullptr);
    EXPECT_NE(BuoyDetector::largest(out, Colour::kRed), nullptr);
    for (std::uint32_t i = 1; i < out.count; ++i) {
      EXPECT_GE(out.detections[i - 1].area_px, out.detections[i].area_px);
    }
  }
}

TEST(CameraPipeline, BearingFromFovMountAndFrameSize) {
  const core::MountTransform port{-90.0, 0.1, -0.2};
  for (const double hfov_deg : {60.0, 80.0, 120.0}) {
    CameraPipeline pipeline(VisionParams::defaults(), hfov_deg, port);
    EXPECT_DOUBLE_EQ(pipeline.params().hfov_deg, hfov_deg);
    EXPECT_DOUBLE_EQ(pipeline.params().mount_yaw_deg, -90.0);
    msg::CameraDetections out;
    for (const cv::Size size : {cv::Size(320, 240), cv::Size(640, 480), cv::Size(1280, 720)}) {
      cv::Mat img = gen::water_background(size.width, size.height);
      const float x = 0.75F * static_cast<float>(size.width);
      gen::draw_shape(img, Shape::kCircle, {x, 0.5F * static_cast<float>(size.height)},
                      0.1F * static_cast<float>(size.height), 0, gen::paint_bgr(Colour::kPurple));
      ASSERT_TRUE(pipeline.process(img, 0, out));
      EXPECT_EQ(out.image_width_px, size.width);
      EXPECT_EQ(out.image_height_px, size.height);
      const msg::Detection* buoy = BuoyDetector::largest(out, Colour::kPurple);
      ASSERT_NE(buoy, nullptr) << size;
      // Pinhole: f = (w/2)/tan(hfov/2); a quarter width right of centre.
      const double expected_deg =
          -90.0 + core::rad_to_deg(std::atan(0.5 * std::tan(core::deg_to_rad(hfov_deg / 2.0))));
      EXPECT_NEAR(buoy->bearing_deg, expected_deg, 0.3) << hfov_deg << " " << size;
    }
  }
}

TEST(CameraPipeline, StampsIndexesAndRejectsBadFrames) {
  CameraPipeline pipeline;
  msg::CameraDetections out;
  const cv::Mat img = dock_scene(320, 240, 4);
  ASSERT_TRUE(pipeline.process(img, 1000, out));
  EXPECT_EQ(out.stamp_ns, 1000);
  EXPECT_EQ(out.frame_index, 1U);
  EXPECT_GT(out.count, 0U);

  EXPECT_FALSE(pipeline.process(cv::Mat(), 2000, out));
  EXPECT_EQ(out.count, 0U);
  EXPECT_EQ(out.image_width_px, 0);
  EXPECT_EQ(out.stamp_ns, 2000);
  EXPECT_EQ(out.frame_index, 2U);
  const cv::Mat grey(240, 320, CV_8UC1, cv::Scalar(100));
  EXPECT_FALSE(pipeline.process(grey, 3000, out));
  EXPECT_EQ(out.count, 0U);

  ASSERT_TRUE(pipeline.process(img, 4000, out));
  EXPECT_EQ(out.frame_index, 4U);
  EXPECT_EQ(pipeline.frames(), 4U);
}

TEST(CameraPipeline, DeterministicAcrossInstancesAndSizeChanges) {
  CameraPipeline a;
  CameraPipeline b;
  msg::CameraDetections out_a;
  msg::CameraDetections out_b;
  const cv::Mat big = dock_scene(640, 480, 5);
  const cv::Mat small = dock_scene(320, 240, 6);
  // `a` sees a size change in between; its reused buffers must not leak into the result.
  ASSERT_TRUE(a.process(big, 1, out_a));
  ASSERT_TRUE(a.process(small, 2, out_a));
  ASSERT_TRUE(a.process(big, 3, out_a));
  ASSERT_TRUE(b.process(big, 3, out_b));
  ASSERT_EQ(out_a.count, out_b.count);
  EXPECT_EQ(keys(out_a), keys(out_b));
  for (std::uint32_t i = 0; i < out_a.count; ++i) {
    EXPECT_EQ(out_a.detections[i].colour, out_b.detections[i].colour);
    EXPECT_EQ(out_a.detections[i].shape, out_b.detections[i].shape);
    EXPECT_EQ(out_a.detections[i].score, out_b.detections[i].score);
  }
}

TEST(CameraPipeline, CapKeepsTheLargest) {
  CameraPipeline pipeline;
  msg::CameraDetections out;
  cv::Mat img = gen::water_background(640, 480);
  // 24 buoys of growing size: only the 16 largest survive.
  for (int i = 0; i < 24; ++i) {
    const auto x = static_cast<float>(40 + (i % 8) * 75);
    const auto y = static_cast<float>(80 + (i / 8) * 150);
    gen::draw_shape(img, Shape::kBuoy, {x, y}, static_cast<float>(14 + 2 * i), 0,
                    gen::paint_bgr(Colour::kYellow));
  }
  ASSERT_TRUE(pipeline.process(img, 0, out));
  ASSERT_EQ(out.count, msg::CameraDetections::kMaxDetections);
  float smallest_kept = out.detections[out.count - 1].area_px;
  EXPECT_GT(smallest_kept, 3.14F * 20.0F * 20.0F / 4.0F);  // the 8 smallest (<= 28 px) are gone
}

TEST(CameraPipeline, SharedMarkerImages) {
  COXSWAIN_REQUIRE_TESTDATA(labels, "markers/labels.csv");
  std::ifstream in(labels);
  ASSERT_TRUE(in.good());
  std::string line;
  std::getline(in, line);  // header
  const VisionParams p = VisionParams::defaults();
  CameraPipeline pipeline(p);
  msg::CameraDetections out;
  int images = 0;
  while (std::getline(in, line)) {
    const std::string file = line.substr(0, line.find(','));
    if (file.empty()) continue;
    const cv::Mat img = cv::imread((labels.parent_path() / file).string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(img.empty()) << file;
    ASSERT_TRUE(pipeline.process(img, images, out));
    EXPECT_EQ(out.image_width_px, img.cols) << file;
    EXPECT_EQ(keys(out), keys(reference(p, img))) << file;
    ++images;
  }
  EXPECT_GT(images, 20);
}

}  // namespace
}  // namespace coxswain::perception
