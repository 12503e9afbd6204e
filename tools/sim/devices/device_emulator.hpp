// SPDX-License-Identifier: Apache-2.0
#pragma once
// The shape every device emulator core has (docs/architecture.md: the simulator injects bytes
// beneath the transport, so the production codecs and sessions run in simulation).
//
// A core is pure: no I/O, no clock (time is passed in), deterministic for a seed. It is fed what
// the host wrote and polled for what the device sends by a given time. The same core runs in the
// simulator's lockstep loop and, behind sim::pty::EmulatorHost, on a pseudo-terminal in real time
// for the unmodified daemon. Its data source is set by its owner: a recorded capture, or the
// simulator's world (each core has a typed set_truth()/feed call for that).
#include <cstdint>
#include <span>

#include "coxswain/core/time.hpp"

namespace coxswain::sim::devices {

/// A device as seen from its serial port. Thread-safety: none; one owner drives it.
class DeviceEmulator {
 public:
  virtual ~DeviceEmulator() = default;
  /// Bytes written by the host, split anywhere.
  virtual void receive(std::span<const std::uint8_t> host_bytes, core::TimeNs now_ns) = 0;
  /// Everything the device sends up to `now_ns` (answers first, then data that fell due). The
  /// view stays valid until the next call to poll() or receive().
  [[nodiscard]] virtual std::span<const std::uint8_t> poll(core::TimeNs now_ns) = 0;
};

}  // namespace coxswain::sim::devices
