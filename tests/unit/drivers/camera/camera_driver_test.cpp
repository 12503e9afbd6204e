// SPDX-License-Identifier: Apache-2.0
// The camera driver's thread end to end on desk sources: image directories (looping or not), an
// MJPG video file, the simulator's follow directory (frames stamped on the injected clock), the
// source vanishing and coming back, a missing device, a disabled camera, and stop() returning
// promptly from a back-off. Conditions are polled with generous deadlines (loaded CI).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "camera_test_util.hpp"
#include "coxswain/core/angles.hpp"
#include "coxswain/drivers/camera/camera_driver.hpp"
#include "sim/devices/camera/frame_writer.hpp"

namespace coxswain::drivers::camera {
namespace {

namespace fs = std::filesystem;
using msg::Colour;
using msg::DeviceState;
using testing::buoy_frame;
using testing::ScratchDir;
using testing::wait_until;

constexpr int kWidth = 640;
constexpr int kHeight = 480;

struct Rig {
  core::LatestSlot<msg::CameraDetections> detections;
  core::LatestSlot<msg::DeviceHealth> health;
  LatestFrame frame;

  [[nodiscard]] msg::DeviceHealth h() const { return health.read().value; }
  [[nodiscard]] DeviceState state() const { return h().state; }
};

config::CameraDeviceConfig camera_config(const std::string& source) {
  config::CameraDeviceConfig c;
  c.source = source;
  c.fps = 50.0;
  c.hfov_deg = 60.0;
  c.timeout_ms = 1000;
  return c;
}

/// Body-frame bearing of a detection at column x of a 640-px frame, 60 deg hfov, mount yaw.
double expected_bearing_deg(double x_px, double mount_yaw_deg) {
  const double f_px = (kWidth / 2.0) / std::tan(core::deg_to_rad(30.0));
  return core::rad_to_deg(std::atan((x_px - kWidth / 2.0) / f_px)) + mount_yaw_deg;
}

/// The purple buoy's bearing in the newest detections, or NaN.
double purple_bearing_deg(const Rig& rig) {
  const auto s = rig.detections.read();
  for (std::uint32_t i = 0; i < s.value.count; ++i) {
    const msg::Detection& d = s.value.detections[i];
    if (d.colour == Colour::kPurple && d.shape == msg::Shape::kBuoy)
      return static_cast<double>(d.bearing_deg);
  }
  return std::nan("");
}

TEST(CameraDriver, ImageDirectoryDetectionsHealthAndFrames) {
  ScratchDir dir("drv_imgdir");
  const std::array<float, 3> xs{160.0F, 320.0F, 480.0F};
  for (std::size_t i = 0; i < xs.size(); ++i) {
    ASSERT_TRUE(cv::imwrite((dir.path() / ("f" + std::to_string(i) + ".png")).string(),
                            buoy_frame(kWidth, kHeight, xs[i])));
  }
  Rig rig;
  core::SteadyClock clock;
  const core::MountTransform mount{10.0, 0.05, 0.0};
  CameraDriver driver(camera_config(dir.path().string()), mount,
                      perception::VisionParams::defaults(), rig.detections, rig.health, clock,
                      &rig.frame);
  EXPECT_EQ(driver.source().kind, SourceKind::kImageDirectory);
  driver.start();
  ASSERT_TRUE(wait_until([&] { return rig.detections.sequence() >= 7; }));  // looped
  const auto s = rig.detections.read();
  EXPECT_EQ(s.value.image_width_px, kWidth);
  EXPECT_EQ(s.value.image_height_px, kHeight);
  EXPECT_EQ(s.stamp_ns, s.value.stamp_ns);
  EXPECT_LE(s.value.stamp_ns, clock.now_ns());
  // Every frame's buoy comes out at one of the three bearings.
  for (int k = 0; k < 6; ++k) {
    const double b = purple_bearing_deg(rig);
    ASSERT_FALSE(std::isnan(b));
    double best = 1e9;
    for (const float x : xs)
      best = std::min(best, std::abs(b - expected_bearing_deg(static_cast<double>(x), 10.0)));
    EXPECT_LT(best, 0.5) << b;
    const std::uint64_t seq = rig.detections.sequence();
    ASSERT_TRUE(wait_until([&] { return rig.detections.sequence() > seq; }));
  }
  ASSERT_TRUE(wait_until([&] { return rig.h().rate_hz > 0.0; }));
  const msg::DeviceHealth h = rig.h();
  EXPECT_EQ(h.device, msg::DeviceId::kCamera);
  EXPECT_EQ(h.state, DeviceState::kRunning) << h.detail_text();
  EXPECT_NE(h.detail_text().find("640x480"), std::string_view::npos) << h.detail_text();
  EXPECT_GE(h.frames_ok, 7U);
  EXPECT_GT(h.bytes_received, 0U);
  EXPECT_EQ(h.framing_errors, 0U);
  EXPECT_EQ(h.reopen_count, 0U);
  EXPECT_GT(h.rate_hz, 2.0);   // paced at 50 fps; a loaded machine may be slower
  EXPECT_LT(h.rate_hz, 60.0);  // but never faster than config fps
  cv::Mat frame;
  core::TimeNs stamp_ns = 0;
  std::uint64_t seq = 0;
  ASSERT_TRUE(rig.frame.read(frame, stamp_ns, seq));
  EXPECT_EQ(frame.size(), cv::Size(kWidth, kHeight));
  EXPECT_GT(seq, 0U);
  driver.stop();
  EXPECT_EQ(rig.h().detail_text(), "stopped");
}

// Live retuning (the live view's vision.<colour>.* parameters): a new HSV box reaches the camera
// thread between two frames. Purple's hue box moved off the buoy's hue loses the buoy; moved back,
// the buoy is seen again; the field of view and mount yaw stay the camera's.
TEST(CameraDriver, NewHsvRangesAreTakenBeforeTheNextFrame) {
  ScratchDir dir("drv_retune");
  ASSERT_TRUE(cv::imwrite((dir.path() / "a.png").string(), buoy_frame(kWidth, kHeight, 480.0F)));
  Rig rig;
  core::SteadyClock clock;
  const core::MountTransform mount{10.0, 0.05, 0.0};
  const perception::VisionParams defaults = perception::VisionParams::defaults();
  CameraDriver driver(camera_config(dir.path().string()), mount, defaults, rig.detections,
                      rig.health, clock);
  driver.start();
  ASSERT_TRUE(wait_until([&] { return !std::isnan(purple_bearing_deg(rig)); }));

  perception::VisionParams blind = defaults;
  const int purple = blind.find_colour(Colour::kPurple);
  ASSERT_GE(purple, 0);
  auto& hsv = blind.colours[static_cast<std::size_t>(purple)].hsv;
  hsv.h_min = 60;  // green hues: the purple buoy no longer matches
  hsv.h_max = 70;
  ASSERT_FALSE(blind.validate().has_value());
  driver.set_vision(blind);
  // Two frames after the request have been processed with the new box.
  auto next_two_frames = [&] {
    const std::uint64_t seq = rig.detections.sequence();
    return wait_until([&] { return rig.detections.sequence() >= seq + 2; });
  };
  ASSERT_TRUE(next_two_frames());
  EXPECT_TRUE(std::isnan(purple_bearing_deg(rig)));
  driver.set_vision(defaults);
  ASSERT_TRUE(next_two_frames());
  const double b = purple_bearing_deg(rig);
  ASSERT_FALSE(std::isnan(b));
  EXPECT_NEAR(b, expected_bearing_deg(480.0, 10.0), 0.5);  // hfov and mount yaw kept
  driver.stop();
  EXPECT_EQ(driver.vision().colours[static_cast<std::size_t>(purple)].hsv.h_min,
            defaults.colours[static_cast<std::size_t>(purple)].hsv.h_min);
  EXPECT_DOUBLE_EQ(driver.vision().hfov_deg, 60.0);
}

TEST(CameraDriver, PlaybackWithoutLoopEndsStale) {
  ScratchDir dir("drv_noloop");
  for (int i = 0; i < 2; ++i) {
    ASSERT_TRUE(cv::imwrite((dir.path() / ("f" + std::to_string(i) + ".bmp")).string(),
                            buoy_frame(320, 240, 100.0F)));
  }
  Rig rig;
  core::SteadyClock clock;
  config::CameraDeviceConfig c = camera_config(dir.path().string());
  c.loop = false;
  CameraDriver driver(c, {}, perception::VisionParams::defaults(), rig.detections, rig.health,
                      clock);
  driver.start();
  ASSERT_TRUE(wait_until([&] { return rig.state() == DeviceState::kStale; }));
  EXPECT_NE(rig.h().detail_text().find("end of"), std::string_view::npos);
  EXPECT_EQ(rig.h().frames_ok, 2U);
  EXPECT_EQ(rig.detections.sequence(), 2U);
}

TEST(CameraDriver, VideoFile) {
  ScratchDir dir("drv_video");
  std::vector<cv::Mat> frames;
  for (int i = 0; i < 4; ++i) frames.push_back(buoy_frame(kWidth, kHeight, 320.0F));
  const fs::path file = dir.path() / "run.avi";
  if (!testing::write_mjpg_avi(file, frames, 25.0)) {
    GTEST_SKIP() << "this OpenCV build cannot write MJPG .avi files with cv::VideoWriter";
  }
  Rig rig;
  core::SteadyClock clock;
  CameraDriver driver(camera_config(file.string()), {}, perception::VisionParams::defaults(),
                      rig.detections, rig.health, clock);
  EXPECT_EQ(driver.source().kind, SourceKind::kVideoFile);
  driver.start();
  ASSERT_TRUE(wait_until([&] { return rig.detections.sequence() >= 6; }));  // looped
  EXPECT_NEAR(purple_bearing_deg(rig), 0.0, 0.5);
  EXPECT_EQ(rig.state(), DeviceState::kRunning);
}

TEST(CameraDriver, FollowDirectoryStampsOnInjectedClock) {
  ScratchDir dir("drv_follow");
  sim::devices::camera::FrameDirWriter writer(dir.path() / "cam");
  Rig rig;
  core::ManualClock clock(1'000);
  CameraDriver driver(camera_config(writer.source()), {}, perception::VisionParams::defaults(),
                      rig.detections, rig.health, clock, &rig.frame);
  driver.start();
  ASSERT_TRUE(wait_until([&] { return rig.state() == DeviceState::kConfiguring; }));
  for (int k = 1; k <= 5; ++k) {
    clock.set_ns(1'000 * (k + 1));
    const float x = 100.0F * static_cast<float>(k);
    const std::uint64_t before = rig.detections.sequence();
    ASSERT_TRUE(writer.write(buoy_frame(kWidth, kHeight, x)));
    ASSERT_TRUE(wait_until([&] { return rig.detections.sequence() > before; })) << k;
    const auto s = rig.detections.read();
    EXPECT_EQ(s.value.stamp_ns, 1'000 * (k + 1));
    EXPECT_NEAR(purple_bearing_deg(rig), expected_bearing_deg(static_cast<double>(x), 0.0), 0.5)
        << k;
  }
  // Health and the frame hand-off follow the detections within moments.
  EXPECT_TRUE(wait_until([&] { return rig.h().frames_ok == 5U; })) << rig.h().frames_ok;
  EXPECT_TRUE(wait_until([&] { return rig.frame.sequence() == 5U; })) << rig.frame.sequence();
  EXPECT_EQ(rig.state(), DeviceState::kRunning);
}

TEST(CameraDriver, SourceVanishesAndComesBack) {
  ScratchDir dir("drv_unplug");
  const fs::path cam = dir.path() / "cam";
  auto writer = std::make_unique<sim::devices::camera::FrameDirWriter>(cam);
  Rig rig;
  core::SteadyClock clock;
  CameraDriver driver(camera_config(writer->source()), {}, perception::VisionParams::defaults(),
                      rig.detections, rig.health, clock);
  driver.start();
  ASSERT_TRUE(wait_until([&] {
    (void)writer->write(buoy_frame(kWidth, kHeight, 200.0F));
    return rig.state() == DeviceState::kRunning;
  }));
  // Unplugged: the directory disappears.
  writer.reset();
  fs::remove_all(cam);
  ASSERT_TRUE(wait_until([&] { return rig.state() == DeviceState::kAbsent; }));
  ASSERT_TRUE(wait_until([&] { return rig.h().reopen_count >= 2; }));
  const std::uint64_t frames_before = rig.h().frames_ok;
  // Plugged back in.
  writer = std::make_unique<sim::devices::camera::FrameDirWriter>(cam);
  ASSERT_TRUE(wait_until([&] {
    (void)writer->write(buoy_frame(kWidth, kHeight, 440.0F));
    return rig.state() == DeviceState::kRunning && rig.h().frames_ok > frames_before;
  }));
  EXPECT_NEAR(purple_bearing_deg(rig), expected_bearing_deg(440.0, 0.0), 0.5);
}

TEST(CameraDriver, FollowWriterSilentGoesStale) {
  ScratchDir dir("drv_stale");
  sim::devices::camera::FrameDirWriter writer(dir.path() / "cam");
  Rig rig;
  core::SteadyClock clock;
  config::CameraDeviceConfig c = camera_config(writer.source());
  c.timeout_ms = 100;
  CameraDriver driver(c, {}, perception::VisionParams::defaults(), rig.detections, rig.health,
                      clock);
  driver.start();
  ASSERT_TRUE(writer.write(buoy_frame(kWidth, kHeight, 200.0F)));
  ASSERT_TRUE(wait_until([&] { return rig.h().frames_ok == 1; }));
  ASSERT_TRUE(wait_until([&] { return rig.state() == DeviceState::kStale; }));
  EXPECT_NE(rig.h().detail_text().find("no frame for 100 ms"), std::string_view::npos);
  ASSERT_TRUE(writer.write(buoy_frame(kWidth, kHeight, 200.0F)));
  ASSERT_TRUE(wait_until([&] { return rig.state() == DeviceState::kRunning; }));
}

TEST(CameraDriver, MissingDeviceRetriesAndStopIsPrompt) {
  Rig rig;
  core::SteadyClock clock;
  CameraDriver driver(camera_config("/dev/video_coxswain_test_missing"), {},
                      perception::VisionParams::defaults(), rig.detections, rig.health, clock);
  EXPECT_EQ(driver.source().kind, SourceKind::kV4l2);
  driver.start();
  ASSERT_TRUE(wait_until([&] { return rig.state() == DeviceState::kAbsent; }));
  EXPECT_NE(rig.h().detail_text().find("no such device"), std::string_view::npos);
  // Back-off 100, 200, 400, 800 ms: the fifth attempt starts after about 1.5 s, then 1.6 s and
  // 2 s waits follow. Stop in the middle of a long wait.
  ASSERT_TRUE(wait_until([&] { return rig.h().reopen_count >= 4; }));
  const std::uint32_t reopens = rig.h().reopen_count;
  EXPECT_LE(reopens, 5U);  // no busy retrying
  const auto t0 = std::chrono::steady_clock::now();
  driver.stop();
  const auto stop_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(stop_s, 1.0);  // the back-off wait is 1.6 s or more: stop() woke it
  EXPECT_EQ(rig.detections.sequence(), 0U);
}

TEST(CameraDriver, StopWhilePlayingAndRestart) {
  ScratchDir dir("drv_stop");
  ASSERT_TRUE(cv::imwrite((dir.path() / "a.png").string(), buoy_frame(320, 240, 50.0F)));
  Rig rig;
  core::SteadyClock clock;
  config::CameraDeviceConfig c = camera_config(dir.path().string());
  c.fps = 2.0;  // a 500 ms pacing wait
  CameraDriver driver(c, {}, perception::VisionParams::defaults(), rig.detections, rig.health,
                      clock);
  driver.start();
  ASSERT_TRUE(wait_until([&] { return rig.detections.sequence() >= 1; }));
  const auto t0 = std::chrono::steady_clock::now();
  driver.stop();
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 0.4);
  driver.stop();  // idempotent
  const std::uint64_t seq = rig.detections.sequence();
  driver.start();
  ASSERT_TRUE(wait_until([&] { return rig.detections.sequence() > seq; }));
}

TEST(CameraDriver, DisabledPublishesOnce) {
  Rig rig;
  core::SteadyClock clock;
  config::CameraDeviceConfig c = camera_config("/dev/videoCAM");
  c.enabled = false;
  CameraDriver driver(c, {}, perception::VisionParams::defaults(), rig.detections, rig.health,
                      clock);
  driver.start();
  EXPECT_EQ(rig.health.sequence(), 1U);
  EXPECT_EQ(rig.state(), DeviceState::kDisabled);
  driver.stop();
}

TEST(LatestFrame, ConcurrentPublishAndReadNeverTear) {
  LatestFrame latest;
  cv::Mat out;
  core::TimeNs stamp_ns = 0;
  std::uint64_t seq = 0;
  EXPECT_FALSE(latest.read(out, stamp_ns, seq));
  std::atomic<bool> done{false};
  std::thread writer([&] {
    cv::Mat frame(120, 160, CV_8UC3);
    for (int k = 1; k <= 300; ++k) {
      frame.setTo(cv::Scalar(k % 256, k % 256, k % 256));
      latest.publish(frame, k);
    }
    done.store(true);
  });
  std::uint64_t last_seq = 0;
  int reads = 0;
  std::string problem;  // first inconsistency seen; checked after the writer is joined
  while ((!done.load() || reads == 0) && problem.empty()) {
    if (!latest.read(out, stamp_ns, seq)) continue;
    ++reads;
    // Whole frames only: every pixel holds the value of the publish that the stamp names.
    const auto value = static_cast<double>(stamp_ns % 256);
    double min_v = 0.0;
    double max_v = 0.0;
    cv::minMaxLoc(out.reshape(1), &min_v, &max_v);
    if (min_v != value || max_v != value)
      problem = "torn frame at stamp " + std::to_string(stamp_ns);
    if (seq < last_seq) problem = "sequence went back";
    if (static_cast<core::TimeNs>(seq) != stamp_ns) problem = "stamp and sequence disagree";
    last_seq = seq;
  }
  writer.join();
  EXPECT_TRUE(problem.empty()) << problem;
  EXPECT_GT(reads, 0);
  ASSERT_TRUE(latest.read(out, stamp_ns, seq));
  EXPECT_EQ(seq, 300U);
  EXPECT_EQ(latest.sequence(), 300U);
}

}  // namespace
}  // namespace coxswain::drivers::camera
