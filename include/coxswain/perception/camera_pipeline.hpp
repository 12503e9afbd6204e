// SPDX-License-Identifier: Apache-2.0
#pragma once
// One camera frame in, every marker and buoy with a body-frame bearing out. The single entry
// point of camera perception: the daemon's camera thread (drivers::camera::CameraDriver) and the
// simulator's lockstep loop both call CameraPipeline::process, so both see the same detections
// for the same pixels.
#include <cstdint>
#include <opencv2/core.hpp>

#include "coxswain/core/frames.hpp"
#include "coxswain/core/time.hpp"
#include "coxswain/msg/camera_detections.hpp"
#include "coxswain/perception/buoy_detector.hpp"
#include "coxswain/perception/marker_detector.hpp"
#include "coxswain/perception/vision_colour_mask.hpp"
#include "coxswain/perception/vision_params.hpp"

namespace coxswain::perception {

/// The detector tunables `vision` with the camera's horizontal field of view (devices.yaml
/// camera.hfov_deg) and mount yaw (boat.yaml mounts.camera) put in, so bearings come out in the
/// body frame. The mount's x/y offset does not change a bearing-only detection.
[[nodiscard]] VisionParams camera_vision_params(const VisionParams& vision, double hfov_deg,
                                                const core::MountTransform& mount);

/// Counters of the last process() call.
struct CameraPipelineStats {
  MarkerDetectStats markers;  // what the marker rules rejected (dropped: over the cap)
};

/// BGR frame (CV_8UC3, any size: bearings and area floors use the frame's own width and height)
/// + capture stamp -> msg::CameraDetections holding every marker (triangle, rectangle, cross,
/// circle of a marker colour) and every buoy (blob of a buoy colour), sorted by area, largest
/// first, at most CameraDetections::kMaxDetections. A blob may appear twice, as a marker and as a
/// buoy (a purple circle is both); consumers filter by shape.
///
/// Each colour mask is built once and scanned by both detectors. Pure and deterministic: no I/O,
/// no clock (the stamp is passed in). Its image buffers (blurred, HSV, masks) and contour vectors
/// are members reused frame to frame, so after the first frame of a given size no image buffer is
/// allocated; cv::findContours still builds its contour lists internally (small, per contour).
/// Not thread-safe: one instance per thread.
class CameraPipeline {
 public:
  /// `params` used as they are (hfov_deg and mount_yaw_deg included). Check params.validate()
  /// first; invalid parameters give meaningless detections, never undefined behaviour.
  explicit CameraPipeline(const VisionParams& params = VisionParams::defaults());
  /// Same as CameraPipeline(camera_vision_params(vision, hfov_deg, mount)).
  CameraPipeline(const VisionParams& vision, double hfov_deg, const core::MountTransform& mount);

  /// Fills `out` (cleared first; frame_index = frames processed so far, counting this one;
  /// stamp_ns = `stamp_ns`). Returns false, with no detections and a zero image size, for an
  /// empty or non-CV_8UC3 frame.
  [[nodiscard]] bool process(const cv::Mat& bgr, core::TimeNs stamp_ns, msg::CameraDetections& out);

  [[nodiscard]] const VisionParams& params() const { return params_; }
  [[nodiscard]] const CameraPipelineStats& last_stats() const { return stats_; }
  [[nodiscard]] std::uint32_t frames() const { return frames_; }

 private:
  VisionParams params_;
  ColourMasker masker_;
  MarkerDetector markers_;
  BuoyDetector buoys_;
  CameraPipelineStats stats_;
  std::uint32_t frames_ = 0;
};

}  // namespace coxswain::perception
