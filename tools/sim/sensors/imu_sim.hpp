// SPDX-License-Identifier: Apache-2.0
#pragma once
// Simulated myAHRS+: one msg::ImuSample per 1/rate_hz with the MAGNETIC yaw of the board as the
// sensor reports it (true heading - declination + mount yaw, plus noise, a slow random-walk drift
// and local magnetic disturbance), heading_deg filled through the driver's own conversion
// (drivers::myahrs::true_heading_deg), small wave-driven roll and pitch, and gyro rates,
// accelerations and the magnetic field in the board's axes (x along its arrow, y right, z down;
// the board is turned mount_yaw_deg from the bow). Deterministic for a seed. Not thread-safe.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "coxswain/core/frames.hpp"
#include "coxswain/core/time.hpp"
#include "coxswain/msg/imu_sample.hpp"
#include "sim/rng/rng.hpp"
#include "sim/sensors/truth.hpp"

namespace coxswain::sim::sensors {

/// A patch of disturbed magnetic field (steel pier, pump house): the yaw error peaks at
/// `offset_deg` at the centre and fades as a Gaussian of distance with `radius_m` as sigma.
struct MagneticDisturbance {
  core::NavPoint center;
  double radius_m = 5.0;
  double offset_deg = 10.0;
};

struct ImuSimConfig {
  double rate_hz = 100.0;
  double mount_yaw_deg = 0.0;              // board x axis turned clockwise from the bow (boat.yaml)
  double declination_deg = -8.5;           // east positive (devices.yaml imu.declination_deg)
  double yaw_noise_sigma_deg = 0.5;        // white noise on the reported yaw
  double yaw_drift_deg_per_sqrt_s = 0.05;  // random walk of the yaw error
  double yaw_drift_max_deg = 5.0;          // the walk is held within +-this
  std::vector<MagneticDisturbance> disturbances;
  // A field error varying along the course: amplitude * sin(2 pi (north cos a + east sin a) / L).
  double sinusoid_amplitude_deg = 0.0;
  double sinusoid_wavelength_m = 20.0;
  double sinusoid_direction_deg = 0.0;
  double roll_amplitude_deg = 2.0;  // waves
  double pitch_amplitude_deg = 1.0;
  double wave_period_s = 2.5;
  double attitude_noise_sigma_deg = 0.1;
  double gyro_noise_sigma_dps = 0.2;
  double accel_noise_sigma_g = 0.01;
  double field_horizontal_ut = 30.0;  // Korea: about 30 uT horizontal, 40 uT down
  double field_down_ut = 40.0;
  double temperature_c = 28.0;
  std::uint64_t seed = 3;

  [[nodiscard]] std::optional<std::string> validate() const;
};

class ImuSim {
 public:
  explicit ImuSim(const ImuSimConfig& config);

  /// Produces the sample due at or before `now_ns` (samples fall on multiples of 1/rate_hz),
  /// true when one was produced; read it with sample(). Call at least once per sample period.
  bool update(core::TimeNs now_ns, const BoatTruth& truth);
  [[nodiscard]] const msg::ImuSample& sample() const { return sample_; }
  /// Current heading error from drift and disturbance (noise excluded), degrees.
  [[nodiscard]] double heading_error_deg() const { return error_deg_; }
  /// The magnetic disturbance at a point, degrees.
  [[nodiscard]] double disturbance_deg(core::NavPoint p) const;
  [[nodiscard]] const ImuSimConfig& config() const { return config_; }

 private:
  ImuSimConfig config_;
  Rng rng_;
  core::TimeNs period_ns_ = 0;
  core::TimeNs last_ns_ = core::kNeverNs;
  double drift_deg_ = 0.0;
  double error_deg_ = 0.0;
  double wave_phase_ = 0.0;
  unsigned sequence_ = 0;
  msg::ImuSample sample_;
};

}  // namespace coxswain::sim::sensors
