// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/device_sessions.hpp"

#include "coxswain/drivers/arduino/session.hpp"
#include "coxswain/drivers/myahrs/session.hpp"
#include "coxswain/drivers/rplidar/session.hpp"
#include "coxswain/drivers/ublox/session.hpp"

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

std::unique_ptr<drivers::DeviceSession> make_device_session(msg::DeviceId id,
                                                            const config::Configuration& config,
                                                            core::LatestStore& store) {
  switch (id) {
    case msg::DeviceId::kLidar:
      return std::make_unique<drivers::rplidar::RplidarSession>(
          config.devices.lidar, config.boat.mounts.lidar, store.lidar);
    case msg::DeviceId::kImu:
      return std::make_unique<drivers::myahrs::MyahrsSession>(config.devices.imu,
                                                              config.boat.mounts.imu, store.imu);
    case msg::DeviceId::kGnss:
      return std::make_unique<drivers::ublox::UbloxSession>(config.devices.gnss, store.gnss);
    case msg::DeviceId::kArduino:
      return std::make_unique<drivers::arduino::ArduinoSession>(
          config.devices.arduino, config.boat.actuators, store.command, store.arduino);
    case msg::DeviceId::kCamera:
      return nullptr;  // not a serial device: drivers::camera::CameraDriver
  }
  return nullptr;
}

}  // namespace coxswain::app
