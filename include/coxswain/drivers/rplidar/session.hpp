// SPDX-License-Identifier: Apache-2.0
#pragma once
// The RPLIDAR's device session (drivers/device_session.hpp): start-up sequence, scanning,
// revolutions published into the LatestStore, health. Protocol: docs/protocols.md section 1.
//
// Start-up, every step with a timeout and a bounded number of attempts (all in virtual time):
//   STOP -> settle -> flush -> GET_INFO (model -> range limits, motor type, scan modes via
//   model_info()) -> GET_HEALTH (error: RESET, wait, ask again, at most kMaxHealthResets times;
//   warning: noted in the health detail, scanning goes on) -> [GET_ACC_BOARD_FLAG for A2/A3]
//   -> [GET_LIDAR_CONF typical mode, its answer type and us/sample | GET_SAMPLERATE] -> motor
//   start (A1: DTR de-asserted, because Linux raises DTR on open and an A1 spins only with DTR
//   low; A2/A3: SET_MOTOR_PWM motor_pwm; S-series: HQ_MOTOR_SPEED_CTRL motor_rpm; C1: nothing,
//   the firmware runs it) -> SCAN or EXPRESS_SCAN (legacy 0x82, ultra 0x84, dense 0x85) -> first
//   samples within kFirstDataTimeoutMs (spin-up).
// Scanning: nodes go through the ScanAssembler (body frame through the mount, seam astern); a
// revolution is stamped with the arrival of the chunk holding the first byte of its first
// sample and published. A revolution touched by a decoder checksum or framing error (during it,
// or within the decode delay before its first sample), or much smaller than its predecessor, is
// dropped (counted in dropped_frames), so a damaged scan never reaches the core.
// Health: no samples for kStaleMs = kStale; silence longer than timeout_ms, or too many decoder
// errors in a one-second window, sends RESET and restarts the sequence; when kMaxRestarts restarts
// in a row bring no revolution, on_poll returns kReopen.
//
// Thread-safety: none; every method is called from the lidar's device thread (DeviceSession).
// Allocates once in the constructor (the assembler's two scans); none per byte or poll.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include "coxswain/config/devices_config.hpp"
#include "coxswain/core/frames.hpp"
#include "coxswain/core/latest_store.hpp"
#include "coxswain/drivers/device_session.hpp"
#include "coxswain/drivers/rplidar/codec.hpp"
#include "coxswain/drivers/rplidar/protocol.hpp"
#include "coxswain/drivers/rplidar/request.hpp"
#include "coxswain/drivers/rplidar/scan_assembler.hpp"

namespace coxswain::drivers::rplidar {

/// Where the start-up sequence is.
enum class SessionStep : std::uint8_t {
  kClosed,
  kStopSettle,  // STOP sent; waiting for in-flight data before flushing
  kGetInfo,
  kGetHealth,
  kResetWait,  // RESET sent; the lidar reboots
  kAccBoard,
  kConfTypical,
  kConfAnswerType,
  kConfUsPerSample,
  kSampleRate,
  kStartScan,  // motor started, scan command sent, waiting for the first samples
  kScanning,
};

[[nodiscard]] const char* session_step_name(SessionStep step);

/// The scan the session chose after the queries.
struct ScanPlan {
  bool express = false;
  std::uint8_t express_mode = 0;  // EXPRESS_SCAN working mode (0 = legacy express)
  AnswerType answer = AnswerType::kMeasurement;
  double sample_duration_us = 0.0;
};

class RplidarSession final : public DeviceSession {
 public:
  static constexpr std::int64_t kStopSettleMs = 20;
  static constexpr std::int64_t kInfoTimeoutMs = 500;  // the SDK's first GET_INFO timeout
  static constexpr std::int64_t kCommandTimeoutMs = 1000;
  static constexpr std::int64_t kResetWaitMs = 1000;
  static constexpr std::int64_t kFirstDataTimeoutMs = 3000;  // motor spin-up to stable rotation
  static constexpr int kMaxAttempts = 3;                     // per query
  static constexpr int kMaxHealthResets = 3;
  static constexpr int kMaxRestarts = 2;  // RESET restarts without a revolution before kReopen
  static constexpr std::int64_t kStaleMs = 200;
  static constexpr std::int64_t kErrorWindowMs = 1000;
  /// A window with at least this many decoder errors, and errors >= 20 % of good frames, restarts.
  static constexpr std::uint64_t kMaxErrorsPerWindow = 20;
  /// Samples per revolution below which a revolution is not published (a stalled motor).
  static constexpr std::uint32_t kMinPointsPerRevolution = 16;
  /// Samples a decoder error can reach back before it is noticed: two ultra capsules.
  static constexpr std::uint64_t kDecodeDelaySamples = std::uint64_t{2} * 96U;
  /// A-series firmware < 1.17 has no GET_SAMPLERATE; the SDK assumes this (docs/protocols.md 1.5).
  static constexpr double kLegacySampleDurationUs = 476.0;

  RplidarSession(const config::LidarDeviceConfig& config, const core::MountTransform& lidar_mount,
                 core::LatestSlot<msg::LidarScan>& scans);

  [[nodiscard]] msg::DeviceId device() const override { return msg::DeviceId::kLidar; }
  void on_open(DeviceLink& link, core::TimeNs now_ns) override;
  void on_bytes(std::span<const std::uint8_t> bytes, core::TimeNs arrival_ns,
                DeviceLink& link) override;
  SessionVerdict on_poll(DeviceLink& link, core::TimeNs now_ns) override;
  void on_close(core::TimeNs now_ns) override;
  void fill_health(msg::DeviceHealth& health, core::TimeNs now_ns) const override;

  // Observation (tests, diagnostics).
  [[nodiscard]] SessionStep step() const { return step_; }
  [[nodiscard]] const ModelInfo& model() const { return model_; }
  [[nodiscard]] const DeviceInfo& device_info() const { return info_; }
  [[nodiscard]] const ScanPlan& plan() const { return plan_; }
  [[nodiscard]] const DecoderStats& decoder_stats() const { return decoder_.stats(); }
  [[nodiscard]] std::uint64_t published() const { return published_; }
  [[nodiscard]] std::uint64_t dropped_revolutions() const { return dropped_revolutions_; }
  [[nodiscard]] std::uint32_t restarts() const { return restarts_total_; }
  [[nodiscard]] std::uint32_t health_resets() const { return health_resets_total_; }
  [[nodiscard]] std::string_view detail() const { return {detail_.data()}; }

 private:
  void send(DeviceLink& link, const Request& r, SessionStep next, core::TimeNs now_ns,
            std::int64_t timeout_ms);
  void request_info(DeviceLink& link, core::TimeNs now_ns);
  void after_health(DeviceLink& link, core::TimeNs now_ns);
  void plan_scan(DeviceLink& link, core::TimeNs now_ns);
  void start_scan(DeviceLink& link, core::TimeNs now_ns);
  /// RESET and run the sequence again; kReopen when restarts keep failing.
  void restart(DeviceLink& link, core::TimeNs now_ns, const char* why);
  void on_timeout(DeviceLink& link, core::TimeNs now_ns);
  void handle(const Message& m, std::uint64_t end_index, DeviceLink& link);
  void handle_nodes(const NodeBatch& batch, std::uint64_t end_index);
  [[nodiscard]] core::TimeNs arrival_of(std::uint64_t byte_index) const;
  [[nodiscard]] std::uint64_t error_count() const;
  void note(const char* fmt, ...) __attribute__((format(printf, 2, 3)));
  void note_running();

  config::LidarDeviceConfig config_;
  core::LatestSlot<msg::LidarScan>& scans_;
  Decoder decoder_;
  // Held in place (two full scans, about 128 KiB): no allocation of its own.
  std::optional<ScanAssembler> assembler_;

  SessionStep step_ = SessionStep::kClosed;
  core::TimeNs deadline_ns_ = core::kNeverNs;
  int attempts_ = 0;
  Request pending_{};  // the request being waited for (resent on timeout)
  SessionVerdict verdict_ = SessionVerdict::kContinue;
  DeviceInfo info_{};
  ModelInfo model_{};
  bool use_pwm_ = false;
  ScanPlan plan_{};
  std::uint16_t typical_mode_ = 0;
  int health_resets_ = 0;  // in this start-up
  int restarts_ = 0;       // since the last published revolution
  std::uint32_t restarts_total_ = 0;
  std::uint32_t health_resets_total_ = 0;
  bool health_warning_ = false;
  std::uint16_t health_warning_code_ = 0;

  // Byte positions -> arrival stamps of the chunks that carried them.
  struct Chunk {
    std::uint64_t first_index = 0;
    core::TimeNs arrival_ns = core::kNeverNs;
  };
  static constexpr std::size_t kChunkRing = 64;
  std::array<Chunk, kChunkRing> chunks_{};
  std::size_t chunk_count_ = 0;
  std::uint64_t bytes_total_ = 0;

  core::TimeNs opened_ns_ = core::kNeverNs;
  core::TimeNs last_data_ns_ = core::kNeverNs;  // arrival of the last decoded samples
  // Damage attribution (see handle_nodes).
  std::uint64_t samples_added_ = 0;
  std::uint64_t errors_seen_ = 0;
  std::uint64_t last_error_sample_ = 0;
  bool have_error_ = false;
  std::uint64_t revolution_first_sample_ = 0;
  std::uint32_t last_revolution_points_ = 0;
  std::uint64_t published_ = 0;
  std::uint64_t dropped_revolutions_ = 0;
  // Error window.
  core::TimeNs window_start_ns_ = core::kNeverNs;
  std::uint64_t window_errors_at_start_ = 0;
  std::uint64_t window_frames_at_start_ = 0;
  // Revolution rate from the last published stamps.
  static constexpr std::size_t kRateRing = 8;
  std::array<core::TimeNs, kRateRing> rev_stamps_{};
  std::size_t rev_stamp_count_ = 0;

  std::array<char, 192> detail_{};
};

}  // namespace coxswain::drivers::rplidar
