// SPDX-License-Identifier: Apache-2.0
#pragma once
// The daemon's serial device drivers: one SerialTransport (own thread) per enabled serial device
// that has a session.
#include <array>
#include <functional>
#include <memory>
#include <vector>

#include "coxswain/config/config.hpp"
#include "coxswain/core/clock.hpp"
#include "coxswain/core/latest_store.hpp"
#include "coxswain/drivers/device_session.hpp"
#include "coxswain/drivers/serial/serial_transport.hpp"

namespace coxswain::app {

/// Owns the sessions and transports of a run. Construction makes a session for every enabled
/// serial device through `make_session` (nullptr = no driver in this build: the device is left
/// to DeviceProbe); start() opens them, stop() closes them (each within milliseconds).
/// Thread-safety: start/stop/destruction from one thread; counters() from any thread.
class SerialDrivers {
 public:
  using SessionFactory =
      std::function<std::unique_ptr<drivers::DeviceSession>(msg::DeviceId device)>;

  SerialDrivers(const config::DevicesConfig& devices, const SessionFactory& make_session,
                core::LatestStore& store, const core::Clock& clock,
                drivers::RawByteSink* raw_sink = nullptr,
                const drivers::serial::TransportOptions& options = {});
  ~SerialDrivers();
  SerialDrivers(const SerialDrivers&) = delete;
  SerialDrivers& operator=(const SerialDrivers&) = delete;

  void start();
  void stop();

  /// True for the devices a transport drives (their health slot is the transport's).
  [[nodiscard]] bool drives(msg::DeviceId id) const;
  [[nodiscard]] std::array<bool, msg::kDeviceCount> driven() const { return driven_; }
  /// Transport counters of a driven device (zeros otherwise).
  [[nodiscard]] drivers::serial::TransportCounters counters(msg::DeviceId id) const;

 private:
  struct Driver {
    std::unique_ptr<drivers::DeviceSession> session;
    std::unique_ptr<drivers::serial::SerialTransport> transport;
  };
  std::vector<Driver> drivers_;
  std::array<bool, msg::kDeviceCount> driven_{};
};

}  // namespace coxswain::app
