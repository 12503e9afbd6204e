// SPDX-License-Identifier: Apache-2.0
#pragma once
// Noise-free sensors: IMU samples (true heading, yaw rate, body acceleration) at imu_rate_hz and
// GNSS fixes (true position of the GNSS mount, velocity over ground) at gnss_rate_hz, published
// from the truth. For tests, and for runs that want to separate control from sensing errors; the
// realistic sensors live in tools/sim/sensors. Deterministic; runner thread only.
#include "coxswain/config/config.hpp"
#include "coxswain/core/geodesy.hpp"
#include "sim/runner/sensor_suite.hpp"

namespace coxswain::sim::runner {

class IdealSensorSuite final : public SensorSuite {
 public:
  IdealSensorSuite(const core::GeoPoint& origin, const config::BoatConfig& boat,
                   double imu_rate_hz = 100.0, double gnss_rate_hz = 5.0);
  void step(const dynamics::TruthState& truth, core::TimeNs now_ns,
            core::LatestStore& store) override;

 private:
  core::LocalFrame frame_;
  config::BoatConfig boat_;
  core::TimeNs imu_period_ns_;
  core::TimeNs gnss_period_ns_;
  core::TimeNs next_imu_ns_ = 0;
  core::TimeNs next_gnss_ns_ = 0;
  unsigned imu_sequence_ = 0;
};

}  // namespace coxswain::sim::runner
