// SPDX-License-Identifier: Apache-2.0
#pragma once
// The camera driver: one thread that opens devices.yaml `camera.source` (a V4L2 camera, a video
// file, an image directory or the simulator's follow directory; see frame_source.hpp), stamps
// each frame on the injected clock as it is captured, runs perception::CameraPipeline on it and
// publishes the detections and the device health into the store. Frames themselves never enter
// the store; an optional LatestFrame hands the newest one to the recorder and the live view.
//
// Failure handling: a source that cannot be opened, or is lost (unplugged, deleted), is retried
// with a back-off of 100 ms doubling to 2 s, reset by the first good frame. No new frame for
// `timeout_ms` makes the state kStale. The thread sleeps on a condition variable between polls and
// reopen attempts, so it never busy-loops and stop() wakes it at once; a V4L2 grab in progress
// delays stop() by one frame period. A V4L2 camera that stops streaming while still plugged in
// blocks a grab for OpenCV's select() timeout (environment OPENCV_VIDEOIO_V4L_SELECT_TIMEOUT,
// seconds, default 10): until it returns, health is not refreshed and stop() waits. Ten failed
// grabs in a row close and reopen the device.
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <opencv2/core.hpp>
#include <string>
#include <thread>

#include "coxswain/config/devices_config.hpp"
#include "coxswain/core/clock.hpp"
#include "coxswain/core/frames.hpp"
#include "coxswain/core/latest_store.hpp"
#include "coxswain/drivers/camera/frame_source.hpp"
#include "coxswain/msg/camera_detections.hpp"
#include "coxswain/msg/device_health.hpp"
#include "coxswain/perception/camera_pipeline.hpp"
#include "coxswain/perception/vision_params.hpp"

namespace coxswain::drivers::camera {

/// The newest camera frame, for consumers that want pixels (recorder, live view) at their own
/// pace. Thread-safety: any number of publishers and readers; a mutex guards one buffer, and both
/// publish() and read() copy (about 0.1 ms for 640x480), so neither side ever holds a reference
/// into the other's image and the camera thread is never blocked for longer than one copy.
class LatestFrame {
 public:
  /// Copies `bgr` in (the buffer is reused while the size stays the same), with what the
  /// detectors found in it (none when null), so a viewer draws them on this very frame.
  void publish(const cv::Mat& bgr, core::TimeNs stamp_ns,
               const msg::CameraDetections* detections = nullptr);
  /// Copies the newest frame into `out` (reusing its buffer). False when nothing was published;
  /// `stamp_ns` and `sequence` (1 for the first frame) describe the copied frame, `detections`
  /// (when not null) receives its detections.
  bool read(cv::Mat& out, core::TimeNs& stamp_ns, std::uint64_t& sequence,
            msg::CameraDetections* detections = nullptr) const;
  /// Frames published so far; cheap, for polling "is there a new one?".
  [[nodiscard]] std::uint64_t sequence() const;

 private:
  mutable std::mutex mutex_;
  cv::Mat frame_;
  core::TimeNs stamp_ns_ = core::kNeverNs;
  std::uint64_t sequence_ = 0;
  msg::CameraDetections detections_{};
};

/// Runs the camera. Counters in DeviceHealth: frames_ok = frames processed, bytes_received =
/// bytes of those frames as read (encoded file size, or decoded image size), framing_errors =
/// grabs or decodes that failed, dropped_frames = frames the follow directory passed over to stay
/// on the newest, reopen_count = opens after the first, rate_hz = frames per second over the
/// last second or more of the injected clock. Thread-safety: construct, start() and stop() from
/// one thread; the slots are written only by the driver's thread.
class CameraDriver {
 public:
  /// `vision` are the detector tunables; hfov_deg comes from `config` and the mount yaw from
  /// `mount` (boat.yaml mounts.camera). `frame_out` may be null.
  CameraDriver(const config::CameraDeviceConfig& config, const core::MountTransform& mount,
               const perception::VisionParams& vision,
               core::LatestSlot<msg::CameraDetections>& detections_out,
               core::LatestSlot<msg::DeviceHealth>& health_out, const core::Clock& clock,
               LatestFrame* frame_out = nullptr);
  CameraDriver(const CameraDriver&) = delete;
  CameraDriver& operator=(const CameraDriver&) = delete;
  ~CameraDriver();

  /// Starts the thread (no-op when running). A disabled camera publishes kDisabled once.
  void start();
  /// Stops and joins the thread; returns promptly (see the header comment). Idempotent.
  void stop();

  [[nodiscard]] const SourceSpec& source() const { return spec_; }

  /// New detector tunables (live retuning, e.g. the HSV boxes), taken by the camera thread before
  /// its next frame; the camera's field of view and mount yaw are kept. Wait-free, one caller
  /// thread at a time (the tick thread); check vision.validate() first.
  void set_vision(const perception::VisionParams& vision);
  /// The detector tunables the camera thread uses (for tests; call while it is stopped).
  [[nodiscard]] const perception::VisionParams& vision() const { return pipeline_.params(); }

 private:
  void run();
  bool wait_for_stop(core::TimeNs duration_ns);
  void set_state(msg::DeviceState state, const std::string& detail);
  void publish_health();
  void on_frame(const ReadResult& r);

  config::CameraDeviceConfig config_;
  core::MountTransform mount_;
  SourceSpec spec_;
  perception::CameraPipeline pipeline_;
  core::LatestSlot<perception::VisionParams> vision_in_;  // set_vision() -> camera thread
  std::uint64_t vision_seen_ = 0;                         // camera thread
  core::LatestSlot<msg::CameraDetections>& detections_out_;
  core::LatestSlot<msg::DeviceHealth>& health_out_;
  const core::Clock& clock_;
  LatestFrame* frame_out_;

  // Driver thread only.
  cv::Mat frame_;
  msg::CameraDetections detections_{};
  msg::DeviceHealth health_{};
  std::string last_detail_;
  std::string last_settings_report_;
  core::TimeNs rate_window_start_ns_ = core::kNeverNs;
  std::uint64_t rate_window_frames_ = 0;

  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_requested_ = false;
  std::thread thread_;
};

}  // namespace coxswain::drivers::camera
