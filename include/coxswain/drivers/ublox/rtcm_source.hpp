// SPDX-License-Identifier: Apache-2.0
#pragma once
// RTCM 3 correction reader for an RTK rover (docs/protocols.md 3.9): reads a correction stream from
//   - tcp://host:port   e.g. a local NTRIP client's output or a caster relay; reconnects with
//                       exponential backoff after a refused connection, an error or EOF;
//   - a named pipe      reopened (after backoff) whenever its writer goes away;
//   - a regular file    read once, frame by frame, as fast as the queue drains (no drops);
// splits it into CRC-24Q-checked frames with the pure Rtcm3Framer (bad frames are counted and
// dropped) and pushes whole frames into an RtcmQueue that UbloxSession drains on the GNSS
// device thread. Live inputs drop a frame when the queue is full: stale corrections are useless.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <thread>

#include "coxswain/core/time.hpp"
#include "coxswain/drivers/ublox/rtcm_queue.hpp"

namespace coxswain::drivers::ublox {

/// Counters of one RtcmSource (a consistent-enough snapshot of relaxed atomics).
struct RtcmSourceStats {
  std::uint64_t bytes_in = 0;
  std::uint64_t frames_ok = 0;  // CRC-valid frames queued or dropped
  std::uint64_t frames_queued = 0;
  std::uint64_t frames_dropped = 0;  // queue full (live inputs only)
  std::uint64_t crc_errors = 0;      // framer checksum errors
  std::uint64_t framing_errors = 0;
  std::uint64_t connects = 0;  // successful opens/connects
  std::uint64_t failures = 0;  // failed opens/connects, read errors, EOFs of live inputs
  bool finished = false;       // a regular file was read to its end
};

struct RtcmSourceOptions {
  core::TimeNs backoff_initial_ns = 100 * core::kNsPerMs;
  core::TimeNs backoff_max_ns = 5 * core::kNsPerSec;
  /// Told, on the reader thread, why the input cannot be read ("cannot connect to
  /// caster:2101: Connection refused") once per distinct reason, not at every retry, and
  /// "connected"/"opened" when it can be read again after a problem. May be empty.
  std::function<void(bool problem, std::string_view what)> on_event;
};

/// Owns one reader thread. Thread-safety: start/stop from one owner thread; stats() from any
/// thread; the queue's consumer side belongs to the GNSS device thread.
class RtcmSource {
 public:
  /// `input` as config::GnssDeviceConfig::rtcm_input ("" = no corrections: start() does nothing).
  RtcmSource(std::string input, RtcmQueue& queue, const RtcmSourceOptions& options = {});
  ~RtcmSource();
  RtcmSource(const RtcmSource&) = delete;
  RtcmSource& operator=(const RtcmSource&) = delete;

  void start();
  /// Stops and joins the thread; idempotent.
  void stop();

  [[nodiscard]] RtcmSourceStats stats() const;
  [[nodiscard]] const std::string& input() const { return input_; }

  /// True when `input` is a tcp://host:port address; sets host and port.
  static bool parse_tcp(const std::string& input, std::string& host, std::string& port);

  struct Impl;  // Asio state, defined in rtcm_source.cpp

 private:
  std::string input_;
  RtcmQueue& queue_;
  RtcmSourceOptions options_;
  std::unique_ptr<Impl> impl_;
  std::thread thread_;
};

}  // namespace coxswain::drivers::ublox
