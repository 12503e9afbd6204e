// SPDX-License-Identifier: Apache-2.0
// Frame sources one read at a time (no thread): source classification, the follow-directory
// naming shared with the simulator's writer, image directories in name order with and without
// looping, MJPG video files, and the follow directory taking the newest frame, counting skipped
// ones, surviving deletions and writer restarts, and reporting a vanished directory as lost.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "camera_test_util.hpp"
#include "coxswain/drivers/camera/frame_source.hpp"
#include "sim/devices/camera/frame_writer.hpp"

namespace coxswain::drivers::camera {
namespace {

namespace fs = std::filesystem;
using testing::buoy_frame;
using testing::ScratchDir;

config::CameraDeviceConfig config_for(const std::string& source, bool loop) {
  config::CameraDeviceConfig c;
  c.source = source;
  c.loop = loop;
  return c;
}

/// Mean of the blue channel: tells generated frames apart (each is painted differently).
double mean_blue(const cv::Mat& m) { return cv::mean(m)[0]; }

cv::Mat flat(int blue) { return {48, 64, CV_8UC3, cv::Scalar(blue, 100, 100)}; }

TEST(CameraSource, Classify) {
  ScratchDir dir("classify");
  EXPECT_EQ(classify_source("/dev/videoCAM").kind, SourceKind::kV4l2);
  EXPECT_EQ(classify_source("0").kind, SourceKind::kV4l2);
  EXPECT_EQ(classify_source("/dev/null").kind, SourceKind::kV4l2);  // a character device
  EXPECT_EQ(classify_source(dir.path().string()).kind, SourceKind::kImageDirectory);
  EXPECT_EQ(classify_source((dir.path() / "run.avi").string()).kind, SourceKind::kVideoFile);
  const SourceSpec follow = classify_source("follow:" + dir.path().string());
  EXPECT_EQ(follow.kind, SourceKind::kFollowDirectory);
  EXPECT_EQ(follow.path, dir.path().string());
  // A follow directory that does not exist yet is still a follow directory.
  EXPECT_EQ(classify_source("follow:/nonexistent/x").kind, SourceKind::kFollowDirectory);
}

TEST(CameraSource, FollowFrameNames) {
  EXPECT_EQ(follow_frame_name(42, ".bmp"), "frame-000000000042.bmp");
  EXPECT_EQ(parse_follow_frame_index("frame-000000000042.bmp"), 42U);
  EXPECT_EQ(parse_follow_frame_index(follow_frame_name(123456789012345ULL, ".png")),
            123456789012345ULL);
  EXPECT_FALSE(parse_follow_frame_index(".frame-000000000042.bmp"));  // writer's temporary
  EXPECT_FALSE(parse_follow_frame_index("frame-42.bmp"));             // too few digits
  EXPECT_FALSE(parse_follow_frame_index("frame-000000000042"));       // no extension
  EXPECT_FALSE(parse_follow_frame_index("frame-00000000004x.bmp"));
  EXPECT_FALSE(parse_follow_frame_index("image-000000000042.bmp"));
}

TEST(CameraSource, ImageDirectoryInNameOrderThenEndOrLoop) {
  ScratchDir dir("imgdir");
  // Written out of order; names decide the order. Non-images and hidden files are ignored.
  ASSERT_TRUE(cv::imwrite((dir.path() / "b.png").string(), flat(20)));
  ASSERT_TRUE(cv::imwrite((dir.path() / "a.png").string(), flat(10)));
  ASSERT_TRUE(cv::imwrite((dir.path() / "c.bmp").string(), flat(30)));
  ASSERT_TRUE(cv::imwrite((dir.path() / ".hidden.png").string(), flat(99)));
  { std::ofstream(dir.path() / "notes.txt") << "not an image"; }
  core::ManualClock clock(5);
  cv::Mat frame;
  for (const bool loop : {false, true}) {
    auto src = make_frame_source(classify_source(dir.path().string()),
                                 config_for(dir.path().string(), loop));
    std::string detail;
    ASSERT_TRUE(src->open(detail)) << detail;
    EXPECT_TRUE(src->paced());
    for (const int blue : {10, 20, 30}) {
      const ReadResult r = src->read(frame, clock);
      ASSERT_EQ(r.status, ReadStatus::kFrame);
      EXPECT_NEAR(mean_blue(frame), blue, 0.5);
      EXPECT_EQ(r.stamp_ns, 5);
      EXPECT_GT(r.bytes, 0U);
    }
    const ReadResult r = src->read(frame, clock);
    if (loop) {
      ASSERT_EQ(r.status, ReadStatus::kFrame);
      EXPECT_NEAR(mean_blue(frame), 10, 0.5);
    } else {
      EXPECT_EQ(r.status, ReadStatus::kEnd);
    }
  }
}

TEST(CameraSource, EmptyOrMissingDirectoryDoesNotOpen) {
  ScratchDir dir("empty");
  std::string detail;
  auto src = make_frame_source(classify_source(dir.path().string()),
                               config_for(dir.path().string(), true));
  EXPECT_FALSE(src->open(detail));
  EXPECT_NE(detail.find("no image files"), std::string::npos) << detail;
  auto follow = make_frame_source(classify_source("follow:" + (dir.path() / "x").string()),
                                  config_for("", true));
  EXPECT_FALSE(follow->open(detail));
  auto video =
      make_frame_source(classify_source((dir.path() / "x.avi").string()), config_for("", true));
  EXPECT_FALSE(video->open(detail));
  EXPECT_NE(detail.find("no such file"), std::string::npos) << detail;
}

TEST(CameraSource, VideoFileMjpg) {
  ScratchDir dir("video");
  std::vector<cv::Mat> frames;
  for (int i = 0; i < 5; ++i)
    frames.push_back(buoy_frame(320, 240, 40.0F + 60.0F * static_cast<float>(i)));
  const fs::path file = dir.path() / "run.avi";
  if (!testing::write_mjpg_avi(file, frames, 10.0)) {
    GTEST_SKIP() << "this OpenCV build cannot write MJPG .avi files with cv::VideoWriter";
  }
  core::ManualClock clock(0);
  cv::Mat frame;
  for (const bool loop : {false, true}) {
    auto src = make_frame_source(classify_source(file.string()), config_for(file.string(), loop));
    EXPECT_EQ(src->kind(), SourceKind::kVideoFile);
    std::string detail;
    ASSERT_TRUE(src->open(detail)) << detail;
    for (int i = 0; i < 5; ++i) {
      ASSERT_EQ(src->read(frame, clock).status, ReadStatus::kFrame) << i;
      EXPECT_EQ(frame.cols, 320);
      EXPECT_EQ(frame.rows, 240);
    }
    const ReadResult r = src->read(frame, clock);
    EXPECT_EQ(r.status, loop ? ReadStatus::kFrame : ReadStatus::kEnd);
  }
}

TEST(CameraSource, FollowDirectoryNewestFirstAndDeleteSafe) {
  ScratchDir dir("follow");
  const fs::path frames_dir = dir.path() / "cam";
  // A frame left by an earlier run is cleared by the writer, or it would shadow the new ones.
  fs::create_directories(frames_dir);
  ASSERT_TRUE(cv::imwrite((frames_dir / follow_frame_name(900, ".bmp")).string(), flat(90)));
  sim::devices::camera::FrameDirWriter writer(frames_dir, {".bmp", 3});
  EXPECT_FALSE(fs::exists(frames_dir / follow_frame_name(900, ".bmp")));
  EXPECT_EQ(writer.source(), "follow:" + frames_dir.string());

  auto src = make_frame_source(classify_source(writer.source()), config_for("", true));
  EXPECT_FALSE(src->paced());
  std::string detail;
  ASSERT_TRUE(src->open(detail)) << detail;
  core::ManualClock clock(7);
  cv::Mat frame;
  EXPECT_EQ(src->read(frame, clock).status, ReadStatus::kNotYet);

  ASSERT_TRUE(writer.write(flat(10)));
  ReadResult r = src->read(frame, clock);
  ASSERT_EQ(r.status, ReadStatus::kFrame);
  EXPECT_NEAR(mean_blue(frame), 10, 0.5);
  EXPECT_EQ(r.skipped, 0U);
  EXPECT_EQ(r.stamp_ns, 7);
  EXPECT_EQ(src->read(frame, clock).status, ReadStatus::kNotYet);  // no repeats

  // Four more frames: the newest is read, three counted as skipped, and only three remain on
  // disk (keep_frames).
  for (const int blue : {20, 30, 40, 50}) ASSERT_TRUE(writer.write(flat(blue)));
  r = src->read(frame, clock);
  ASSERT_EQ(r.status, ReadStatus::kFrame);
  EXPECT_NEAR(mean_blue(frame), 50, 0.5);
  EXPECT_EQ(r.skipped, 3U);
  int files = 0;
  for (const auto& e : fs::directory_iterator(frames_dir)) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 3);
  EXPECT_EQ(writer.last_index(), 5U);

  // The newest file deleted before it is read: nothing new, no error.
  ASSERT_TRUE(writer.write(flat(60)));
  fs::remove(frames_dir / follow_frame_name(6, ".bmp"));
  EXPECT_EQ(src->read(frame, clock).status, ReadStatus::kNotYet);
  ASSERT_TRUE(writer.write(flat(70)));
  r = src->read(frame, clock);
  ASSERT_EQ(r.status, ReadStatus::kFrame);
  EXPECT_NEAR(mean_blue(frame), 70, 0.5);

  // An undecodable frame is counted once and passed over.
  { std::ofstream(frames_dir / follow_frame_name(8, ".bmp")) << "garbage"; }
  EXPECT_EQ(src->read(frame, clock).status, ReadStatus::kFailed);
  EXPECT_EQ(src->read(frame, clock).status, ReadStatus::kNotYet);

  // The simulator starts again: a new writer clears the directory and counts from 1.
  sim::devices::camera::FrameDirWriter again(frames_dir, {".bmp", 3});
  ASSERT_TRUE(again.write(flat(15)));
  r = src->read(frame, clock);
  ASSERT_EQ(r.status, ReadStatus::kFrame);
  EXPECT_NEAR(mean_blue(frame), 15, 0.5);

  // The directory vanishes: lost.
  fs::remove_all(frames_dir);
  EXPECT_EQ(src->read(frame, clock).status, ReadStatus::kLost);
  EXPECT_FALSE(src->open(detail));
}

TEST(CameraSource, WriterRejectsBadFrames) {
  ScratchDir dir("writer");
  sim::devices::camera::FrameDirWriter writer(dir.path() / "cam");
  EXPECT_FALSE(writer.write(cv::Mat()));
  EXPECT_FALSE(writer.write(cv::Mat(10, 10, CV_8UC1, cv::Scalar(0))));
  EXPECT_EQ(writer.last_index(), 0U);
  ASSERT_TRUE(writer.write(flat(1)));
  writer.remove_all();
  EXPECT_TRUE(fs::is_empty(writer.directory()));
  // A format no encoder knows is refused when the writer is made, not frame by frame.
  EXPECT_THROW(sim::devices::camera::FrameDirWriter(dir.path() / "odd", {".nosuchformat", 3}),
               std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir.path() / "odd"));
}

}  // namespace
}  // namespace coxswain::drivers::camera
