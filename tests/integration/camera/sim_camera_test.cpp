// SPDX-License-Identifier: Apache-2.0
// The simulator's camera path end to end: a devices.yaml naming `follow:<dir>` is loaded like the
// daemon loads it, the simulator side renders a dock scene at 30 fps into that directory with
// FrameDirWriter (its own thread, real time), and the daemon side's CameraDriver fills the
// LatestStore that the tick reads: detections fresh, markers and buoys right, health running at
// about the writer's rate.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <thread>

#include "camera_test_util.hpp"
#include "coxswain/config/config.hpp"
#include "coxswain/core/latest_store.hpp"
#include "coxswain/drivers/camera/camera_driver.hpp"
#include "coxswain/perception/marker_detector.hpp"
#include "sim/devices/camera/frame_writer.hpp"
#include "vision_scene.hpp"

namespace coxswain {
namespace {

namespace fs = std::filesystem;
namespace gen = perception::testing;
using msg::Colour;
using msg::Shape;

/// Dock seen from the water, drifting sideways by `shift_px` (the boat yawing).
cv::Mat render(int frame, float shift_px) {
  cv::Mat img = gen::water_background(640, 480);
  const float dx = shift_px * std::sin(0.2F * static_cast<float>(frame));
  gen::draw_marker(img, Shape::kCircle, Colour::kGreen, {150.0F + dx, 200.0F}, 60.0F, 0);
  gen::draw_marker(img, Shape::kCross, Colour::kBlue, {320.0F + dx, 200.0F}, 60.0F, 15);
  gen::draw_marker(img, Shape::kTriangle, Colour::kBlack, {490.0F + dx, 200.0F}, 60.0F, 0);
  gen::draw_shape(img, Shape::kCircle, {320.0F + dx, 400.0F}, 40.0F, 0,
                  gen::paint_bgr(Colour::kPurple));
  gen::add_noise(img, 4.0, static_cast<std::uint64_t>(frame) + 1U);
  return img;
}

TEST(SimCamera, WriterToDriverToStore) {
  drivers::camera::testing::ScratchDir dir("integration");
  const fs::path frames = dir.path() / "camera";
  const fs::path devices_yaml = dir.path() / "devices.yaml";
  {
    std::ofstream out(devices_yaml);
    out << "kind: devices\n"
           "lidar: {enabled: false}\nimu: {enabled: false}\ngnss: {enabled: false}\n"
           "arduino: {enabled: false}\n"
           "camera:\n  source: \"follow:"
        << frames.string() << "\"\n  fps: 30\n  hfov_deg: 70\n  timeout_ms: 2000\n";
  }
  config::ConfigErrors errors;
  const config::DevicesConfig devices = config::load_devices_config(devices_yaml.string(), errors);
  ASSERT_TRUE(errors.empty()) << errors.format();
  ASSERT_EQ(drivers::camera::classify_source(devices.camera.source).kind,
            drivers::camera::SourceKind::kFollowDirectory);

  // Simulator side: the writer must exist before the daemon looks (the real simulator starts
  // first), but the driver also copes with the directory appearing later.
  sim::devices::camera::FrameDirWriter writer(frames);
  std::atomic<bool> stop{false};
  std::atomic<int> written{0};
  std::thread sim([&] {
    auto next = std::chrono::steady_clock::now();
    for (int k = 0; !stop.load(); ++k) {
      if (writer.write(render(k, 20.0F))) written.fetch_add(1);
      next += std::chrono::microseconds(33'333);
      std::this_thread::sleep_until(next);
    }
  });

  // Daemon side.
  core::LatestStore store;
  core::SteadyClock clock;
  drivers::camera::LatestFrame latest_frame;
  const core::MountTransform mount{0.0, 0.05, 0.0};
  drivers::camera::CameraDriver driver(devices.camera, mount, perception::VisionParams::defaults(),
                                       store.camera, store.health_of(msg::DeviceId::kCamera), clock,
                                       &latest_frame);
  driver.start();

  // The tick's view: fresh detections holding the three markers and the buoy.
  auto snapshot = std::make_unique<core::Snapshot>();
  const bool seen = drivers::camera::testing::wait_until(
      [&] {
        store.snapshot(*snapshot);
        const msg::CameraDetections& d = snapshot->camera.value;
        const auto& health = snapshot->health[static_cast<std::size_t>(msg::DeviceId::kCamera)];
        return snapshot->camera.valid() && snapshot->camera.sequence >= 30 &&
               health.value.rate_hz > 0.0 &&  // a rate needs a second of frames
               perception::find_target(d, Colour::kGreen, Shape::kCircle) &&
               perception::find_target(d, Colour::kBlue, Shape::kCross) &&
               perception::find_target(d, Colour::kBlack, Shape::kTriangle);
      },
      20.0);
  stop.store(true);
  sim.join();
  ASSERT_TRUE(seen) << "camera sequence " << snapshot->camera.sequence;

  const msg::CameraDetections& d = snapshot->camera.value;
  const auto green = perception::find_target(d, Colour::kGreen, Shape::kCircle);
  const auto black = perception::find_target(d, Colour::kBlack, Shape::kTriangle);
  ASSERT_TRUE(green && black);
  EXPECT_LT(green->bearing_deg, -15.0F);  // left placard, port side
  EXPECT_GT(black->bearing_deg, 15.0F);
  EXPECT_LT(std::abs(black->bearing_deg), 35.0F);  // inside the 70-deg field of view
  bool buoy = false;
  for (std::uint32_t i = 0; i < d.count; ++i) {
    buoy |= d.detections[i].colour == Colour::kPurple && d.detections[i].shape == Shape::kBuoy;
  }
  EXPECT_TRUE(buoy);
  EXPECT_EQ(d.image_width_px, 640);
  // Fresh: stamped on the daemon's clock within the last moments of the run.
  EXPECT_LT(clock.now_ns() - snapshot->camera.stamp_ns, 2 * core::kNsPerSec);

  const msg::DeviceHealth& h =
      snapshot->health[static_cast<std::size_t>(msg::DeviceId::kCamera)].value;
  EXPECT_EQ(h.device, msg::DeviceId::kCamera);
  EXPECT_EQ(h.state, msg::DeviceState::kRunning) << h.detail_text();
  EXPECT_EQ(h.framing_errors, 0U);
  // Every written frame was either processed or counted as skipped (the last few may be unread).
  EXPECT_LE(h.frames_ok + h.dropped_frames, static_cast<std::uint64_t>(written.load()));
  // Health is published just after the detections of the same frame: at most one behind.
  EXPECT_GE(h.frames_ok + 1, snapshot->camera.sequence);
  // ~30 Hz unloaded; a loaded machine or a sanitizer build processes fewer and skips the rest.
  EXPECT_GT(h.rate_hz, 0.5);
  EXPECT_LT(h.rate_hz, 45.0);
  EXPECT_GE(latest_frame.sequence(), 30U);
  driver.stop();
}

}  // namespace
}  // namespace coxswain
