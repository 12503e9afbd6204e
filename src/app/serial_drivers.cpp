// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/serial_drivers.hpp"

#include <spdlog/spdlog.h>

#include "coxswain/app/device_sessions.hpp"

namespace coxswain::app {

SerialDrivers::SerialDrivers(const config::DevicesConfig& devices,
                             const SessionFactory& make_session, core::LatestStore& store,
                             const core::Clock& clock, drivers::RawByteSink* raw_sink,
                             const drivers::serial::TransportOptions& options) {
  for (const msg::DeviceId id : kSerialDevices) {
    const config::SerialDeviceConfig* port = serial_device_config(id, devices);
    if (port == nullptr || !port->enabled) continue;
    Driver d;
    d.session = make_session(id);
    if (!d.session) {
      spdlog::info("{}: no driver in this build; only its presence is probed",
                   msg::device_name(id));
      continue;
    }
    d.transport = std::make_unique<drivers::serial::SerialTransport>(
        *port, *d.session, store.health_of(id), clock, raw_sink, options);
    driven_[static_cast<std::size_t>(id)] = true;
    drivers_.push_back(std::move(d));
  }
}

SerialDrivers::~SerialDrivers() { stop(); }

void SerialDrivers::start() {
  for (Driver& d : drivers_) d.transport->start();
}

void SerialDrivers::stop() {
  for (Driver& d : drivers_) d.transport->stop();
}

bool SerialDrivers::drives(msg::DeviceId id) const { return driven_[static_cast<std::size_t>(id)]; }

drivers::serial::TransportCounters SerialDrivers::counters(msg::DeviceId id) const {
  for (const Driver& d : drivers_) {
    if (d.transport->device() == id) return d.transport->counters();
  }
  return {};
}

}  // namespace coxswain::app
