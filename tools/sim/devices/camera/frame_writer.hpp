// SPDX-License-Identifier: Apache-2.0
#pragma once
// The simulator's camera: rendered frames handed to the unmodified daemon through a "follow
// directory" (devices.yaml `camera.source: follow:<directory>`; the protocol and why it was chosen
// are in coxswain/drivers/camera/frame_source.hpp). Each write() encodes the frame into a hidden
// temporary file in the directory and renames it to frame-<index>.<ext>, so the daemon only ever
// sees whole files; frames older than `keep_frames` are deleted so the directory stays small.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>

namespace coxswain::sim::devices::camera {

struct FrameWriterOptions {
  /// Image format by extension. ".bmp" is lossless and costs almost nothing to encode (about
  /// 1 ms for 640x480); ".png" is smaller on disk but ~10x slower; a lossy ".jpg" shifts colours.
  std::string extension = ".bmp";
  /// Frames kept on disk behind the newest; a reader slower than this many frames skips ahead.
  std::size_t keep_frames = 4;
};

/// Writes numbered frames into one directory. Not thread-safe (one simulator thread writes);
/// the daemon reads the directory concurrently through the file system.
class FrameDirWriter {
 public:
  /// Creates `directory` if needed and removes frame files a previous run left there (their
  /// higher indices would otherwise shadow this run's frames). Throws std::invalid_argument when
  /// no encoder knows `options.extension`, std::filesystem_error when the directory cannot be
  /// created.
  explicit FrameDirWriter(std::filesystem::path directory, FrameWriterOptions options = {});
  FrameDirWriter(const FrameDirWriter&) = delete;
  FrameDirWriter& operator=(const FrameDirWriter&) = delete;
  /// Leaves the frames on disk (a reader may still be looking); remove_all() clears them.
  ~FrameDirWriter() = default;

  /// Publishes `bgr` (CV_8UC3) as the next frame. False (nothing published) when the frame is
  /// empty or the file cannot be written.
  bool write(const cv::Mat& bgr);
  /// Deletes every frame file (and temporary) of this writer's directory.
  void remove_all();

  /// devices.yaml `camera.source` that makes the daemon read these frames.
  [[nodiscard]] std::string source() const;
  [[nodiscard]] const std::filesystem::path& directory() const { return directory_; }
  /// Index of the newest frame written (frames are numbered from 1); 0 before the first.
  [[nodiscard]] std::uint64_t last_index() const { return index_; }

 private:
  std::filesystem::path directory_;
  FrameWriterOptions options_;
  std::uint64_t index_ = 0;
};

}  // namespace coxswain::sim::devices::camera
