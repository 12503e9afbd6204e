// SPDX-License-Identifier: Apache-2.0
#pragma once
// Where camera frames come from. devices.yaml `camera.source` names one of four kinds:
//
// - a V4L2 device ("/dev/videoCAM", any other /dev path, a character device, or a bare index
//   "0"): cv::VideoCapture with cv::CAP_V4L2, configured from CameraDeviceConfig;
// - a video file (anything else that is not a directory): cv::VideoCapture with any backend,
//   played at config fps, looping when `loop`;
// - an image directory: its image files in file-name order, played at config fps, looping when
//   `loop` (desk work on recorded frames);
// - "follow:<directory>": the simulator's camera. The writer (sim/devices/camera/frame_writer.hpp)
//   writes each rendered frame as `frame-<12-digit index>.<ext>` by writing a hidden temporary
//   file and renaming it (rename within a directory is atomic, so a reader never sees half a
//   file), then deletes frames older than a few indices. The reader lists the directory, takes
//   the newest frame newer than the last one it read (frames in between count as dropped) and
//   tolerates files vanishing under it. Chosen over v4l2loopback (a kernel module, unavailable
//   here and on CI) and over a socket stream (needs a protocol, a server, and reconnection on
//   both sides): a directory works with the unmodified daemon, survives either side restarting,
//   and can be inspected by hand. The cost is one small directory listing per poll.
//
// Thread-safety: a FrameSource is used by one thread (the camera driver's).
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <opencv2/core.hpp>

#include "coxswain/config/devices_config.hpp"
#include "coxswain/core/clock.hpp"
#include "coxswain/core/time.hpp"

namespace coxswain::drivers::camera {

enum class SourceKind : std::uint8_t { kV4l2 = 0, kVideoFile, kImageDirectory, kFollowDirectory };

[[nodiscard]] std::string_view source_kind_name(SourceKind kind);

/// What `source` names; the path has any "follow:" prefix removed.
struct SourceSpec {
  SourceKind kind = SourceKind::kV4l2;
  std::string path;
};

inline constexpr std::string_view kFollowPrefix = "follow:";

/// Classifies a devices.yaml `camera.source` (see the header comment). Looks at the file system
/// (is it a directory? a character device?); a path that does not exist yet is a V4L2 device
/// under /dev and a video file elsewhere.
[[nodiscard]] SourceSpec classify_source(const std::string& source);

/// File name of frame `index` in a follow directory: "frame-000000000042.bmp" for (42, ".bmp").
[[nodiscard]] std::string follow_frame_name(std::uint64_t index, std::string_view extension);
/// Index of a follow-directory frame file name, or nullopt for anything else (hidden temporary
/// files, other names).
[[nodiscard]] std::optional<std::uint64_t> parse_follow_frame_index(std::string_view file_name);

/// Result of one FrameSource::read.
enum class ReadStatus : std::uint8_t {
  kFrame = 0,  // `bgr` holds a new frame
  kNotYet,     // nothing new yet (follow directory): poll again later
  kFailed,     // one grab or decode failed; the source may still deliver
  kEnd,        // a file or directory played to its end without `loop`
  kLost,       // the source is gone (unplugged, deleted): close and reopen
};

/// Outcome details of one read.
struct ReadResult {
  ReadStatus status = ReadStatus::kNotYet;
  core::TimeNs stamp_ns = core::kNeverNs;  // capture time of the frame (kFrame only)
  std::uint64_t skipped = 0;  // frames passed over to get to this one (follow directory)
  std::uint64_t bytes = 0;    // size of the frame as read (encoded file or decoded image)
};

/// One opened source of BGR frames.
class FrameSource {
 public:
  virtual ~FrameSource() = default;

  /// Opens (and for V4L2 configures) the source. False with `detail` saying why.
  [[nodiscard]] virtual bool open(std::string& detail) = 0;
  /// Settings the device did not take as asked ("exposure 100 -> 78"), empty when all were
  /// accepted or the source has none. Valid after open().
  [[nodiscard]] virtual std::string settings_report() const { return {}; }
  /// Reads the next frame into `bgr` (CV_8UC3, reusing its buffer where the backend allows),
  /// stamped on `clock` as soon as it was captured or found.
  [[nodiscard]] virtual ReadResult read(cv::Mat& bgr, const core::Clock& clock) = 0;
  /// True when the driver must pace reads at config fps (files and image directories); false
  /// when read() itself waits for the device or the writer (V4L2, follow directory).
  [[nodiscard]] virtual bool paced() const = 0;
  [[nodiscard]] virtual SourceKind kind() const = 0;
};

/// Builds the source `spec` names, configured by `config` (resolution, fps, exposure...; loop).
[[nodiscard]] std::unique_ptr<FrameSource> make_frame_source(
    const SourceSpec& spec, const config::CameraDeviceConfig& config);

}  // namespace coxswain::drivers::camera
