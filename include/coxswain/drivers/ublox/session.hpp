// SPDX-License-Identifier: Apache-2.0
#pragma once
// u-blox GNSS device session (drivers/device_session.hpp): configures the receiver, decodes its
// stream, publishes fixes and reports health. Protocol facts: docs/protocols.md
// section 3.
//
// Start-up: the configuration plan of drivers/ublox/config.hpp (CFG-VALSET on an F9, legacy
// CFG-RATE/NAV5/MSG on an M8), one frame at a time, each waiting for its ACK-ACK with a timeout
// and retries. A NAK or a step whose retries run out is noted in the health detail and the plan
// moves on: a receiver already configured (u-center, saved to flash) still works, so decoding
// never waits for the plan.
//
// Which fix is published (one per navigation epoch):
//   NAV-PVT always. NMEA GGA only while no NAV-PVT arrived within the last `nmea_hold_ns`, and
//   RMC/GLL only while neither NAV-PVT nor GGA did. NAV-PVT carries everything (accuracy, RTK
//   state, velocity) and GGA carries more than RMC, so when the receiver emits several per epoch
//   only the richest one is published and a receiver left in NMEA-only mode still yields fixes.
//
// Stamps: a fix is stamped with the arrival time of the read chunk that held the first byte of
// its frame (located from the frame length in the stream; after a resync inside the decoder the
// estimate can name a chunk at most one frame later).
//
// Health: frames_ok / checksum_errors / framing_errors are the decoder's (every protocol on the
// line); rate_hz is published fixes per second over the last 2 s (the navigation rate);
// kConfiguring while the plan runs, kRunning while frames arrive, kStale after timeout_ms of
// silence; after reopen_after_ns of silence on_poll answers kReopen.
//
// RTCM 3: frames queued by an RtcmSource (another thread) are written to the receiver in
// on_poll, whole, between our own configuration frames. A frame the link refuses (its write
// queue is full) waits in the queue for the next poll. While the port is closed the bounded
// queue fills and the live source drops the newest frames (RtcmSource), so at most one queue of
// old corrections (64 frames, a few seconds) is sent after a reopen.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "coxswain/config/devices_config.hpp"
#include "coxswain/core/latest_store.hpp"
#include "coxswain/core/time.hpp"
#include "coxswain/drivers/device_session.hpp"
#include "coxswain/drivers/rate_window.hpp"
#include "coxswain/drivers/ublox/codec.hpp"
#include "coxswain/drivers/ublox/config.hpp"
#include "coxswain/drivers/ublox/rtcm_queue.hpp"

namespace coxswain::drivers::ublox {

/// Timing knobs of the session; the defaults suit a real receiver.
struct SessionTiming {
  core::TimeNs ack_timeout_ns = 500 * core::kNsPerMs;  // per configuration frame
  int max_attempts = 3;                                // sends per frame before giving up
  core::TimeNs rate_window_ns = 2 * core::kNsPerSec;   // rate_hz is measured over this window
  /// Silence after which the port is reopened; 0 = max(10 x timeout_ms, 5 s).
  core::TimeNs reopen_after_ns = 0;
  /// How long a NAV-PVT (or GGA) suppresses the poorer NMEA fixes; 0 = max(3 periods, 2.5 s):
  /// long enough for a receiver left at its 1 Hz power-on rate.
  core::TimeNs nmea_hold_ns = 0;
};

/// The GNSS receiver's session. Single-threaded: every method runs on the device thread (the
/// accessors too, or after that thread stopped); the RTCM queue is the only cross-thread hand-over.
class UbloxSession final : public DeviceSession {
 public:
  UbloxSession(const config::GnssDeviceConfig& config, core::LatestSlot<msg::GnssFix>& fixes,
               const SessionTiming& timing = {});

  /// Corrections to forward (nullptr: none). Set before the device thread starts.
  void set_rtcm_queue(RtcmQueue* queue) { rtcm_ = queue; }

  [[nodiscard]] msg::DeviceId device() const override { return msg::DeviceId::kGnss; }
  void on_open(DeviceLink& link, core::TimeNs now_ns) override;
  void on_bytes(std::span<const std::uint8_t> bytes, core::TimeNs arrival_ns,
                DeviceLink& link) override;
  SessionVerdict on_poll(DeviceLink& link, core::TimeNs now_ns) override;
  void on_close(core::TimeNs now_ns) override;
  void fill_health(msg::DeviceHealth& health, core::TimeNs now_ns) const override;

  // ---- Introspection (tests, logs) ----
  [[nodiscard]] bool configuring() const { return open_ && step_ < plan_.count; }
  /// Steps of the last plan that were NAKed or never acknowledged.
  [[nodiscard]] std::size_t config_failures() const { return config_failures_; }
  [[nodiscard]] std::uint64_t fixes_published() const { return fixes_published_; }
  /// NMEA fixes not published because a richer message covered the epoch.
  [[nodiscard]] std::uint64_t fixes_suppressed() const { return fixes_suppressed_; }
  [[nodiscard]] std::uint64_t rtcm_frames_forwarded() const { return rtcm_forwarded_; }
  [[nodiscard]] const CodecStats& codec_stats() const { return decoder_.stats(); }
  [[nodiscard]] const ConfigPlan& plan() const { return plan_; }

 private:
  struct Chunk {
    std::uint64_t start = 0;  // stream offset of the chunk's first byte
    core::TimeNs arrival_ns = core::kNeverNs;
  };
  void send_step(DeviceLink& link, core::TimeNs now_ns);
  void finish_step(DeviceLink& link, core::TimeNs now_ns, std::string_view failure);
  void handle(const Message& m, core::TimeNs stamp_ns, DeviceLink& link);
  [[nodiscard]] core::TimeNs arrival_of(std::uint64_t offset) const;
  void set_detail(std::string_view a, std::string_view b = {});

  config::GnssDeviceConfig config_;
  core::LatestSlot<msg::GnssFix>& fixes_;
  SessionTiming timing_;
  core::TimeNs reopen_after_ns_;
  core::TimeNs nmea_hold_ns_;
  core::TimeNs stale_after_ns_;
  RtcmQueue* rtcm_ = nullptr;

  Decoder decoder_;
  ConfigPlan plan_;
  std::size_t step_ = 0;
  int attempts_ = 0;
  core::TimeNs step_sent_ns_ = core::kNeverNs;
  core::TimeNs last_now_ns_ = core::kNeverNs;
  std::size_t config_failures_ = 0;
  bool open_ = false;

  std::array<Chunk, 512> chunks_{};
  std::size_t chunk_next_ = 0;
  std::size_t chunk_count_ = 0;
  std::uint64_t stream_offset_ = 0;  // bytes handed to the decoder so far
  std::uint64_t last_dollar_offset_ = 0;

  core::TimeNs opened_ns_ = core::kNeverNs;
  core::TimeNs last_frame_ns_ = core::kNeverNs;
  core::TimeNs last_pvt_ns_ = core::kNeverNs;
  core::TimeNs last_gga_ns_ = core::kNeverNs;
  RateWindow<> rate_;
  std::uint64_t fixes_published_ = 0;
  std::uint64_t fixes_suppressed_ = 0;
  std::uint64_t rtcm_forwarded_ = 0;
  std::array<char, 160> detail_{};
};

}  // namespace coxswain::drivers::ublox
