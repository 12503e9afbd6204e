// SPDX-License-Identifier: Apache-2.0
#pragma once
// Docking-marker detection by classic vision (docs/missions.md, "Docking"): per-colour HSV
// range -> morphology -> contours -> shape rules -> bearing. Works at any image size: the bearing
// uses the actual frame width and areas are fractions of the actual frame.
#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "coxswain/core/time.hpp"
#include "coxswain/msg/camera_detections.hpp"
#include "coxswain/perception/vision_colour_mask.hpp"
#include "coxswain/perception/vision_params.hpp"
#include "coxswain/perception/vision_shape.hpp"

namespace coxswain::perception {

/// Counters of the last detect() call, for tuning and tests.
struct MarkerDetectStats {
  int contours = 0;       // outer contours seen over all colours
  int too_small = 0;      // below min_area_fraction
  int cut_by_edge = 0;    // bounding box within edge_margin_px of the border
  int outline_only = 0;   // fill ratio too low (a ring, e.g. a placard's black outline)
  int unknown_shape = 0;  // no rule matched
  int dropped = 0;        // more than CameraDetections::kMaxDetections candidates
};

/// Finds every marker (triangle, rectangle, cross, circle) of every marker colour in a frame.
/// Output detections are sorted by area, largest first. Not thread-safe; one per camera thread.
class MarkerDetector {
 public:
  explicit MarkerDetector(const VisionParams& params = VisionParams::defaults());

  /// Fills `out` (cleared first) from `bgr` (CV_8UC3). Returns false for an unusable image.
  [[nodiscard]] bool detect(const cv::Mat& bgr, core::TimeNs stamp_ns, msg::CameraDetections& out);

  /// Scans one colour's ready-made mask (CV_8UC1 of a `width` x `height` frame, e.g. from a
  /// ColourMasker shared with the buoy detector) and adds its markers to `out` without clearing
  /// it. Statistics accumulate until reset_stats(). For CameraPipeline, which builds each mask
  /// once for both detectors.
  /// `offset` places the mask's top-left pixel in the frame (ColourMasker::MaskView).
  void scan_mask(msg::Colour colour, const cv::Mat& mask, cv::Point offset, int width, int height,
                 msg::CameraDetections& out);
  void reset_stats() { stats_ = {}; }

  [[nodiscard]] const MarkerDetectStats& last_stats() const { return stats_; }
  [[nodiscard]] const VisionParams& params() const { return params_; }

 private:
  /// Whether contour `island` (inside a hole of the blob whose outer contour is `root`) is a
  /// marker on a placard rather than a glyph artefact.
  [[nodiscard]] bool placard_island(std::size_t island, int root, int width, int height) const;

  VisionParams params_;
  ColourMasker masker_;
  ShapeAnalyzer analyzer_;
  std::vector<std::vector<cv::Point>> contours_;
  std::vector<cv::Vec4i> hierarchy_;
  MarkerDetectStats stats_;
};

/// The largest detection with exactly this colour and shape (never a larger non-target), or
/// nullopt. kUnknown in either argument matches any value of that field.
[[nodiscard]] std::optional<msg::Detection> find_target(const msg::CameraDetections& detections,
                                                        msg::Colour colour, msg::Shape shape);

/// Inserts `d` keeping `out` sorted by area (largest first); when full, drops the smallest.
/// Returns false when `d` itself was dropped or replaced an existing entry.
bool insert_by_area(msg::CameraDetections& out, const msg::Detection& d);

}  // namespace coxswain::perception
