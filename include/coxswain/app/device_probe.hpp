// SPDX-License-Identifier: Apache-2.0
#pragma once
// Looks for each configured device node without opening it (opening an Arduino resets it) and
// publishes its presence into the store's health slot. It stands in only for devices whose driver
// is not running; once a driver owns a device, the driver publishes that device's health.
#include <array>
#include <string>

#include "coxswain/config/config.hpp"
#include "coxswain/core/latest_store.hpp"

namespace coxswain::app {

struct ProbedDevice {
  msg::DeviceId id = msg::DeviceId::kLidar;
  bool enabled = false;
  std::string path;
};

/// Not thread-safe: one probing thread calls probe_once; it is the single writer of the health
/// slots of the devices it probes.
class DeviceProbe {
 public:
  /// Devices marked in `driven` have a running driver, which owns their health slot: they are
  /// not probed.
  DeviceProbe(const config::DevicesConfig& devices, core::LatestStore& store,
              const std::array<bool, msg::kDeviceCount>& driven = {});
  /// Checks every device and publishes its health stamped `now_ns`.
  void probe_once(core::TimeNs now_ns);
  [[nodiscard]] static msg::DeviceHealth probe(const ProbedDevice& device, core::TimeNs now_ns);

 private:
  std::array<ProbedDevice, msg::kDeviceCount> devices_;
  std::array<bool, msg::kDeviceCount> driven_;
  core::LatestStore& store_;
};

}  // namespace coxswain::app
