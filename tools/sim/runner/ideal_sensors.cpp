// SPDX-License-Identifier: Apache-2.0
#include "sim/runner/ideal_sensors.hpp"

#include <cmath>

#include "coxswain/core/angles.hpp"
#include "sim/dynamics/boat_model.hpp"

namespace coxswain::sim::runner {

IdealSensorSuite::IdealSensorSuite(const core::GeoPoint& origin, const config::BoatConfig& boat,
                                   double imu_rate_hz, double gnss_rate_hz)
    : frame_(origin),
      boat_(boat),
      imu_period_ns_(core::sec_to_ns(1.0 / imu_rate_hz)),
      gnss_period_ns_(core::sec_to_ns(1.0 / gnss_rate_hz)) {}

void IdealSensorSuite::step(const dynamics::TruthState& truth, core::TimeNs now_ns,
                            core::LatestStore& store) {
  if (now_ns >= next_imu_ns_) {
    next_imu_ns_ = now_ns + imu_period_ns_;
    msg::ImuSample s;
    s.stamp_ns = now_ns;
    s.heading_deg = truth.pose.heading_deg;
    s.yaw_magnetic_deg = truth.pose.heading_deg;
    constexpr double kG = 9.80665;
    s.accel_g = {truth.accel_forward_mps2 / kG, truth.accel_starboard_mps2 / kG, 1.0};
    s.gyro_dps = {0.0, 0.0, truth.yaw_rate_dps};
    s.has_inertial = true;
    s.sequence = imu_sequence_++;
    store.imu.publish(s, now_ns);
  }
  if (now_ns >= next_gnss_ns_) {
    next_gnss_ns_ = now_ns + gnss_period_ns_;
    const core::NavPoint antenna =
        core::body_to_nav(truth.pose, {boat_.mounts.gnss.x_m, boat_.mounts.gnss.y_m});
    const core::GeoPoint geo = frame_.to_geo(antenna);
    msg::GnssFix f;
    f.stamp_ns = now_ns;
    f.fix_type = msg::FixType::k3D;
    f.fix_ok = true;
    f.rtk = msg::RtkSolution::kFixed;
    f.lat_deg = geo.lat_deg;
    f.lon_deg = geo.lon_deg;
    f.h_acc_m = 0.01;
    f.satellites = 20;
    f.velocity_valid = true;
    const core::NavPoint v = dynamics::velocity_at(truth, antenna);  // the antenna's own
    f.vel_north_mps = v.north_m;
    f.vel_east_mps = v.east_m;
    f.ground_speed_mps = std::hypot(v.north_m, v.east_m);
    f.course_deg = core::rad_to_deg(std::atan2(v.east_m, v.north_m));
    store.gnss.publish(f, now_ns);
  }
}

}  // namespace coxswain::sim::runner
