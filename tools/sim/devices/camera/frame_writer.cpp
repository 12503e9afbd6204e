// SPDX-License-Identifier: Apache-2.0
#include "sim/devices/camera/frame_writer.hpp"

#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <system_error>
#include <utility>
#include <vector>

#include "coxswain/drivers/camera/frame_source.hpp"

namespace coxswain::sim::devices::camera {
namespace fs = std::filesystem;

FrameDirWriter::FrameDirWriter(fs::path directory, FrameWriterOptions options)
    : directory_(std::move(directory)), options_(std::move(options)) {
  // Asking here also builds OpenCV's codec registry on the constructing thread, before any
  // reader thread of this process starts: the registry's own guard is invisible to
  // ThreadSanitizer, so a first write racing a reader's first read would be reported.
  bool writable = false;
  try {
    writable = cv::haveImageWriter(options_.extension);
  } catch (const cv::Exception&) {
  }
  if (!writable) {
    throw std::invalid_argument("camera frame writer: no image encoder for extension '" +
                                options_.extension + "'");
  }
  fs::create_directories(directory_);
  remove_all();
}

void FrameDirWriter::remove_all() {
  std::error_code ec;
  std::vector<fs::path> doomed;
  for (fs::directory_iterator it(directory_, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (drivers::camera::parse_follow_frame_index(name) || name.rfind(".frame-", 0) == 0) {
      doomed.push_back(it->path());
    }
  }
  for (const fs::path& p : doomed) fs::remove(p, ec);
}

bool FrameDirWriter::write(const cv::Mat& bgr) {
  if (bgr.empty() || bgr.type() != CV_8UC3) return false;
  const std::uint64_t index = index_ + 1;
  const std::string name = drivers::camera::follow_frame_name(index, options_.extension);
  // Hidden (leading dot) so a reader never picks it up; same extension so imwrite knows the
  // format; same directory so the rename is atomic.
  const fs::path tmp = directory_ / ("." + name);
  try {
    if (!cv::imwrite(tmp.string(), bgr)) return false;
  } catch (const cv::Exception&) {
    return false;
  }
  std::error_code ec;
  fs::rename(tmp, directory_ / name, ec);
  if (ec) {
    fs::remove(tmp, ec);
    return false;
  }
  index_ = index;
  if (index_ > options_.keep_frames) {
    fs::remove(directory_ / drivers::camera::follow_frame_name(index_ - options_.keep_frames,
                                                               options_.extension),
               ec);
  }
  return true;
}

std::string FrameDirWriter::source() const {
  return std::string(drivers::camera::kFollowPrefix) + directory_.string();
}

}  // namespace coxswain::sim::devices::camera
