// SPDX-License-Identifier: Apache-2.0
#pragma once
// Scoring camera detections against labelled frames (`coxswain vision eval`) and fitting the
// colour boxes from labelled frames (`coxswain vision calibrate`).
//
// Labels CSV: a header, then one row per labelled object:
//   file,colour,shape,x_px,y_px,width_px,height_px[,flags]
// colour/shape as in msg (shape `buoy` for a buoy); `none,none` with empty box for a frame that
// holds nothing; flags `partial` for an object cut by the frame border (neither counted for
// recall nor a false report when found). Not thread-safe.
#include <array>
#include <cstddef>
#include <istream>
#include <map>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "coxswain/msg/camera_detections.hpp"
#include "coxswain/perception/vision_params.hpp"

namespace coxswain::app {

struct LabelledObject {
  msg::Colour colour = msg::Colour::kUnknown;
  msg::Shape shape = msg::Shape::kUnknown;
  cv::Rect2d box;
  bool partial = false;
};

struct LabelledFrame {
  std::string file;
  std::vector<LabelledObject> objects;  // empty: nothing in view
};

/// Parses a labels CSV (bounded: at most 1,000,000 rows of at most 4096 bytes). nullopt with
/// `error` naming the line on a malformed row.
[[nodiscard]] std::optional<std::vector<LabelledFrame>> read_labels(std::istream& in,
                                                                    std::string& error);

/// Recall, precision, false reports and confusions, accumulated frame by frame.
struct EvalTally {
  static constexpr std::size_t kColours = 9;                  // msg::Colour values
  static constexpr std::size_t kShapes = 6;                   // msg::Shape values
  std::array<std::array<int, kShapes>, kColours> labelled{};  // [colour][shape], not partial
  std::array<std::array<int, kShapes>, kColours> found{};
  std::array<int, kColours> reported_by_colour{};  // detections, every one
  std::array<int, kColours> wrong_by_colour{};     // of which false reports
  std::array<int, kShapes> reported_by_shape{};
  std::array<int, kShapes> wrong_by_shape{};
  // On each labelled object (not partial): [true shape][reported shape] of its colour's
  // detections, kUnknown = nothing; and [true colour][reported colour] of its shape's.
  std::array<std::array<int, kShapes>, kShapes> shape_confusion{};
  std::array<std::array<int, kColours>, kColours> colour_confusion{};
  int frames = 0;
  int frames_with_false_report = 0;
  int false_reports = 0;
  std::vector<std::string> false_report_notes;  // the first few, "file: colour/shape at x,y"
  std::vector<std::string> miss_notes;          // the first few missed objects
  std::vector<double> frame_ms;
  // Found objects: the detection's horizontal centre minus the labelled box's, in pixels (a
  // camera bearing comes from it, so a bias here is a bearing bias).
  std::vector<double> centre_dx_px;

  void add(const LabelledFrame& frame, const msg::CameraDetections& detections);
  [[nodiscard]] double recall_colour(msg::Colour c) const;  // -1 when nothing labelled
  [[nodiscard]] double recall_shape(msg::Shape s) const;
  /// The smallest per-colour and per-shape recall over labelled classes (1 when none).
  [[nodiscard]] double min_recall() const;
  [[nodiscard]] double false_report_rate() const;
  /// The tables as text.
  [[nodiscard]] std::string report() const;
};

/// Fits one HSV box per labelled marker colour from the pixels in the middle of each labelled
/// glyph (the central `core_fraction` of its box): hue, saturation and value between the 1st
/// and 99th percentiles, widened by a margin; red's hue wraps. Colours without samples keep
/// `base`'s box. Counts of samples per colour in `samples` (may be null).
struct CalibrationSamples {
  std::map<msg::Colour, std::vector<cv::Vec3b>> hsv;
};
void add_calibration_samples(const cv::Mat& bgr, const LabelledFrame& frame,
                             CalibrationSamples& samples, double core_fraction = 0.3);
[[nodiscard]] perception::VisionParams fit_colour_boxes(const CalibrationSamples& samples,
                                                        const perception::VisionParams& base);

}  // namespace coxswain::app
