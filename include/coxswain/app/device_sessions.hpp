// SPDX-License-Identifier: Apache-2.0
#pragma once
// Which device sessions the daemon runs: the one place where a serial device's protocol session
// is chosen and given its config and store slots.
#include <array>
#include <memory>

#include "coxswain/config/config.hpp"
#include "coxswain/core/latest_store.hpp"
#include "coxswain/drivers/device_session.hpp"

namespace coxswain::app {

/// The serial devices, in start order (the camera is not a serial device).
inline constexpr std::array<msg::DeviceId, 4> kSerialDevices = {
    msg::DeviceId::kLidar, msg::DeviceId::kImu, msg::DeviceId::kGnss, msg::DeviceId::kArduino};

/// The serial port settings of `id`; nullptr for the camera.
[[nodiscard]] const config::SerialDeviceConfig* serial_device_config(
    msg::DeviceId id, const config::DevicesConfig& devices);

/// The session that drives device `id`, publishing into `store`; nullptr when this build has no
/// driver for it (the daemon then only probes the device's presence). Adding a driver is one
/// line in the switch. `config` and `store` must outlive the session.
[[nodiscard]] std::unique_ptr<drivers::DeviceSession> make_device_session(
    msg::DeviceId id, const config::Configuration& config, core::LatestStore& store);

}  // namespace coxswain::app
