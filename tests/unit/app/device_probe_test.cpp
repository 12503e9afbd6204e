// SPDX-License-Identifier: Apache-2.0
#include "coxswain/app/device_probe.hpp"

#include <gtest/gtest.h>

#include <memory>

#include "coxswain/app/health_reporter.hpp"

namespace coxswain::app {
namespace {

TEST(DeviceProbe, AbsentPresentAndDisabled) {
  const auto absent = DeviceProbe::probe({msg::DeviceId::kLidar, true, "/dev/ttyNoSuchLiDAR"}, 5);
  EXPECT_EQ(absent.state, msg::DeviceState::kAbsent);
  EXPECT_EQ(absent.detail_text(), "/dev/ttyNoSuchLiDAR: No such file or directory");
  EXPECT_EQ(absent.stamp_ns, 5);
  const auto present = DeviceProbe::probe({msg::DeviceId::kImu, true, "/dev/null"}, 5);
  EXPECT_EQ(present.state, msg::DeviceState::kPresent);
  const auto disabled = DeviceProbe::probe({msg::DeviceId::kCamera, false, "/dev/video0"}, 5);
  EXPECT_EQ(disabled.state, msg::DeviceState::kDisabled);
}

TEST(DeviceProbe, LeavesDrivenDevicesToTheirDriver) {
  auto store = std::make_unique<core::LatestStore>();
  config::DevicesConfig devices;
  devices.lidar.path = "/dev/ttyNoSuchLiDAR";
  devices.imu.path = "/dev/null";
  std::array<bool, msg::kDeviceCount> driven{};
  driven[static_cast<std::size_t>(msg::DeviceId::kImu)] = true;
  DeviceProbe probe(devices, *store, driven);
  probe.probe_once(1);
  EXPECT_EQ(store->health_of(msg::DeviceId::kImu).sequence(), 0U);  // never written
  EXPECT_EQ(store->health_of(msg::DeviceId::kLidar).read().value.state, msg::DeviceState::kAbsent);
}

TEST(HealthReporter, ReportsEachChangeOnce) {
  auto store = std::make_unique<core::LatestStore>();
  auto snap = std::make_unique<core::Snapshot>();
  config::DevicesConfig devices;
  devices.lidar.path = "/dev/ttyNoSuchLiDAR";
  devices.imu.path = "/dev/null";
  devices.gnss.enabled = false;
  devices.arduino.path = "/dev/ttyNoSuchArduino";
  devices.camera.source = "/dev/NoSuchVideo";
  DeviceProbe probe(devices, *store);
  HealthReporter reporter;
  probe.probe_once(1);
  store->snapshot(*snap);
  EXPECT_EQ(reporter.report_changes(*snap), 5);
  for (int tick = 0; tick < 100; ++tick) {  // the same state every tick: nothing to report
    probe.probe_once(2 + tick);
    store->snapshot(*snap);
    EXPECT_EQ(reporter.report_changes(*snap), 0);
  }
  EXPECT_EQ(HealthReporter::summary(*snap),
            "lidar=absent imu=present gnss=disabled arduino=absent camera=absent");
}

}  // namespace
}  // namespace coxswain::app
