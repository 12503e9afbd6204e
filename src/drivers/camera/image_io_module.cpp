// SPDX-License-Identifier: Apache-2.0
// The image-I/O module: the one place OpenCV's imgcodecs and videoio are linked for the daemon
// (see image_io.hpp). Every entry catches what OpenCV throws.
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "coxswain/drivers/camera/image_io.hpp"

namespace coxswain::drivers::camera {
namespace {

class OpenCvCapture final : public Capture {
 public:
  bool open_index(int index, int api) override {
    try {
      return cap_.open(index, api) && cap_.isOpened();
    } catch (const cv::Exception&) {
      return false;
    }
  }
  bool open_path(const std::string& path, int api) override {
    try {
      return cap_.open(path, api) && cap_.isOpened();
    } catch (const cv::Exception&) {
      return false;
    }
  }
  bool is_opened() const override { return cap_.isOpened(); }
  bool grab() override {
    try {
      return cap_.grab();
    } catch (const cv::Exception&) {
      return false;
    }
  }
  bool retrieve(cv::Mat& bgr) override {
    try {
      return cap_.retrieve(bgr);
    } catch (const cv::Exception&) {
      return false;
    }
  }
  bool read(cv::Mat& bgr) override {
    try {
      return cap_.read(bgr);
    } catch (const cv::Exception&) {
      return false;
    }
  }
  bool set(int prop, double value) override {
    try {
      return cap_.set(prop, value);
    } catch (const cv::Exception&) {
      return false;
    }
  }
  double get(int prop) const override {
    try {
      return cap_.get(prop);
    } catch (const cv::Exception&) {
      return 0.0;
    }
  }
  void release() override {
    try {
      cap_.release();
    } catch (const cv::Exception&) {
    }
  }

 private:
  cv::VideoCapture cap_;
};

cv::Mat read_image_file(const std::string& path) {
  try {
    return cv::imread(path, cv::IMREAD_COLOR);
  } catch (const cv::Exception&) {
    return {};
  }
}

bool encode_jpeg_image(const cv::Mat& bgr, int quality, std::vector<std::uint8_t>& out) {
  out.clear();
  try {
    const std::vector<int> params{cv::IMWRITE_JPEG_QUALITY, quality};
    if (cv::imencode(".jpg", bgr, out, params)) return true;
  } catch (const cv::Exception&) {
  }
  out.clear();
  return false;
}

Capture* new_opencv_capture() { return new OpenCvCapture(); }

const ImageIoModule kModule{ImageIoModule::kAbiVersion, &read_image_file, &encode_jpeg_image,
                            &new_opencv_capture};

}  // namespace
}  // namespace coxswain::drivers::camera

extern "C" __attribute__((visibility("default"))) const coxswain::drivers::camera::ImageIoModule*
coxswain_image_io_module() {
  // OpenCV builds its codec registry (and registers GDAL's drivers, tens of ms) on first use.
  // The loader calls this once under std::call_once, so the registry is complete before any
  // thread reads an image, and ThreadSanitizer sees why (the registry's own guard lives in
  // uninstrumented OpenCV code).
  (void)cv::haveImageWriter(".bmp");  // looks at the extension only, opens no file
  return &coxswain::drivers::camera::kModule;
}
