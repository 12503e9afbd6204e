// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/device_sessions.hpp"

namespace coxswain::app {

const config::SerialDeviceConfig* serial_device_config(msg::DeviceId id,
                                                       const config::DevicesConfig& devices) {
  switch (id) {
    case msg::DeviceId::kLidar:
      return &devices.lidar;
    case msg::DeviceId::kImu:
      return &devices.imu;
    case msg::DeviceId::kGnss:
      return &devices.gnss;
    case msg::DeviceId::kArduino:
      return &devices.arduino;
    case msg::DeviceId::kCamera:
      return nullptr;
  }
  return nullptr;
}

std::unique_ptr<drivers::DeviceSession> make_device_session(
    msg::DeviceId id, [[maybe_unused]] const config::Configuration& config,
    [[maybe_unused]] core::LatestStore& store) {
  // One `return std::make_unique<...Session>(...)` per device whose session is in the build.
  switch (id) {
    case msg::DeviceId::kLidar:
    case msg::DeviceId::kImu:
    case msg::DeviceId::kGnss:
    case msg::DeviceId::kArduino:
    case msg::DeviceId::kCamera:
      return nullptr;
  }
  return nullptr;
}

}  // namespace coxswain::app
