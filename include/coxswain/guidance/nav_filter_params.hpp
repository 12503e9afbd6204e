// SPDX-License-Identifier: Apache-2.0
#pragma once
// The navigation filter's tunables, apart from the filter so that the configuration (plain data)
// need not see Eigen.
#include <cstdint>
#include <optional>
#include <string>

namespace coxswain::guidance {

struct NavFilterParams {
  // Process noise (random walks, per sqrt(second)).
  double accel_noise_mps2 = 0.3;                      // unmodelled acceleration (white)
  double heading_walk_deg_per_sqrt_s = 0.2;           // gyro noise integrated into heading
  double heading_walk_no_gyro_deg_per_sqrt_s = 40.0;  // no yaw rate: the boat's own turns
  double gyro_bias_walk_dps_per_sqrt_s = 0.02;        // yaw-rate bias drift
  double gnss_bias_wander_sigma_m = 1.0;              // receiver bias wander around its constant
  double gnss_bias_tau_s = 300.0;                     // part (Gauss-Markov), per axis
  double mag_bias_walk_deg_per_sqrt_s = 0.3;          // magnetometer error drift
  // Priors.
  double initial_gnss_bias_sigma_m = 10.0;  // constant part before the start calibration
  double initial_mag_bias_sigma_deg = 5.0;
  double initial_gyro_bias_sigma_dps = 1.0;
  double initial_velocity_sigma_mps = 1.0;  // first fix without a velocity
  // Measurement noise.
  double mag_noise_deg = 2.0;              // white part of the magnetometer heading
  double gnss_sigma_floor_m = 0.3;         // single point, per axis (hAcc / sqrt 2 above)
  double gnss_float_sigma_floor_m = 0.1;   // RTK float
  double gnss_fixed_sigma_floor_m = 0.02;  // RTK fixed
  double gnss_unknown_sigma_m = 2.5;       // no hAcc (NMEA without GST): per axis
  double gnss_velocity_sigma_mps = 0.1;    // per axis: without sAcc, and the floor under it
  // Course over ground as a heading measurement. Off by default: a steady current crabs the
  // boat the same way for a whole leg, an error no white-noise model averages out (it cost
  // docking approaches their slip in the simulator); worth it with a magnetometer that cannot
  // be calibrated, in still water. The magnetometer-disagreement report runs either way.
  bool cog_heading_update = false;
  double cog_min_speed_mps = 0.6;      // slower: the course is noise
  double cog_max_yaw_rate_dps = 4.0;   // turning: the antenna's swing and crab
  double cog_crab_sigma_deg = 6.0;     // leeway: COG - heading at any speed
  double cog_current_mps = 0.2;        // water current the crab angle is allowed for
  double cog_interval_s = 1.0;         // at most one COG update per interval
  double mag_cog_disagree_deg = 15.0;  // mean |COG - magnetometer| that is reported
  double mag_cog_window_s = 10.0;      // time constant of that mean
  // Gating.
  double gate_chi2_2dof = 13.8;              // 99.9 % (position, velocity, bias)
  double gate_chi2_1dof = 10.8;              // 99.9 % (heading)
  std::uint32_t max_rejected_fixes = 10;     // then the fix is taken (covariance opened)
  std::uint32_t max_rejected_headings = 50;  // the same for magnetometer samples
  double max_fix_gap_s = 5.0;                // longer outage: position restarts at the fix
  // Start calibration.
  double start_placement_sigma_m = 0.3;    // the boat on the known start point, per axis
  double uncalibrated_bias_sigma_m = 0.3;  // no start calibration: the receiver's frame
                                           // is the waypoints' (their agreement, per axis)

  [[nodiscard]] std::optional<std::string> validate() const;
};

}  // namespace coxswain::guidance
