// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/camera/camera_driver.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <string_view>

namespace coxswain::drivers::camera {
namespace {

constexpr core::TimeNs kBackoffMinNs = 100 * core::kNsPerMs;
constexpr core::TimeNs kBackoffMaxNs = 2 * core::kNsPerSec;
constexpr core::TimeNs kEndPollNs = 100 * core::kNsPerMs;
constexpr core::TimeNs kHealthPeriodNs = 200 * core::kNsPerMs;
constexpr core::TimeNs kRateWindowNs = core::kNsPerSec;
// Grabs failing this many times in a row mean the device is gone even if its node still exists.
constexpr int kMaxConsecutiveFailures = 10;

core::TimeNs steady_now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

std::string describe(const SourceSpec& spec) {
  return std::string(source_kind_name(spec.kind)) + " " + spec.path;
}

}  // namespace

void LatestFrame::publish(const cv::Mat& bgr, core::TimeNs stamp_ns,
                          const msg::CameraDetections* detections) {
  const std::lock_guard<std::mutex> lock(mutex_);
  bgr.copyTo(frame_);
  stamp_ns_ = stamp_ns;
  detections_ = detections != nullptr ? *detections : msg::CameraDetections{};
  ++sequence_;
}

bool LatestFrame::read(cv::Mat& out, core::TimeNs& stamp_ns, std::uint64_t& sequence,
                       msg::CameraDetections* detections) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (sequence_ == 0) return false;
  frame_.copyTo(out);
  stamp_ns = stamp_ns_;
  sequence = sequence_;
  if (detections != nullptr) *detections = detections_;
  return true;
}

std::uint64_t LatestFrame::sequence() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return sequence_;
}

CameraDriver::CameraDriver(const config::CameraDeviceConfig& config,
                           const core::MountTransform& mount,
                           const perception::VisionParams& vision,
                           core::LatestSlot<msg::CameraDetections>& detections_out,
                           core::LatestSlot<msg::DeviceHealth>& health_out,
                           const core::Clock& clock, LatestFrame* frame_out)
    : config_(config),
      mount_(mount),
      spec_(classify_source(config.source)),
      pipeline_(vision, config.hfov_deg, mount),
      detections_out_(detections_out),
      health_out_(health_out),
      clock_(clock),
      frame_out_(frame_out) {
  health_.device = msg::DeviceId::kCamera;
  health_.state = msg::DeviceState::kDisabled;
}

CameraDriver::~CameraDriver() { stop(); }

void CameraDriver::start() {
  if (thread_.joinable()) return;
  if (!config_.enabled) {
    set_state(msg::DeviceState::kDisabled, "disabled in devices.yaml");
    return;
  }
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_requested_ = false;
  }
  thread_ = std::thread([this] { run(); });
}

void CameraDriver::stop() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_requested_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

bool CameraDriver::wait_for_stop(core::TimeNs duration_ns) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (duration_ns > 0) {
    wake_.wait_for(lock, std::chrono::nanoseconds(duration_ns), [this] { return stop_requested_; });
  }
  return stop_requested_;
}

void CameraDriver::publish_health() {
  health_.stamp_ns = clock_.now_ns();
  health_out_.publish(health_, health_.stamp_ns);
}

void CameraDriver::set_state(msg::DeviceState state, const std::string& detail) {
  if (state == health_.state && detail == last_detail_) return;
  health_.state = state;
  health_.set_detail(detail);
  last_detail_ = detail;
  if (state != msg::DeviceState::kRunning) health_.rate_hz = 0.0;
  publish_health();
}

void CameraDriver::set_vision(const perception::VisionParams& vision) {
  vision_in_.publish(vision, clock_.now_ns());
}

void CameraDriver::on_frame(const ReadResult& r) {
  if (vision_in_.sequence() != vision_seen_) {
    const core::Sample<perception::VisionParams> v = vision_in_.read();
    vision_seen_ = v.sequence;
    // Rebuilt on the camera thread between two frames (its buffers reallocate on this frame).
    pipeline_ = perception::CameraPipeline(v.value, config_.hfov_deg, mount_);
  }
  (void)pipeline_.process(frame_, r.stamp_ns, detections_);
  // The frame first: whoever sees detections N can also fetch frame N (or a newer one).
  if (frame_out_ != nullptr) frame_out_->publish(frame_, r.stamp_ns, &detections_);
  detections_out_.publish(detections_, r.stamp_ns);

  ++health_.frames_ok;
  health_.bytes_received += r.bytes;
  health_.dropped_frames += r.skipped;
  health_.last_frame_ns = r.stamp_ns;
  if (rate_window_start_ns_ == core::kNeverNs || r.stamp_ns < rate_window_start_ns_) {
    rate_window_start_ns_ = r.stamp_ns;
    rate_window_frames_ = 0;
  } else {
    ++rate_window_frames_;
    const core::TimeNs elapsed_ns = r.stamp_ns - rate_window_start_ns_;
    if (elapsed_ns >= kRateWindowNs) {
      health_.rate_hz = static_cast<double>(rate_window_frames_) / core::ns_to_sec(elapsed_ns);
      rate_window_start_ns_ = r.stamp_ns;
      rate_window_frames_ = 0;
    }
  }
  if (health_.state != msg::DeviceState::kRunning) {
    set_state(msg::DeviceState::kRunning, std::to_string(frame_.cols) + "x" +
                                              std::to_string(frame_.rows) + " frames from " +
                                              describe(spec_));
  }
}

void CameraDriver::run() {
  const core::TimeNs period_ns = core::sec_to_ns(1.0 / config_.fps);
  // Follow directories are polled several times per frame period so a frame waits little.
  const core::TimeNs poll_ns =
      std::clamp<core::TimeNs>(period_ns / 4, 2 * core::kNsPerMs, 20 * core::kNsPerMs);
  const core::TimeNs timeout_ns = core::ms_to_ns(config_.timeout_ms);
  core::TimeNs backoff_ns = kBackoffMinNs;
  bool first_open = true;

  while (!wait_for_stop(0)) {
    if (!first_open) ++health_.reopen_count;
    first_open = false;
    // While the source stays missing the state stays kAbsent/kError: one log line per outage,
    // not two per retry.
    if (health_.state != msg::DeviceState::kAbsent && health_.state != msg::DeviceState::kError) {
      set_state(msg::DeviceState::kOpening, "opening " + describe(spec_));
    }
    const std::unique_ptr<FrameSource> source = make_frame_source(spec_, config_);
    std::string detail;
    if (source == nullptr || !source->open(detail)) {
      const bool missing = detail.rfind("no such", 0) == 0 || detail.rfind("no frame", 0) == 0;
      set_state(missing ? msg::DeviceState::kAbsent : msg::DeviceState::kError, detail);
      publish_health();  // fresh stamp and reopen count on every attempt, even with no change
      if (wait_for_stop(backoff_ns)) break;
      backoff_ns = std::min(2 * backoff_ns, kBackoffMaxNs);
      continue;
    }
    const std::string report = source->settings_report();
    if (report != last_settings_report_) {
      if (!report.empty())
        spdlog::warn("camera {}: device changed settings: {}", spec_.path, report);
      last_settings_report_ = report;
    }
    set_state(msg::DeviceState::kConfiguring, "opened " + describe(spec_) + ", no frame yet");

    // Stale = waited this long for a frame; measured from when the driver was last ready for one
    // (opened, or done with the previous frame), so slow processing never counts as silence.
    core::TimeNs waiting_since_ns = clock_.now_ns();
    core::TimeNs next_due_ns = steady_now_ns();
    core::TimeNs last_health_ns = next_due_ns;
    int consecutive_failures = 0;
    bool lost = false;
    while (!lost) {
      if (source->paced()) {
        if (wait_for_stop(next_due_ns - steady_now_ns())) break;
        next_due_ns += period_ns;
        // Fell more than a frame behind (slow decode, loaded machine): no burst to catch up.
        if (next_due_ns < steady_now_ns() - period_ns) next_due_ns = steady_now_ns();
      } else if (wait_for_stop(0)) {
        break;
      }
      const ReadResult r = source->read(frame_, clock_);
      core::TimeNs idle_ns = 0;  // how long to sleep before the next read
      switch (r.status) {
        case ReadStatus::kFrame:
          on_frame(r);
          consecutive_failures = 0;
          backoff_ns = kBackoffMinNs;
          break;
        case ReadStatus::kNotYet:
          idle_ns = poll_ns;
          break;
        case ReadStatus::kFailed:
          ++health_.framing_errors;
          if (++consecutive_failures >= kMaxConsecutiveFailures) {
            lost = true;
            detail = std::to_string(consecutive_failures) + " reads in a row failed on " +
                     describe(spec_);
          }
          if (!source->paced()) idle_ns = poll_ns;  // a failing device may fail at once: no spin
          break;
        case ReadStatus::kEnd:
          set_state(msg::DeviceState::kStale, "end of " + describe(spec_) + " (loop: false)");
          idle_ns = kEndPollNs;
          break;
        case ReadStatus::kLost:
          lost = true;
          detail = "lost " + describe(spec_);
          break;
      }
      if (lost) break;

      const core::TimeNs now_ns = clock_.now_ns();
      if (r.status == ReadStatus::kFrame) waiting_since_ns = now_ns;
      const core::TimeNs since_ns = now_ns - waiting_since_ns;
      if ((health_.state == msg::DeviceState::kRunning ||
           health_.state == msg::DeviceState::kConfiguring) &&
          since_ns > timeout_ns) {
        set_state(msg::DeviceState::kStale,
                  "no frame for " + std::to_string(config_.timeout_ms) + " ms");
      }
      const core::TimeNs steady_ns = steady_now_ns();
      if (r.status == ReadStatus::kFrame || steady_ns - last_health_ns >= kHealthPeriodNs) {
        publish_health();
        last_health_ns = steady_ns;
      }
      if (idle_ns > 0 && wait_for_stop(idle_ns)) break;
    }
    if (!lost) break;  // stop requested
    set_state(msg::DeviceState::kAbsent, detail);
    if (wait_for_stop(backoff_ns)) break;
    backoff_ns = std::min(2 * backoff_ns, kBackoffMaxNs);
  }
  set_state(
      health_.state == msg::DeviceState::kRunning ? msg::DeviceState::kPresent : health_.state,
      "stopped");
}

}  // namespace coxswain::drivers::camera
