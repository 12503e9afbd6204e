// SPDX-License-Identifier: Apache-2.0
#pragma once
// Image files and video capture through a module loaded on first use. OpenCV's imgcodecs and
// videoio bring some 120 shared libraries with them (GDAL, GStreamer, FFmpeg, ...), about 48 MB
// of resident memory in every process that links them; a boat without a camera, or with one that
// has not yet given a frame, should not carry them. The module (libcoxswain_image_io.so) is
// looked for in COXSWAIN_IMAGE_IO_MODULE (a file), beside the executable, in ../lib/coxswain
// from it, and in the build tree it was built in.
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace coxswain::drivers::camera {

/// A camera or a video file (cv::VideoCapture inside the module). Not thread-safe.
class Capture {
 public:
  Capture() = default;
  Capture(const Capture&) = delete;
  Capture& operator=(const Capture&) = delete;
  virtual ~Capture() = default;
  /// `api`: a cv::VideoCaptureAPIs value (cv::CAP_V4L2, cv::CAP_ANY).
  virtual bool open_index(int index, int api) = 0;
  virtual bool open_path(const std::string& path, int api) = 0;
  [[nodiscard]] virtual bool is_opened() const = 0;
  virtual bool grab() = 0;
  virtual bool retrieve(cv::Mat& bgr) = 0;
  virtual bool read(cv::Mat& bgr) = 0;
  virtual bool set(int prop, double value) = 0;  // cv::VideoCaptureProperties
  [[nodiscard]] virtual double get(int prop) const = 0;
  virtual void release() = 0;
};

/// What the module hands out. Its functions never throw.
struct ImageIoModule {
  static constexpr int kAbiVersion = 1;
  int abi_version = 0;
  cv::Mat (*read_image)(const std::string& path) = nullptr;  // BGR; empty when unreadable
  bool (*encode_jpeg)(const cv::Mat& bgr, int quality, std::vector<std::uint8_t>& out) = nullptr;
  Capture* (*new_capture)() = nullptr;  // owned by the caller
};

/// The module, loaded once on the first call (thread-safe); nullptr when it cannot be loaded,
/// with the reason in `error`.
const ImageIoModule* image_io(std::string* error = nullptr);

/// Whether the module file is there, without loading it (a source checks this when it opens
/// and loads the module with its first frame).
bool image_io_installed(std::string* error = nullptr);

/// An image file as BGR; empty when unreadable or when the module is missing (`error` says).
cv::Mat read_image(const std::string& path, std::string* error = nullptr);

/// A new capture, or nullptr with the reason.
std::unique_ptr<Capture> make_capture(std::string& error);

}  // namespace coxswain::drivers::camera
