// SPDX-License-Identifier: Apache-2.0
// Cost per camera frame of marker detection (7 colours, all shapes) and buoy detection on a
// generated 640x480 scene: three placards with markers on water, with sensor noise.
#include <benchmark/benchmark.h>

#include <opencv2/imgproc.hpp>

#include "coxswain/perception/buoy_detector.hpp"
#include "coxswain/perception/marker_detector.hpp"
#include "vision_scene.hpp"

namespace coxswain::perception {
namespace {

namespace gen = testing;

cv::Mat dock_scene(int width, int height) {
  cv::Mat img = gen::water_background(width, height);
  const auto w = static_cast<float>(width);
  const auto h = static_cast<float>(height);
  gen::draw_marker(img, msg::Shape::kCircle, msg::Colour::kGreen, {0.2F * w, 0.45F * h}, 0.15F * h,
                   0);
  gen::draw_marker(img, msg::Shape::kCross, msg::Colour::kBlue, {0.5F * w, 0.45F * h}, 0.15F * h,
                   20);
  gen::draw_marker(img, msg::Shape::kTriangle, msg::Colour::kBlack, {0.8F * w, 0.45F * h},
                   0.15F * h, 0);
  gen::draw_shape(img, msg::Shape::kCircle, {0.35F * w, 0.85F * h}, 0.06F * h, 0,
                  gen::paint_bgr(msg::Colour::kPurple));
  gen::add_noise(img, 6.0, 11);
  return img;
}

void BM_MarkerDetect(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const int height = static_cast<int>(state.range(1));
  const cv::Mat img = dock_scene(width, height);
  MarkerDetector det;
  msg::CameraDetections out;
  // The three placards must be found (the purple buoy also reads as a purple circle).
  const bool ok = det.detect(img, 0, out) &&
                  find_target(out, msg::Colour::kGreen, msg::Shape::kCircle).has_value() &&
                  find_target(out, msg::Colour::kBlue, msg::Shape::kCross).has_value() &&
                  find_target(out, msg::Colour::kBlack, msg::Shape::kTriangle).has_value();
  if (!ok) state.SkipWithError("scene not detected");
  core::TimeNs t = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(det.detect(img, ++t, out));
    benchmark::DoNotOptimize(out.count);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["detections"] = static_cast<double>(out.count);
}
BENCHMARK(BM_MarkerDetect)
    ->Args({640, 480})
    ->Args({320, 240})
    ->Args({1280, 720})
    ->Unit(benchmark::kMillisecond);

void BM_BuoyDetect(benchmark::State& state) {
  const cv::Mat img = dock_scene(640, 480);
  BuoyDetector det;
  msg::CameraDetections out;
  core::TimeNs t = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(det.detect(img, ++t, out));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_BuoyDetect)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace coxswain::perception

BENCHMARK_MAIN();
