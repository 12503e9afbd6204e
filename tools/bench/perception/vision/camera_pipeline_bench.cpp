// SPDX-License-Identifier: Apache-2.0
// Cost per camera frame of the whole camera perception (CameraPipeline: every marker and buoy of
// every colour from one set of masks), compared with running the two detectors one after the
// other, on a generated dock scene with sensor noise.
#include <benchmark/benchmark.h>

#include "coxswain/perception/camera_pipeline.hpp"
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
  gen::draw_shape(img, msg::Shape::kCircle, {0.9F * w, 0.8F * h}, 0.08F * h, 0,
                  gen::paint_bgr(msg::Colour::kRed));
  gen::add_noise(img, 6.0, 11);
  return img;
}

void BM_CameraPipeline(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const int height = static_cast<int>(state.range(1));
  const cv::Mat img = dock_scene(width, height);
  CameraPipeline pipeline(VisionParams::defaults(), 80.0, core::MountTransform{});
  msg::CameraDetections out;
  const bool ok = pipeline.process(img, 0, out) &&
                  find_target(out, msg::Colour::kGreen, msg::Shape::kCircle).has_value() &&
                  find_target(out, msg::Colour::kBlue, msg::Shape::kCross).has_value() &&
                  find_target(out, msg::Colour::kBlack, msg::Shape::kTriangle).has_value() &&
                  BuoyDetector::largest(out, msg::Colour::kRed) != nullptr;
  if (!ok) state.SkipWithError("scene not detected");
  core::TimeNs t = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(pipeline.process(img, ++t, out));
    benchmark::DoNotOptimize(out.count);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["detections"] = static_cast<double>(out.count);
}
BENCHMARK(BM_CameraPipeline)
    ->Args({640, 480})
    ->Args({320, 240})
    ->Args({1280, 720})
    ->Unit(benchmark::kMillisecond);

/// The same work done by the two detectors separately (each builds its own masks).
void BM_SeparateDetectors(benchmark::State& state) {
  const cv::Mat img = dock_scene(640, 480);
  MarkerDetector markers;
  BuoyDetector buoys;
  msg::CameraDetections m;
  msg::CameraDetections b;
  core::TimeNs t = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(markers.detect(img, ++t, m));
    benchmark::DoNotOptimize(buoys.detect(img, t, b));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_SeparateDetectors)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace coxswain::perception

BENCHMARK_MAIN();
