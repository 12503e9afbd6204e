// SPDX-License-Identifier: Apache-2.0
#pragma once
// The thin Asio layer under every serial device driver (docs/architecture.md "Drivers"): opens the
// udev-named port from config, reads and stamps bytes for the device's DeviceSession, writes
// what the session asks, reopens with backoff after an unplug, tees raw bytes to a recorder and
// publishes the device's health. Asio stays inside the implementation.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "coxswain/config/devices_config.hpp"
#include "coxswain/core/clock.hpp"
#include "coxswain/core/latest_store.hpp"
#include "coxswain/core/time.hpp"
#include "coxswain/drivers/device_session.hpp"

namespace coxswain::drivers::serial {

/// Timing and sizes of a transport. The defaults suit every device coxswain drives.
struct TransportOptions {
  core::TimeNs poll_period_ns = 10 * core::kNsPerMs;       // session.on_poll period
  core::TimeNs health_period_ns = 100 * core::kNsPerMs;    // health published at least this often
  core::TimeNs backoff_initial_ns = 100 * core::kNsPerMs;  // first reopen delay
  core::TimeNs backoff_max_ns = 2 * core::kNsPerSec;       // reopen delay cap (doubling)
  std::size_t write_queue_bytes = 4096;  // bytes queued while a write is in flight
  std::size_t read_chunk_bytes = 4096;   // largest single read
};

/// Transport counters, readable from any thread.
struct TransportCounters {
  std::uint64_t bytes_received = 0;
  std::uint64_t bytes_written = 0;   // written to the port (completed writes)
  std::uint64_t writes_dropped = 0;  // DeviceLink::write calls refused (queue full or closed)
  std::uint64_t bytes_dropped = 0;   // their bytes
  std::uint64_t opens = 0;           // successful opens
  std::uint32_t reopen_count = 0;    // successful opens after the first
  std::uint64_t open_failures = 0;
  std::uint64_t closes = 0;  // unplug, read error or kReopen
};

/// One serial device: a thread with its own io_context runs the port, the session and the
/// timers. Behaviour:
/// - open: raw 8N1 at `config.baud`, no flow control, ASYNC_LOW_LATENCY when the driver has it;
///   then session.on_open(). A path that is missing or cannot be opened gives state kAbsent
///   with the reason, and another try after the backoff.
/// - read: each completed read is stamped with `clock` and handed to session.on_bytes() (and to
///   `raw_sink`, if any). EOF or a read error (USB unplug) closes the port: session.on_close(),
///   then reopen after the backoff: 100 ms doubling to 2 s, reset once a reopened port produced
///   data. A kReopen verdict from on_poll does the same.
/// - write: DeviceLink::write copies into a fixed-capacity queue; a full queue drops and counts.
///   Accepted bytes are teed to `raw_sink` (kToDevice) when queued.
/// - health: the session's view (fill_health) plus bytes_received and reopen_count, published
///   into `health_slot` (this transport is its single writer) at ~10 Hz and on every state change.
/// No call ever blocks the device thread; stop() returns within a few milliseconds whatever the
/// device does.
///
/// Thread-safety: start(), stop() and the destructor from one owning thread; counters() and
/// running() from any thread. The session, the link and `raw_sink` are called on the transport's
/// thread only. `session`, `health_slot`, `clock` and `raw_sink` must outlive the transport.
class SerialTransport {
 public:
  SerialTransport(const config::SerialDeviceConfig& config, DeviceSession& session,
                  core::LatestSlot<msg::DeviceHealth>& health_slot, const core::Clock& clock,
                  RawByteSink* raw_sink = nullptr, const TransportOptions& options = {});
  ~SerialTransport();
  SerialTransport(const SerialTransport&) = delete;
  SerialTransport& operator=(const SerialTransport&) = delete;

  /// Starts the device thread (the first open is tried at once). Call once.
  void start();
  /// Closes the port (session.on_close() if it was open) and joins the thread. Idempotent.
  void stop();

  [[nodiscard]] bool running() const;
  [[nodiscard]] TransportCounters counters() const;
  [[nodiscard]] msg::DeviceId device() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace coxswain::drivers::serial
