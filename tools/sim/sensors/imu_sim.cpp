// SPDX-License-Identifier: Apache-2.0
#include "sim/sensors/imu_sim.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "coxswain/core/angles.hpp"
#include "coxswain/drivers/myahrs/heading.hpp"

namespace coxswain::sim::sensors {

namespace {
constexpr double kGravityMps2 = 9.80665;
}  // namespace

std::optional<std::string> ImuSimConfig::validate() const {
  if (!(rate_hz >= 1.0 && rate_hz <= 100.0)) return "imu rate_hz must be in [1, 100]";
  if (!std::isfinite(mount_yaw_deg) || std::abs(mount_yaw_deg) > 360.0) {
    return "imu mount_yaw_deg must be within [-360, 360]";
  }
  if (!std::isfinite(declination_deg) || std::abs(declination_deg) > 90.0) {
    return "imu declination_deg must be within [-90, 90]";
  }
  if (!(yaw_noise_sigma_deg >= 0.0 && yaw_noise_sigma_deg <= 30.0)) {
    return "imu yaw_noise_sigma_deg in [0, 30]";
  }
  if (!(yaw_drift_deg_per_sqrt_s >= 0.0 && yaw_drift_deg_per_sqrt_s <= 10.0)) {
    return "imu yaw_drift_deg_per_sqrt_s in [0, 10]";
  }
  if (!(yaw_drift_max_deg >= 0.0 && yaw_drift_max_deg <= 180.0)) {
    return "imu yaw_drift_max_deg in [0, 180]";
  }
  for (const MagneticDisturbance& d : disturbances) {
    if (!(d.radius_m > 0.0) || !std::isfinite(d.offset_deg) || std::abs(d.offset_deg) > 180.0 ||
        !std::isfinite(d.center.north_m) || !std::isfinite(d.center.east_m)) {
      return "imu disturbance needs radius_m > 0 and offset_deg within [-180, 180]";
    }
  }
  if (!std::isfinite(sinusoid_amplitude_deg) || std::abs(sinusoid_amplitude_deg) > 180.0) {
    return "imu sinusoid_amplitude_deg within [-180, 180]";
  }
  if (!(sinusoid_wavelength_m > 0.0)) return "imu sinusoid_wavelength_m must be > 0";
  if (!std::isfinite(sinusoid_direction_deg)) return "imu sinusoid_direction_deg must be finite";
  if (!(roll_amplitude_deg >= 0.0 && roll_amplitude_deg <= 45.0) ||
      !(pitch_amplitude_deg >= 0.0 && pitch_amplitude_deg <= 45.0)) {
    return "imu roll/pitch amplitudes in [0, 45]";
  }
  if (!(wave_period_s > 0.1)) return "imu wave_period_s must be > 0.1";
  if (!(attitude_noise_sigma_deg >= 0.0) || !(gyro_noise_sigma_dps >= 0.0) ||
      !(accel_noise_sigma_g >= 0.0)) {
    return "imu noise sigmas must be >= 0";
  }
  if (!(field_horizontal_ut > 0.0) || !std::isfinite(field_down_ut)) {
    return "imu field_horizontal_ut must be > 0";
  }
  if (!std::isfinite(temperature_c)) return "imu temperature_c must be finite";
  return {};
}

ImuSim::ImuSim(const ImuSimConfig& config)
    : config_(config),
      rng_(config.seed),
      period_ns_(static_cast<core::TimeNs>(std::llround(1e9 / config.rate_hz))) {
  wave_phase_ = rng_.uniform(0.0, 2.0 * core::kPi);
}

double ImuSim::disturbance_deg(core::NavPoint p) const {
  double out = 0.0;
  for (const MagneticDisturbance& d : config_.disturbances) {
    const double r = core::distance_m(p, d.center) / d.radius_m;
    out += d.offset_deg * std::exp(-0.5 * r * r);
  }
  if (config_.sinusoid_amplitude_deg != 0.0) {
    const double a = core::deg_to_rad(config_.sinusoid_direction_deg);
    const double along = p.north_m * std::cos(a) + p.east_m * std::sin(a);
    out += config_.sinusoid_amplitude_deg *
           std::sin(2.0 * core::kPi * along / config_.sinusoid_wavelength_m);
  }
  return out;
}

bool ImuSim::update(core::TimeNs now_ns, const BoatTruth& truth) {
  const core::TimeNs t_ns = now_ns >= 0 ? (now_ns / period_ns_) * period_ns_
                                        : -((-now_ns + period_ns_ - 1) / period_ns_) * period_ns_;
  if (last_ns_ != core::kNeverNs && t_ns <= last_ns_) return false;
  const double dt_s = last_ns_ == core::kNeverNs ? 0.0 : core::ns_to_sec(t_ns - last_ns_);
  last_ns_ = t_ns;

  if (dt_s > 0.0) {
    drift_deg_ += rng_.normal(config_.yaw_drift_deg_per_sqrt_s * std::sqrt(dt_s));
    drift_deg_ = std::clamp(drift_deg_, -config_.yaw_drift_max_deg, config_.yaw_drift_max_deg);
  }
  const core::NavPoint at = core::body_to_nav(truth.pose, {0.0, 0.0});
  error_deg_ = drift_deg_ + disturbance_deg(at);

  msg::ImuSample s;
  s.stamp_ns = now_ns;
  // The board reports the magnetic heading of its own x axis: the bow's true heading turned by
  // the mount and taken back to magnetic north (true = magnetic + declination).
  s.yaw_magnetic_deg =
      core::wrap_deg(truth.pose.heading_deg + config_.mount_yaw_deg - config_.declination_deg +
                     error_deg_ + rng_.normal(config_.yaw_noise_sigma_deg));
  drivers::myahrs::HeadingConfig hc;
  hc.mount_yaw_deg = config_.mount_yaw_deg;
  hc.declination_deg = config_.declination_deg;
  s.heading_deg = drivers::myahrs::true_heading_deg(s.yaw_magnetic_deg, hc);

  const double t_s = core::ns_to_sec(t_ns);
  const double w = 2.0 * core::kPi / config_.wave_period_s;
  const double roll_body = config_.roll_amplitude_deg * std::sin(w * t_s + wave_phase_);
  const double pitch_body =
      config_.pitch_amplitude_deg * std::sin(0.8 * w * t_s + 1.3 * wave_phase_);
  const double roll_rate = config_.roll_amplitude_deg * w * std::cos(w * t_s + wave_phase_);
  const double pitch_rate =
      config_.pitch_amplitude_deg * 0.8 * w * std::cos(0.8 * w * t_s + 1.3 * wave_phase_);

  // Body -> board axes: the board is turned mount_yaw clockwise about z (down).
  const double m = core::deg_to_rad(config_.mount_yaw_deg);
  const double cm = std::cos(m);
  const double sm = std::sin(m);
  const auto to_board = [cm, sm](double x, double y) {
    return std::array<double, 2>{x * cm + y * sm, -x * sm + y * cm};
  };
  const auto att = to_board(roll_body, pitch_body);  // small angles rotate like a vector
  s.roll_deg = att[0] + rng_.normal(config_.attitude_noise_sigma_deg);
  s.pitch_deg = att[1] + rng_.normal(config_.attitude_noise_sigma_deg);

  const auto gyro = to_board(roll_rate, pitch_rate);
  s.gyro_dps = {gyro[0] + rng_.normal(config_.gyro_noise_sigma_dps),
                gyro[1] + rng_.normal(config_.gyro_noise_sigma_dps),
                truth.yaw_rate_dps + rng_.normal(config_.gyro_noise_sigma_dps)};

  // Specific force: the accelerometer reads the reaction to gravity (z ~ -1 g at rest) plus the
  // motion; the IMU sits aft of the bow reference but the lever-arm terms are small at boat rates.
  const auto acc =
      to_board(truth.accel_forward_mps2 / kGravityMps2, truth.accel_starboard_mps2 / kGravityMps2);
  const double roll_r = core::deg_to_rad(roll_body);
  const double pitch_r = core::deg_to_rad(pitch_body);
  const auto grav = to_board(std::sin(pitch_r), -std::sin(roll_r) * std::cos(pitch_r));
  s.accel_g = {acc[0] + grav[0] + rng_.normal(config_.accel_noise_sigma_g),
               acc[1] + grav[1] + rng_.normal(config_.accel_noise_sigma_g),
               -std::cos(roll_r) * std::cos(pitch_r) + rng_.normal(config_.accel_noise_sigma_g)};

  // Magnetic field in board axes (level approximation): points to magnetic north, dips down.
  const double mag_heading = core::deg_to_rad(s.yaw_magnetic_deg);
  s.mag_ut = {config_.field_horizontal_ut * std::cos(mag_heading),
              -config_.field_horizontal_ut * std::sin(mag_heading), config_.field_down_ut};
  s.temperature_c = config_.temperature_c;
  s.has_inertial = true;
  s.sequence = sequence_++;
  sample_ = s;
  return true;
}

}  // namespace coxswain::sim::sensors
