// SPDX-License-Identifier: Apache-2.0
#include "sim/sensors/imu_sim.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "coxswain/core/angles.hpp"
#include "coxswain/drivers/myahrs/heading.hpp"

namespace coxswain::sim::sensors {
namespace {

ImuSimConfig quiet(double mount_yaw_deg, double declination_deg) {
  ImuSimConfig c;
  c.mount_yaw_deg = mount_yaw_deg;
  c.declination_deg = declination_deg;
  c.yaw_noise_sigma_deg = 0.0;
  c.yaw_drift_deg_per_sqrt_s = 0.0;
  c.attitude_noise_sigma_deg = 0.0;
  c.gyro_noise_sigma_dps = 0.0;
  c.accel_noise_sigma_g = 0.0;
  return c;
}

TEST(ImuSim, HeadingRoundTripThroughTheDriversConversionIsTruth) {
  for (const double mount : {0.0, 90.0, -135.0, 180.0}) {
    for (const double decl : {0.0, -8.5, 12.0}) {
      ImuSim sim(quiet(mount, decl));
      drivers::myahrs::HeadingConfig hc;
      hc.mount_yaw_deg = mount;
      hc.declination_deg = decl;
      BoatTruth truth;
      core::TimeNs t = 0;
      for (double h = -179.0; h <= 180.0; h += 7.0) {
        truth.pose.heading_deg = h;
        t += core::ms_to_ns(10);
        ASSERT_TRUE(sim.update(t, truth));
        const msg::ImuSample& s = sim.sample();
        // What the driver computes from the sensor's own yaw gives back the true heading.
        EXPECT_NEAR(
            core::angle_diff_deg(drivers::myahrs::true_heading_deg(s.yaw_magnetic_deg, hc), h), 0.0,
            1e-9)
            << "mount " << mount << " decl " << decl << " heading " << h;
        EXPECT_NEAR(core::angle_diff_deg(s.heading_deg, h), 0.0, 1e-9);
      }
    }
  }
}

TEST(ImuSim, MagneticYawIsTrueMinusDeclination) {
  ImuSim sim(quiet(0.0, -8.5));
  BoatTruth truth;
  truth.pose.heading_deg = 10.0;
  ASSERT_TRUE(sim.update(0, truth));
  EXPECT_NEAR(sim.sample().yaw_magnetic_deg, 18.5, 1e-9);  // true 10 = magnetic 18.5 - 8.5
}

TEST(ImuSim, RatesAccelerationsAndRate) {
  ImuSimConfig c = quiet(0.0, 0.0);
  c.roll_amplitude_deg = 0.0;
  c.pitch_amplitude_deg = 0.0;
  c.rate_hz = 50.0;
  ImuSim sim(c);
  BoatTruth truth;
  truth.yaw_rate_dps = 25.0;
  truth.accel_forward_mps2 = 0.980665;
  truth.accel_starboard_mps2 = -1.96133;
  int samples = 0;
  for (core::TimeNs t = 0; t < core::sec_to_ns(1.0); t += core::ms_to_ns(5)) {
    if (sim.update(t, truth)) ++samples;
  }
  EXPECT_EQ(samples, 50);
  const msg::ImuSample& s = sim.sample();
  EXPECT_TRUE(s.has_inertial);
  EXPECT_NEAR(s.gyro_dps[2], 25.0, 1e-9);
  EXPECT_NEAR(s.accel_g[0], 0.1, 1e-9);
  EXPECT_NEAR(s.accel_g[1], -0.2, 1e-9);
  EXPECT_NEAR(s.accel_g[2], -1.0, 1e-9);  // reaction to gravity, z down
  EXPECT_EQ(s.sequence, 49U);
}

TEST(ImuSim, DriftIsSlowAndBounded_DisturbanceIsLocal) {
  ImuSimConfig c = quiet(0.0, 0.0);
  c.yaw_drift_deg_per_sqrt_s = 0.2;
  c.yaw_drift_max_deg = 4.0;
  c.disturbances.push_back({{20.0, 0.0}, 3.0, 15.0});
  ImuSim sim(c);
  BoatTruth truth;
  double prev = 0.0;
  double max_step = 0.0;
  double max_abs = 0.0;
  for (core::TimeNs t = 0; t <= core::sec_to_ns(600.0); t += core::ms_to_ns(10)) {
    ASSERT_TRUE(sim.update(t, truth));
    const double e = sim.heading_error_deg();
    max_step = std::max(max_step, std::abs(e - prev));
    max_abs = std::max(max_abs, std::abs(e));
    prev = e;
  }
  EXPECT_LE(max_abs, 4.0);
  EXPECT_GT(max_abs, 1.0);
  EXPECT_LT(max_step, 0.15);
  EXPECT_NEAR(sim.disturbance_deg({20.0, 0.0}), 15.0, 1e-9);
  EXPECT_LT(std::abs(sim.disturbance_deg({0.0, 0.0})), 1e-6);
}

}  // namespace
}  // namespace coxswain::sim::sensors
