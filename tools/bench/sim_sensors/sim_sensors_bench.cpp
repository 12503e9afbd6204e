// SPDX-License-Identifier: Apache-2.0
// Simulated sensor costs: one lidar revolution against a course (per model), one 640x480 camera
// frame (plain, noisy/blurred, glare; and rendered + run through the marker and buoy detectors),
// one GNSS epoch and one IMU sample; and a lockstep 3-minute course with every sensor at its
// real rate, with and without the camera, reporting the real-time factor (simulated / CPU time).
#include <benchmark/benchmark.h>

#include <cmath>
#include <opencv2/core.hpp>

#include "coxswain/core/angles.hpp"
#include "coxswain/perception/buoy_detector.hpp"
#include "coxswain/perception/marker_detector.hpp"
#include "sim/sensors/camera_sim.hpp"
#include "sim/sensors/gnss_sim.hpp"
#include "sim/sensors/imu_sim.hpp"
#include "sim/sensors/lidar_sim.hpp"

namespace coxswain::sim::sensors {
namespace {

/// A KABOAT-like course: a 60 x 40 m pool, three docks along the north wall, 24 buoys.
world::World course() {
  world::World w;
  w.origin = {35.0695, 128.828, 0.0};
  w.walls.push_back(
      {{{-5.0, -20.0}, {55.0, -20.0}, {55.0, 20.0}, {-5.0, 20.0}, {-5.0, -20.0}}, 0.5});
  const msg::Colour colours[] = {msg::Colour::kRed, msg::Colour::kGreen, msg::Colour::kBlue};
  const msg::Shape shapes[] = {msg::Shape::kTriangle, msg::Shape::kCross, msg::Shape::kCircle};
  for (int i = 0; i < 3; ++i) {
    world::Dock d;
    const double e = -4.0 + 4.0 * i;
    d.walls.push_back({{{51.0, e - 0.8}, {55.0, e - 0.8}}, 0.5});
    d.walls.push_back({{{51.0, e + 0.8}, {55.0, e + 0.8}}, 0.5});
    d.marker = {colours[i], shapes[i], 0.6, 1.0, {54.9, e}, 180.0};
    d.entrance = {51.0, e};
    w.docks.push_back(d);
  }
  const msg::Colour buoy_colours[] = {msg::Colour::kRed, msg::Colour::kGreen, msg::Colour::kYellow,
                                      msg::Colour::kOrange};
  for (int i = 0; i < 12; ++i) {
    const double n = 6.0 + 3.5 * i;
    w.buoys.push_back({{n, -3.0 + std::sin(i)}, 0.25, 0.6, buoy_colours[i % 4]});
    w.buoys.push_back({{n, 3.0 + std::cos(i)}, 0.25, 0.6, buoy_colours[(i + 1) % 4]});
  }
  w.buoys.push_back({{30.0, 8.0}, 0.3, 0.8, msg::Colour::kPurple});
  return w;
}

/// A boat driving a slow S up the course at 1.5 m/s.
BoatTruth truth_at(double t_s) {
  BoatTruth b;
  const double psi_deg = 35.0 * std::sin(0.15 * t_s);
  b.pose.heading_deg = psi_deg;
  b.yaw_rate_dps = 35.0 * 0.15 * std::cos(0.15 * t_s);
  const double n = std::fmod(1.5 * t_s, 45.0);
  b.pose.position = {n, 1.2 * std::sin(0.15 * t_s)};  // between the buoy rows
  b.surge_mps = 1.5;
  b.vel_north_mps = 1.5 * std::cos(core::deg_to_rad(psi_deg));
  b.vel_east_mps = 1.5 * std::sin(core::deg_to_rad(psi_deg));
  return b;
}

void BM_LidarRevolution(benchmark::State& state) {
  const auto model = static_cast<LidarModel>(state.range(0));
  LidarSim sim(LidarSimConfig::for_model(model), course());
  const core::TimeNs period = core::sec_to_ns(1.0 / sim.config().rate_hz);
  core::TimeNs t = 0;
  std::uint64_t beams = 0;
  for (auto _ : state) {
    // One revolution in 10 ms runner ticks, as the lockstep runner drives it.
    const core::TimeNs end = t + period;
    for (; t < end; t += core::ms_to_ns(10)) {
      beams += sim.update(t, truth_at(core::ns_to_sec(t))).beams;
    }
    benchmark::DoNotOptimize(sim.scan().point_count);
  }
  state.counters["beams_per_rev"] = static_cast<double>(sim.config().beams_per_revolution());
  state.SetItemsProcessed(static_cast<std::int64_t>(beams));
}
BENCHMARK(BM_LidarRevolution)
    ->Arg(static_cast<int>(LidarModel::kA2M8))
    ->Arg(static_cast<int>(LidarModel::kA3))
    ->Arg(static_cast<int>(LidarModel::kS2))
    ->Unit(benchmark::kMicrosecond);

CameraSimConfig camera_variant(int variant) {
  CameraSimConfig c;
  if (variant >= 1) {
    c.noise_sigma = 4.0;
    c.blur_kernel_px = 3;
  }
  if (variant >= 2) {
    c.glare = true;
    c.sun_bearing_deg = 10.0;
  }
  return c;
}

void BM_CameraRender(benchmark::State& state) {
  CameraSim cam(camera_variant(static_cast<int>(state.range(0))), course());
  cv::Mat frame;
  double t_s = 20.0;
  for (auto _ : state) {
    cam.render(truth_at(t_s).pose, frame);
    t_s += 0.1;
    benchmark::DoNotOptimize(frame.data);
  }
}
// 0 = plain, 1 = noise + blur, 2 = noise + blur + glare.
BENCHMARK(BM_CameraRender)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond);

void BM_CameraRenderAndDetect(benchmark::State& state) {
  CameraSim cam(camera_variant(1), course());
  perception::MarkerDetector markers;
  perception::BuoyDetector buoys;
  msg::CameraDetections out;
  cv::Mat frame;
  double t_s = 20.0;
  for (auto _ : state) {
    cam.render(truth_at(t_s).pose, frame);
    t_s += 0.1;
    benchmark::DoNotOptimize(markers.detect(frame, 0, out));
    benchmark::DoNotOptimize(buoys.detect(frame, 0, out));
  }
}
BENCHMARK(BM_CameraRenderAndDetect)->Unit(benchmark::kMicrosecond);

void BM_GnssEpoch(benchmark::State& state) {
  GnssSim sim(GnssSimConfig{}, {35.0695, 128.828, 0.0});
  core::TimeNs t = 0;
  for (auto _ : state) {
    t += core::ms_to_ns(200);
    benchmark::DoNotOptimize(sim.update(t, truth_at(core::ns_to_sec(t))));
  }
}
BENCHMARK(BM_GnssEpoch);

void BM_ImuSample(benchmark::State& state) {
  ImuSimConfig c;
  c.disturbances.push_back({{30.0, 5.0}, 4.0, 12.0});
  ImuSim sim(c);
  core::TimeNs t = 0;
  for (auto _ : state) {
    t += core::ms_to_ns(10);
    benchmark::DoNotOptimize(sim.update(t, truth_at(core::ns_to_sec(t))));
  }
}
BENCHMARK(BM_ImuSample);

/// Lockstep 3-minute course at 100 Hz runner ticks: lidar (A2M8, 10 Hz), GNSS 5 Hz, IMU 100 Hz,
/// and, when range(0) > 0, the camera (noise + blur) rendered at range(0) Hz; when range(1) is 1
/// each frame also goes through the marker and buoy detectors, as the daemon's camera thread
/// would (that is the daemon's cost, reported so the whole loop's real-time factor is known).
void BM_LockstepCourse3Min(benchmark::State& state) {
  const world::World w = course();
  const double camera_hz = static_cast<double>(state.range(0));
  const bool detect = state.range(1) != 0;
  constexpr double kCourseS = 180.0;
  for (auto _ : state) {
    LidarSim lidar(LidarSimConfig{}, w);
    GnssSim gnss(GnssSimConfig{}, w.origin);
    ImuSim imu(ImuSimConfig{});
    CameraSimConfig cc = camera_variant(1);
    cc.rate_hz = camera_hz > 0.0 ? camera_hz : 1.0;
    CameraSim camera(cc, w);
    perception::MarkerDetector markers;
    perception::BuoyDetector buoys;
    msg::CameraDetections out;
    cv::Mat frame;
    std::uint64_t produced = 0;
    for (core::TimeNs t = 0; t <= core::sec_to_ns(kCourseS); t += core::ms_to_ns(10)) {
      const BoatTruth truth = truth_at(core::ns_to_sec(t));
      produced += lidar.update(t, truth).scan_ready ? 1U : 0U;
      produced += gnss.update(t, truth) ? 1U : 0U;
      produced += imu.update(t, truth) ? 1U : 0U;
      if (camera_hz > 0.0 && camera.update(t, truth.pose, frame)) {
        if (detect) {
          (void)markers.detect(frame, t, out);
          (void)buoys.detect(frame, t, out);
        }
        ++produced;
      }
    }
    benchmark::DoNotOptimize(produced);
  }
  state.counters["realtime_factor"] =
      benchmark::Counter(kCourseS * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate);  // simulated seconds per CPU second
}
BENCHMARK(BM_LockstepCourse3Min)
    ->Args({0, 0})
    ->Args({10, 0})
    ->Args({30, 0})
    ->Args({5, 1})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

}  // namespace
}  // namespace coxswain::sim::sensors
