// SPDX-License-Identifier: Apache-2.0
#pragma once
// myAHRS+ device session (drivers/device_session.hpp): start-up exchange, decoding, heading,
// publishing and health. Protocol facts: docs/protocols.md section 2.
//
// Start-up: the plan of drivers/myahrs/commands.hpp (@mode,T quiets the stream, @version,
// @divider, @asc_out|@bin_out, then @mode,AC|BC), one request at a time, each waiting for its
// `~name,OK` answer with a timeout and retries (the vendor SDK waits 500 ms). An `~name,ERROR`
// or a step whose retries run out is noted in the health detail and the plan moves on: data is
// decoded and published whatever the plan's outcome.
//
// Heading: the decoder applies drivers::myahrs::true_heading_deg() with the configured
// declination and the IMU mount yaw (boat.yaml mounts.imu.yaw_deg).
//
// Health: counters from the decoder; rate_hz is published samples per second over the last 2 s;
// kConfiguring while the start-up runs, kRunning while frames arrive, kStale after timeout_ms of
// silence; after reopen_after_ns of silence on_poll answers kReopen.
//
// Stamps: a sample is stamped with the arrival time of the read chunk that held its first byte:
// the first frame start byte (`$ ~ @` or DLE) handed to the decoder after its previous output.
// Garbage that itself holds such a byte before a frame can make the stamp one chunk early.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "coxswain/config/devices_config.hpp"
#include "coxswain/core/frames.hpp"
#include "coxswain/core/latest_store.hpp"
#include "coxswain/core/time.hpp"
#include "coxswain/drivers/device_session.hpp"
#include "coxswain/drivers/myahrs/codec.hpp"
#include "coxswain/drivers/myahrs/commands.hpp"
#include "coxswain/drivers/rate_window.hpp"

namespace coxswain::drivers::myahrs {

/// Timing knobs of the session; the defaults suit the real sensor.
struct SessionTiming {
  core::TimeNs response_timeout_ns = 500 * core::kNsPerMs;  // per request (the SDK's wait)
  int max_attempts = 3;                                     // sends per request
  core::TimeNs rate_window_ns = 2 * core::kNsPerSec;
  /// Silence after which the port is reopened; 0 = max(10 x timeout_ms, 5 s).
  core::TimeNs reopen_after_ns = 0;
};

/// The IMU's session. Single-threaded: every method runs on the device thread.
class MyahrsSession final : public DeviceSession {
 public:
  MyahrsSession(const config::ImuDeviceConfig& config, const core::MountTransform& imu_mount,
                core::LatestSlot<msg::ImuSample>& samples, const SessionTiming& timing = {});

  [[nodiscard]] msg::DeviceId device() const override { return msg::DeviceId::kImu; }
  void on_open(DeviceLink& link, core::TimeNs now_ns) override;
  void on_bytes(std::span<const std::uint8_t> bytes, core::TimeNs arrival_ns,
                DeviceLink& link) override;
  SessionVerdict on_poll(DeviceLink& link, core::TimeNs now_ns) override;
  void on_close(core::TimeNs now_ns) override;
  void fill_health(msg::DeviceHealth& health, core::TimeNs now_ns) const override;

  // ---- Introspection (tests, logs) ----
  [[nodiscard]] bool configuring() const { return open_ && step_ < plan_.count; }
  [[nodiscard]] std::size_t startup_failures() const { return startup_failures_; }
  [[nodiscard]] std::uint64_t samples_published() const { return samples_published_; }
  [[nodiscard]] const DecoderStats& decoder_stats() const { return decoder_.stats(); }
  [[nodiscard]] const StartupPlan& plan() const { return plan_; }
  /// The `ver=` of the last `~version,OK` answer ("" until seen).
  [[nodiscard]] std::string_view firmware_version() const { return {version_.data()}; }

 private:
  void send_step(DeviceLink& link, core::TimeNs now_ns);
  void finish_step(DeviceLink& link, core::TimeNs now_ns, std::string_view failure);
  void on_response(const CommandResponse& r, DeviceLink& link);
  void set_detail(std::string_view a, std::string_view b = {});

  config::ImuDeviceConfig config_;
  core::LatestSlot<msg::ImuSample>& samples_;
  SessionTiming timing_;
  core::TimeNs stale_after_ns_;
  core::TimeNs reopen_after_ns_;
  std::optional<std::string> config_error_;

  Decoder decoder_;
  StartupPlan plan_;
  std::size_t step_ = 0;
  int attempts_ = 0;
  core::TimeNs step_sent_ns_ = core::kNeverNs;
  core::TimeNs last_now_ns_ = core::kNeverNs;
  std::size_t startup_failures_ = 0;
  bool open_ = false;

  core::TimeNs pending_start_ns_ = core::kNeverNs;  // arrival of the current frame's first byte
  core::TimeNs opened_ns_ = core::kNeverNs;
  core::TimeNs last_frame_ns_ = core::kNeverNs;
  RateWindow<> rate_;
  std::uint64_t samples_published_ = 0;
  std::array<char, 32> version_{};
  std::array<char, 160> detail_{};
};

}  // namespace coxswain::drivers::myahrs
