// SPDX-License-Identifier: Apache-2.0
#include "camera_test_util.hpp"

#include <opencv2/videoio.hpp>

namespace coxswain::drivers::camera::testing {

bool write_mjpg_avi(const std::filesystem::path& file, const std::vector<cv::Mat>& frames,
                    double fps) {
  if (frames.empty()) return false;
  cv::VideoWriter writer;
  try {
    if (!writer.open(file.string(), cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), fps,
                     frames.front().size(), true)) {
      return false;
    }
    for (const cv::Mat& f : frames) writer.write(f);
    writer.release();
  } catch (const cv::Exception&) {
    return false;
  }
  return std::filesystem::exists(file) && std::filesystem::file_size(file) > 0;
}

}  // namespace coxswain::drivers::camera::testing
