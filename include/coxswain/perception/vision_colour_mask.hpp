// SPDX-License-Identifier: Apache-2.0
#pragma once
// BGR frame -> one label per pixel holding a bit per colour range, in a single pass through a
// lookup table on the quantised BGR value; then a cleaned binary mask per colour, cut to the rows
// and columns where that colour occurs. Shared by the marker and buoy detectors.
//
// Before labelling, the dominant colour of each horizontal strip of the frame (sky, far and near
// water) is fitted as a Gaussian in BGR; the table entries within BackgroundParams::reject_sigma
// of any of them lose every colour bit for this frame, so water that falls inside a colour's HSV
// box (blue-green sea in the blue box) is not that colour.
//
// Buffers are members, reused frame to frame (allocated when the image size changes). Not
// thread-safe: one instance per detector. Copyable.
#include <array>
#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "coxswain/perception/vision_params.hpp"

namespace coxswain::perception {

/// A Gaussian colour model in BGR (grey levels), with its inverse covariance.
struct ColourGaussian {
  bool valid = false;
  std::array<double, 3> mean_bgr{};
  std::array<double, 3> sigma_bgr{};  // per-axis spread after clamping to [min_sigma, max_sigma]
  std::array<double, 9> inverse_covariance{};
  double share = 0.0;  // fraction of the band's samples in the fitted cluster

  /// Squared Mahalanobis distance of a BGR value from the mean.
  [[nodiscard]] double distance2(double b, double g, double r) const;
};

/// One strip's samples, channel by channel (structure of arrays, so the distance passes over them
/// vectorise). Kept by the caller between frames: its buffers are reused.
struct ColourSamples {
  std::vector<std::uint8_t> b;
  std::vector<std::uint8_t> g;
  std::vector<std::uint8_t> r;
  std::vector<std::uint8_t> bucket;  // which eighth of the strip's width
  std::vector<std::uint8_t> inside;  // scratch: within the current model's 3 sigma
};

/// Fits the dominant colour of rows [row_begin, row_end) of `bgr` (CV_8UC3) sampled every
/// `p.sample_step_px` (coarser when that grid would hold more than `p.max_samples`); invalid when
/// that colour holds less than `p.min_share` of the samples.
[[nodiscard]] ColourGaussian fit_dominant_colour(const cv::Mat& bgr, int row_begin, int row_end,
                                                 const BackgroundParams& p);
/// The same, with the caller's sample buffers (no allocation once they have grown).
[[nodiscard]] ColourGaussian fit_dominant_colour(const cv::Mat& bgr, int row_begin, int row_end,
                                                 const BackgroundParams& p, ColourSamples& samples);

/// Per-colour bits of one BGR value under `params` (bit i = params.colours[i]), through the same
/// HSV boxes the table is built from (no background rejection).
[[nodiscard]] std::uint16_t colour_bits(const VisionParams& params, int b, int g, int r);

class ColourMasker {
 public:
  static constexpr int kLevelBits = 5;  // per channel: 32 levels of 8 grey values
  static constexpr int kLevels = 1 << kLevelBits;
  static constexpr std::size_t kTableSize = static_cast<std::size_t>(kLevels) * kLevels * kLevels;

  /// A colour's mask (CV_8UC1, 255 = that colour) over the sub-rectangle of the frame starting at
  /// `offset`; empty when the colour does not occur. Valid until the next mask() or set_frame().
  struct MaskView {
    cv::Mat mask;
    cv::Point offset;
  };

  explicit ColourMasker(const VisionParams& params);

  /// Blurs `bgr` (CV_8UC3), fits the background models and labels every pixel. Returns false for
  /// an empty or non-BGR image.
  [[nodiscard]] bool set_frame(const cv::Mat& bgr);

  /// Mask of params.colours[colour_index] over the current frame, after opening and closing.
  MaskView mask(std::size_t colour_index);

  /// Labels of the current frame (CV_16UC1, bit i = params.colours[i]).
  [[nodiscard]] const cv::Mat& labels() const { return labels_; }
  /// The background models of the current frame, one per strip, top to bottom (invalid: the
  /// strip has no dominant colour, or fewer strips are configured).
  [[nodiscard]] const std::array<ColourGaussian, BackgroundParams::kMaxStrips>& background() const {
    return background_;
  }

 private:
  void reject(const ColourGaussian& g);

  BackgroundParams background_params_;
  std::size_t colour_count_ = 0;
  int blur_kernel_px_;
  int pad_px_ = 0;
  cv::Mat open_kernel_;
  cv::Mat close_kernel_;
  std::vector<std::uint16_t> table_;        // from the HSV boxes
  std::vector<std::uint16_t> frame_table_;  // this frame's copy, background rejected
  std::array<ColourGaussian, BackgroundParams::kMaxStrips> background_{};
  ColourSamples samples_;
  cv::Mat blurred_;
  cv::Mat labels_;
  std::vector<std::uint16_t> row_bits_;
  std::vector<std::uint16_t> col_bits_;
  cv::Mat mask_;
  cv::Mat morph_;
};

}  // namespace coxswain::perception
