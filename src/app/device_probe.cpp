// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/device_probe.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace coxswain::app {

DeviceProbe::DeviceProbe(const config::DevicesConfig& d, core::LatestStore& store,
                         const std::array<bool, msg::kDeviceCount>& driven)
    : driven_(driven), store_(store) {
  devices_ = {ProbedDevice{msg::DeviceId::kLidar, d.lidar.enabled, d.lidar.path},
              ProbedDevice{msg::DeviceId::kImu, d.imu.enabled, d.imu.path},
              ProbedDevice{msg::DeviceId::kGnss, d.gnss.enabled, d.gnss.path},
              ProbedDevice{msg::DeviceId::kArduino, d.arduino.enabled, d.arduino.path},
              ProbedDevice{msg::DeviceId::kCamera, d.camera.enabled, d.camera.source}};
}

msg::DeviceHealth DeviceProbe::probe(const ProbedDevice& device, core::TimeNs now_ns) {
  msg::DeviceHealth h;
  h.stamp_ns = now_ns;
  h.device = device.id;
  if (!device.enabled) {
    h.state = msg::DeviceState::kDisabled;
    h.set_detail("disabled in devices config");
    return h;
  }
  struct stat st {};
  if (::stat(device.path.c_str(), &st) != 0) {
    const int err = errno;
    h.state = msg::DeviceState::kAbsent;
    h.set_detail(device.path + ": " + std::strerror(err));
    return h;
  }
  if (::access(device.path.c_str(), R_OK | W_OK) != 0 && !S_ISDIR(st.st_mode) &&
      !S_ISREG(st.st_mode)) {
    const int err = errno;
    h.state = msg::DeviceState::kError;
    h.set_detail(device.path + ": " + std::strerror(err) +
                 " (is the user in the dialout/video group?)");
    return h;
  }
  h.state = msg::DeviceState::kPresent;
  h.set_detail(device.path + ": present, no driver attached");
  return h;
}

void DeviceProbe::probe_once(core::TimeNs now_ns) {
  for (const ProbedDevice& device : devices_) {
    if (driven_[static_cast<std::size_t>(device.id)]) continue;  // its driver publishes health
    store_.health_of(device.id).publish(probe(device, now_ns), now_ns);
  }
}

}  // namespace coxswain::app
