// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/camera/frame_source.hpp"

#include "coxswain/drivers/camera/image_io.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <opencv2/videoio.hpp>  // the property and backend numbers only: capture is the module's
#include <sstream>
#include <system_error>
#include <utility>
#include <vector>

namespace coxswain::drivers::camera {
namespace fs = std::filesystem;

namespace {

constexpr std::string_view kFramePrefix = "frame-";
constexpr std::size_t kFrameDigits = 12;

bool all_digits(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c)) != 0;
  });
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool is_image_file(const fs::path& p) {
  static constexpr std::array<std::string_view, 11> kExtensions{
      ".png", ".jpg", ".jpeg", ".bmp", ".ppm", ".pgm", ".pnm", ".tif", ".tiff", ".webp", ".jp2"};
  const std::string name = p.filename().string();
  if (name.empty() || name.front() == '.') return false;  // hidden, e.g. a writer's temporary
  const std::string ext = lower(p.extension().string());
  return std::find(kExtensions.begin(), kExtensions.end(), ext) != kExtensions.end();
}

bool path_exists(const fs::path& p) {
  std::error_code ec;
  return fs::exists(p, ec);
}

std::uint64_t frame_bytes(const cv::Mat& m) {
  return static_cast<std::uint64_t>(m.total()) * static_cast<std::uint64_t>(m.elemSize());
}

/// A V4L2 camera through OpenCV's V4L2 backend (no other backend: a device path must never be
/// opened by, say, FFmpeg with different semantics).
class V4l2Source final : public FrameSource {
 public:
  V4l2Source(std::string path, const config::CameraDeviceConfig& config)
      : path_(std::move(path)), config_(config) {}

  bool open(std::string& detail) override {
    if (!all_digits(path_) && !path_exists(path_)) {
      detail = "no such device " + path_;
      return false;
    }
    if (!cap_ && !(cap_ = make_capture(detail))) return false;
    if (all_digits(path_)) {
      (void)cap_->open_index(std::stoi(path_), cv::CAP_V4L2);
    } else {
      (void)cap_->open_path(path_, cv::CAP_V4L2);
    }
    if (!cap_->is_opened()) {
      detail = "cannot open " + path_ + " as a V4L2 camera";
      return false;
    }
    configure();
    return true;
  }

  std::string settings_report() const override { return report_; }

  ReadResult read(cv::Mat& bgr, const core::Clock& clock) override {
    ReadResult r;
    if (!cap_ || !cap_->grab()) {
      // An unplugged camera fails its grabs and its node disappears.
      r.status = all_digits(path_) || path_exists(path_) ? ReadStatus::kFailed : ReadStatus::kLost;
      return r;
    }
    r.stamp_ns = clock.now_ns();  // the grab returned: this frame was just captured
    if (!cap_->retrieve(bgr) || bgr.empty() || bgr.type() != CV_8UC3) {
      r.status = ReadStatus::kFailed;
      return r;
    }
    r.status = ReadStatus::kFrame;
    r.bytes = frame_bytes(bgr);
    return r;
  }

  bool paced() const override { return false; }
  SourceKind kind() const override { return SourceKind::kV4l2; }

 private:
  void configure() {
    // V4L2 exposure_auto: 1 = manual, 3 = aperture priority (automatic).
    const double auto_exposure = config_.auto_exposure ? 3.0 : 1.0;
    const std::array<std::pair<const char*, std::pair<int, double>>, 8> wanted{{
        {"width_px", {cv::CAP_PROP_FRAME_WIDTH, static_cast<double>(config_.width_px)}},
        {"height_px", {cv::CAP_PROP_FRAME_HEIGHT, static_cast<double>(config_.height_px)}},
        {"fps", {cv::CAP_PROP_FPS, config_.fps}},
        {"auto_exposure", {cv::CAP_PROP_AUTO_EXPOSURE, auto_exposure}},
        {"exposure", {cv::CAP_PROP_EXPOSURE, config_.exposure}},
        {"saturation", {cv::CAP_PROP_SATURATION, config_.saturation}},
        {"contrast", {cv::CAP_PROP_CONTRAST, config_.contrast}},
        {"brightness", {cv::CAP_PROP_BRIGHTNESS, config_.brightness}},
    }};
    // One buffered frame: detections should describe the newest image, not one queued behind.
    (void)cap_->set(cv::CAP_PROP_BUFFERSIZE, 1.0);
    for (const auto& [name, prop] : wanted) {
      // Exposure is only settable (and meaningful) in manual mode.
      if (prop.first == cv::CAP_PROP_EXPOSURE && config_.auto_exposure) continue;
      (void)cap_->set(prop.first, prop.second);
    }
    std::ostringstream diff;
    for (const auto& [name, prop] : wanted) {
      if (prop.first == cv::CAP_PROP_EXPOSURE && config_.auto_exposure) continue;
      const double got = cap_->get(prop.first);
      if (std::abs(got - prop.second) > 0.5) {
        if (diff.tellp() > 0) diff << ", ";
        diff << name << " " << prop.second << " -> " << got;
      }
    }
    report_ = diff.str();
  }

  std::string path_;
  config::CameraDeviceConfig config_;
  std::unique_ptr<Capture> cap_;
  std::string report_;
};

/// A video file through any backend OpenCV has (FFmpeg, or its built-in MJPEG reader).
class VideoFileSource final : public FrameSource {
 public:
  VideoFileSource(std::string path, bool loop) : path_(std::move(path)), loop_(loop) {}

  bool open(std::string& detail) override {
    if (!path_exists(path_)) {
      detail = "no such file " + path_;
      return false;
    }
    if (!cap_ && !(cap_ = make_capture(detail))) return false;
    if (!cap_->open_path(path_, cv::CAP_ANY)) {
      detail = "cannot decode video " + path_;
      return false;
    }
    frames_since_open_ = 0;
    return true;
  }

  ReadResult read(cv::Mat& bgr, const core::Clock& clock) override {
    ReadResult r;
    if (!cap_ || !cap_->read(bgr)) {
      if (!path_exists(path_)) {
        r.status = ReadStatus::kLost;
        return r;
      }
      // Reopening is the one way to rewind that every backend supports; a file that yields no
      // frame at all is not looped (that would spin).
      if (!loop_ || frames_since_open_ == 0) {
        r.status = ReadStatus::kEnd;
        return r;
      }
      cap_->release();
      std::string detail;
      if (!open(detail) || !cap_->read(bgr)) {
        r.status = ReadStatus::kLost;
        return r;
      }
    }
    r.stamp_ns = clock.now_ns();
    if (bgr.empty() || bgr.type() != CV_8UC3) {
      r.status = ReadStatus::kFailed;
      return r;
    }
    ++frames_since_open_;
    r.status = ReadStatus::kFrame;
    r.bytes = frame_bytes(bgr);
    return r;
  }

  bool paced() const override { return true; }
  SourceKind kind() const override { return SourceKind::kVideoFile; }

 private:
  std::string path_;
  bool loop_;
  std::unique_ptr<Capture> cap_;
  std::uint64_t frames_since_open_ = 0;
};

/// The image files of a directory, in file-name order.
class ImageDirectorySource final : public FrameSource {
 public:
  ImageDirectorySource(std::string path, bool loop) : dir_(std::move(path)), loop_(loop) {}

  bool open(std::string& detail) override {
    files_.clear();
    next_ = 0;
    std::error_code ec;
    for (fs::directory_iterator it(dir_, ec), end; !ec && it != end; it.increment(ec)) {
      if (is_image_file(it->path())) files_.push_back(it->path());
    }
    if (ec) {
      detail = "cannot list " + dir_.string() + ": " + ec.message();
      return false;
    }
    if (files_.empty()) {
      detail = "no image files in " + dir_.string();
      return false;
    }
    if (!image_io_installed(&detail)) return false;
    std::sort(files_.begin(), files_.end(),
              [](const fs::path& a, const fs::path& b) { return a.filename() < b.filename(); });
    return true;
  }

  ReadResult read(cv::Mat& bgr, const core::Clock& clock) override {
    ReadResult r;
    if (next_ >= files_.size()) {
      if (!loop_) {
        r.status = ReadStatus::kEnd;
        return r;
      }
      next_ = 0;
    }
    const fs::path& file = files_[next_++];
    bgr = read_image(file.string());
    r.stamp_ns = clock.now_ns();
    if (bgr.empty()) {
      r.status = path_exists(dir_) ? ReadStatus::kFailed : ReadStatus::kLost;
      return r;
    }
    std::error_code ec;
    const auto size = fs::file_size(file, ec);
    r.bytes = ec ? frame_bytes(bgr) : static_cast<std::uint64_t>(size);
    r.status = ReadStatus::kFrame;
    return r;
  }

  bool paced() const override { return true; }
  SourceKind kind() const override { return SourceKind::kImageDirectory; }

 private:
  fs::path dir_;
  bool loop_;
  std::vector<fs::path> files_;
  std::size_t next_ = 0;
};

/// The newest frame a writer (the simulator) put into a directory; see the header comment.
class FollowDirectorySource final : public FrameSource {
 public:
  explicit FollowDirectorySource(std::string path) : dir_(std::move(path)) {}

  bool open(std::string& detail) override {
    std::error_code ec;
    if (!fs::is_directory(dir_, ec)) {
      detail = "no frame directory " + dir_.string();
      return false;
    }
    // The module itself loads with the first frame; a boat whose camera shows nothing yet
    // does not carry it.
    if (!image_io_installed(&detail)) return false;
    have_last_ = false;
    return true;
  }

  ReadResult read(cv::Mat& bgr, const core::Clock& clock) override {
    ReadResult r;
    std::error_code ec;
    bool found = false;
    std::uint64_t newest = 0;
    for (fs::directory_iterator it(dir_, ec), end; !ec && it != end; it.increment(ec)) {
      const auto index = parse_follow_frame_index(it->path().filename().native());
      if (index && (!found || *index > newest)) {
        found = true;
        newest = *index;
        newest_path_ = it->path();
      }
    }
    if (ec) {
      r.status = path_exists(dir_) ? ReadStatus::kNotYet : ReadStatus::kLost;
      return r;
    }
    // Nothing new. A newest index below the last one means the writer started again.
    if (!found || (have_last_ && newest == last_)) {
      r.status = ReadStatus::kNotYet;
      return r;
    }
    r.stamp_ns = clock.now_ns();  // the frame appeared now (the writer renders in real time)
    bgr = read_image(newest_path_.string());
    if (bgr.empty()) {
      if (!path_exists(newest_path_)) {
        // Deleted between the listing and the read: a newer one is already there.
        r.status = ReadStatus::kNotYet;
        return r;
      }
      r.status = ReadStatus::kFailed;  // undecodable: counted once, never retried
    } else {
      r.status = ReadStatus::kFrame;
      r.bytes = frame_bytes(bgr);
    }
    r.skipped = have_last_ && newest > last_ ? newest - last_ - 1 : 0;
    have_last_ = true;
    last_ = newest;
    return r;
  }

  bool paced() const override { return false; }
  SourceKind kind() const override { return SourceKind::kFollowDirectory; }

 private:
  fs::path dir_;
  fs::path newest_path_;
  bool have_last_ = false;
  std::uint64_t last_ = 0;
};

}  // namespace

std::string_view source_kind_name(SourceKind kind) {
  switch (kind) {
    case SourceKind::kV4l2:
      return "v4l2";
    case SourceKind::kVideoFile:
      return "video file";
    case SourceKind::kImageDirectory:
      return "image directory";
    case SourceKind::kFollowDirectory:
      return "follow directory";
  }
  return "unknown";
}

SourceSpec classify_source(const std::string& source) {
  if (source.rfind(kFollowPrefix, 0) == 0) {
    return {SourceKind::kFollowDirectory, source.substr(kFollowPrefix.size())};
  }
  std::error_code ec;
  if (fs::is_directory(source, ec)) return {SourceKind::kImageDirectory, source};
  if (all_digits(source) || source.rfind("/dev/", 0) == 0 || fs::is_character_file(source, ec)) {
    return {SourceKind::kV4l2, source};
  }
  return {SourceKind::kVideoFile, source};
}

std::string follow_frame_name(std::uint64_t index, std::string_view extension) {
  std::array<char, 32> digits{};
  std::snprintf(digits.data(), digits.size(), "%012llu", static_cast<unsigned long long>(index));
  std::string name(kFramePrefix);
  name += digits.data();
  name += extension;
  return name;
}

std::optional<std::uint64_t> parse_follow_frame_index(std::string_view file_name) {
  if (file_name.rfind(kFramePrefix, 0) != 0) return std::nullopt;
  const std::string_view rest = file_name.substr(kFramePrefix.size());
  const std::size_t dot = rest.find('.');
  if (dot == std::string_view::npos || dot == rest.size() - 1) return std::nullopt;
  const std::string_view digits = rest.substr(0, dot);
  if (digits.size() < kFrameDigits || digits.size() > 19 || !all_digits(digits)) {
    return std::nullopt;
  }
  std::uint64_t index = 0;
  for (const char c : digits) index = index * 10 + static_cast<std::uint64_t>(c - '0');
  return index;
}

std::unique_ptr<FrameSource> make_frame_source(const SourceSpec& spec,
                                               const config::CameraDeviceConfig& config) {
  switch (spec.kind) {
    case SourceKind::kV4l2:
      return std::make_unique<V4l2Source>(spec.path, config);
    case SourceKind::kVideoFile:
      return std::make_unique<VideoFileSource>(spec.path, config.loop);
    case SourceKind::kImageDirectory:
      return std::make_unique<ImageDirectorySource>(spec.path, config.loop);
    case SourceKind::kFollowDirectory:
      return std::make_unique<FollowDirectorySource>(spec.path);
  }
  return nullptr;
}

}  // namespace coxswain::drivers::camera
