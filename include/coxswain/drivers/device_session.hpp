// SPDX-License-Identifier: Apache-2.0
#pragma once
// The seam between a device's protocol logic and its transport.
//
// A driver is three layers (docs/architecture.md):
//   codec      bytes <-> messages, pure (drivers/<device>/codec.*)
//   session    the device's behaviour: start-up/configuration sequence, ACK waits, retries,
//              silence detection, publishing decoded messages into the LatestStore. It does no
//              I/O of its own and reads no clock: the transport hands it bytes with their arrival
//              stamp and calls it periodically with the current time, and it writes through a
//              DeviceLink. So a session is tested without a port, in virtual time.
//   transport  the thin Asio part (drivers/serial): opens the udev path, reads, writes, reopens
//              with backoff, tees raw bytes to the recorder, owns the device's thread.
#include <cstdint>
#include <span>

#include "coxswain/core/time.hpp"
#include "coxswain/msg/device_health.hpp"

namespace coxswain::drivers {

/// What a session may do to its open device. Implemented by the transport (and by test doubles
/// that capture what a session writes). Called only from the device's own thread.
class DeviceLink {
 public:
  virtual ~DeviceLink() = default;
  /// Queues bytes for the device; never blocks. False when the write queue is full (the bytes
  /// are dropped and counted by the transport).
  virtual bool write(std::span<const std::uint8_t> bytes) = 0;
  /// Sets the DTR modem line (an RPLIDAR A1 spins its motor only with DTR de-asserted).
  virtual void set_dtr(bool asserted) = 0;
  /// Discards bytes received but not yet handed to the session (after a device reset).
  virtual void flush_input() = 0;
};

/// What the session wants the transport to do after a poll.
enum class SessionVerdict : std::uint8_t {
  kContinue = 0,
  kReopen,  // close the port and open it again (after backoff): the device needs a hard restart
};

/// The device-specific behaviour of a driver. One instance per device; every method is called
/// from the device's own thread only, so a session needs no locking. It publishes its decoded
/// messages into its LatestStore slot itself (it is that slot's single writer).
class DeviceSession {
 public:
  virtual ~DeviceSession() = default;

  [[nodiscard]] virtual msg::DeviceId device() const = 0;

  /// The port has just been opened (first open or a reopen): restart the start-up sequence.
  virtual void on_open(DeviceLink& link, core::TimeNs now_ns) = 0;

  /// Bytes read from the device. `arrival_ns` is the steady time at which the read that
  /// returned them completed, i.e. when the first of them was available to us; a message is
  /// stamped with the arrival of the chunk holding its first byte.
  virtual void on_bytes(std::span<const std::uint8_t> bytes, core::TimeNs arrival_ns,
                        DeviceLink& link) = 0;

  /// Called at the transport's poll period (10-20 ms) while the port is open: timeouts, retries,
  /// periodic writes (the Arduino command), silence detection.
  virtual SessionVerdict on_poll(DeviceLink& link, core::TimeNs now_ns) = 0;

  /// The port was closed (unplug, read error, or a kReopen verdict).
  virtual void on_close(core::TimeNs now_ns) = 0;

  /// Writes the session's view into `health`: state (kConfiguring, kRunning, kStale...),
  /// frames_ok, checksum_errors, framing_errors, last_frame_ns, rate_hz, detail. The transport
  /// fills bytes_received and reopen_count itself and publishes the record.
  virtual void fill_health(msg::DeviceHealth& health, core::TimeNs now_ns) const = 0;
};

/// Which way raw bytes travelled.
enum class RawDirection : std::uint8_t { kFromDevice = 0, kToDevice = 1 };

/// Receives every raw byte a transport reads or writes (the flight recorder, capture mode).
/// Called on the device's thread: implementations must not block (copy into a lock-free queue).
class RawByteSink {
 public:
  virtual ~RawByteSink() = default;
  virtual void on_raw(msg::DeviceId device, RawDirection direction, core::TimeNs stamp_ns,
                      std::span<const std::uint8_t> bytes) noexcept = 0;
};

}  // namespace coxswain::drivers
