// SPDX-License-Identifier: Apache-2.0
#pragma once
// GNSS + IMU fusion: an extended Kalman filter on the GNSS antenna's position and velocity, the
// bow's heading, the gyro's yaw-rate bias, the receiver's bias (the 5-10 m one-way shift the
// documents saw) and the magnetometer's heading bias. The IMU's yaw rate and accelerations
// (gravity taken out with roll and pitch) propagate it; GNSS position (noise from the receiver's
// own hAcc, floors per fix type and RTK solution) observes position + bias (a constant part the
// start calibration pins and a Gauss-Markov wander around it); GNSS velocity
// observes velocity; the magnetometer heading observes heading + magnetometer bias; course over
// ground observes heading when the boat runs straight and fast enough; the start-point
// calibration observes the bias. Every update is chi-square gated, so a GNSS jump is refused
// rather than followed; between fixes (and through an outage) the filter dead-reckons and its
// covariance grows. Fixed-size matrices: no allocation, deterministic, not thread-safe.
#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "coxswain/core/frames.hpp"
#include "coxswain/core/time.hpp"
#include "coxswain/guidance/nav_filter_params.hpp"
#include "coxswain/msg/gnss_fix.hpp"

namespace coxswain::guidance {

/// North/east covariance of a position, m^2 (navigation frame).
struct PositionCovariance {
  double nn_m2 = 0.0;
  double ne_m2 = 0.0;
  double ee_m2 = 0.0;

  /// Standard deviation along a unit direction given by a bearing (deg, 0 north, clockwise).
  [[nodiscard]] double sigma_along_m(double bearing_deg) const;
  /// Standard deviation along the line from `from` to `to` (the larger axis when they coincide).
  [[nodiscard]] double sigma_toward_m(core::NavPoint from, core::NavPoint to) const;
  /// Semi-axes (1 sigma, major first) and the bearing of the major axis (deg).
  void axes(double& major_m, double& minor_m, double& major_bearing_deg) const;
  /// Largest 1-sigma along any direction.
  [[nodiscard]] double sigma_major_m() const;
};

/// Quantile of the standard normal distribution (Acklam's rational approximation, 1e-9
/// relative): the k of "estimate + k sigma" for a one-sided confidence `p` in (0, 1).
[[nodiscard]] double normal_quantile(double p);

/// True when `point` lies inside the circle of `radius_m` around `centre` with one-sided
/// confidence given by `k_sigma`: distance + k * sigma (along the line of sight) <= radius.
[[nodiscard]] bool confidently_within(core::NavPoint point, const PositionCovariance& cov,
                                      core::NavPoint centre, double radius_m, double k_sigma);

/// True when the estimate is good enough to judge a line crossing between `left` and `right`:
/// the position is at least k sigma (along the line) inside each end, and k sigma across the
/// line is less than `max_across_m` (a crossing judged within that distance of the line).
[[nodiscard]] bool confident_crossing(core::NavPoint position, const PositionCovariance& cov,
                                      core::NavPoint left, core::NavPoint right, double k_sigma,
                                      double max_across_m);

/// What the filter did with a measurement.
enum class NavUpdate : std::uint8_t { kUsed = 0, kRejected, kForced, kSkipped };

class NavFilter {
 public:
  static constexpr int kStates = 11;
  using Vector = Eigen::Matrix<double, kStates, 1>;
  using Matrix = Eigen::Matrix<double, kStates, kStates>;
  // State order: antenna position and velocity (m, m/s, north/east), heading (rad), yaw-rate
  // bias (rad/s), the GNSS bias's constant part (m), the magnetometer bias (rad), the GNSS
  // bias's wander (m).
  static constexpr int kPn = 0, kPe = 1, kVn = 2, kVe = 3, kPsi = 4, kBg = 5, kBn = 6, kBe = 7,
                       kBm = 8, kWn = 9, kWe = 10;

  explicit NavFilter(NavFilterParams p = {});
  void reset();

  /// An IMU sample: yaw rate (deg/s, clockwise), body accelerations as the sensor reports them
  /// (specific force in g, x forward, y starboard, z down) with roll and pitch (deg) to take
  /// gravity out, and the true magnetometer heading (deg, declination applied). Rates and
  /// accelerations hold until the next sample. `inertial` false: heading only.
  void add_imu(core::TimeNs stamp_ns, double heading_deg, bool inertial, double yaw_rate_dps,
               double accel_fwd_g, double accel_stbd_g, double roll_deg, double pitch_deg);
  /// A GNSS fix of the antenna in the navigation frame with the receiver's quality fields.
  NavUpdate add_fix(core::TimeNs stamp_ns, core::NavPoint fix, const msg::GnssFix& quality);
  /// The start-point calibration: the receiver's bias measured on the known start point
  /// (measured - true, metres) with its standard deviation per axis.
  NavUpdate add_bias_measurement(core::NavPoint bias_m, double sigma_m);
  /// Dead-reckons the state to `now_ns` (no-op when not later than the filter's time).
  void predict_to(core::TimeNs now_ns);

  [[nodiscard]] const NavFilterParams& params() const { return p_; }
  [[nodiscard]] bool has_position() const { return has_position_; }
  [[nodiscard]] bool has_heading() const { return has_heading_; }
  [[nodiscard]] core::NavPoint position() const { return {x_(kPn), x_(kPe)}; }
  [[nodiscard]] core::NavPoint velocity_mps() const { return {x_(kVn), x_(kVe)}; }
  [[nodiscard]] double heading_deg() const;
  [[nodiscard]] double heading_sigma_deg() const;
  [[nodiscard]] double yaw_rate_bias_dps() const;
  /// The receiver's bias now (constant part + wander), measured - true.
  [[nodiscard]] core::NavPoint gnss_bias_m() const {
    return {x_(kBn) + x_(kWn), x_(kBe) + x_(kWe)};
  }
  [[nodiscard]] double mag_bias_deg() const;
  [[nodiscard]] PositionCovariance position_covariance() const;
  [[nodiscard]] const Vector& state() const { return x_; }
  [[nodiscard]] const Matrix& covariance() const { return P_; }
  [[nodiscard]] core::TimeNs stamp_ns() const { return t_ns_; }

  /// The magnetometer disagrees with course over ground: the mean of their difference over
  /// the recent straight runs exceeds mag_cog_disagree_deg.
  [[nodiscard]] bool mag_disagrees() const { return mag_disagrees_; }
  [[nodiscard]] double mag_cog_mean_deg() const { return mag_cog_mean_deg_; }
  /// Displacement since the first fix from the receiver's velocity alone (trapezoids between
  /// fixes): the start calibration takes each waiting fix back by it.
  [[nodiscard]] core::NavPoint travelled_m() const { return travelled_; }

  struct Counters {
    std::uint32_t fixes_used = 0;
    std::uint32_t fixes_rejected = 0;
    std::uint32_t fixes_forced = 0;
    std::uint32_t mag_rejected = 0;
    std::uint32_t cog_used = 0;
  };
  [[nodiscard]] const Counters& counters() const { return counters_; }

 private:
  template <int M>
  NavUpdate update(const Eigen::Matrix<double, M, 1>& innovation,
                   const Eigen::Matrix<double, M, kStates>& H, const Eigen::Matrix<double, M, M>& R,
                   double gate, bool force);
  void init_position(core::NavPoint fix, double sigma_m, const msg::GnssFix& q);
  void update_cog(const msg::GnssFix& q);
  /// Per-axis sigma of the fix's velocity: its sAcc when it has one, never below the floor.
  [[nodiscard]] double velocity_sigma_mps(const msg::GnssFix& q) const;

  NavFilterParams p_;
  Vector x_;
  Matrix P_;
  core::TimeNs t_ns_ = core::kNeverNs;
  bool has_position_ = false;
  bool has_heading_ = false;
  // Inputs held between IMU samples.
  double rate_rps_ = 0.0;
  double acc_fwd_mps2_ = 0.0;
  double acc_stbd_mps2_ = 0.0;
  bool inertial_ = false;
  // GNSS bookkeeping.
  core::TimeNs last_fix_ns_ = core::kNeverNs;
  core::TimeNs last_cog_ns_ = core::kNeverNs;
  std::uint32_t rejected_run_ = 0;
  std::uint32_t rejected_heading_run_ = 0;
  bool last_vel_valid_ = false;
  core::NavPoint last_vel_;
  core::NavPoint travelled_;
  // Magnetometer / COG comparison.
  double last_mag_deg_ = 0.0;
  bool has_mag_ = false;
  double mag_cog_mean_deg_ = 0.0;
  double mag_cog_weight_ = 0.0;
  bool mag_disagrees_ = false;
  Counters counters_;
};

}  // namespace coxswain::guidance
