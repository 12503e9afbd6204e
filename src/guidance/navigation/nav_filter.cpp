// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/nav_filter.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>

#include "coxswain/core/angles.hpp"

namespace coxswain::guidance {

namespace {

constexpr double kGravityMps2 = 9.80665;
using core::kPi;
// Propagation steps longer than this are split (linearisation of the heading terms).
constexpr double kMaxStepS = 0.1;

double wrap_rad(double a) {
  a = std::remainder(a, 2.0 * kPi);
  return a <= -kPi ? a + 2.0 * kPi : a;
}

bool positive(double v) { return v > 0.0 && std::isfinite(v); }
bool non_negative(double v) { return v >= 0.0 && std::isfinite(v); }

}  // namespace

std::optional<std::string> NavFilterParams::validate() const {
  if (!non_negative(accel_noise_mps2) || !non_negative(heading_walk_deg_per_sqrt_s) ||
      !non_negative(heading_walk_no_gyro_deg_per_sqrt_s) ||
      !non_negative(gyro_bias_walk_dps_per_sqrt_s) || !non_negative(gnss_bias_wander_sigma_m) ||
      !non_negative(mag_bias_walk_deg_per_sqrt_s) || !positive(gnss_bias_tau_s)) {
    return "navigation filter: process noise must be finite and >= 0";
  }
  if (!positive(initial_gnss_bias_sigma_m) || !positive(initial_mag_bias_sigma_deg) ||
      !positive(initial_gyro_bias_sigma_dps) || !positive(initial_velocity_sigma_mps)) {
    return "navigation filter: initial sigmas must be > 0";
  }
  if (!positive(mag_noise_deg) || !positive(gnss_sigma_floor_m) ||
      !positive(gnss_float_sigma_floor_m) || !positive(gnss_fixed_sigma_floor_m) ||
      !positive(gnss_unknown_sigma_m) || !positive(gnss_velocity_sigma_mps)) {
    return "navigation filter: measurement sigmas must be > 0";
  }
  if (!non_negative(cog_min_speed_mps) || !positive(cog_max_yaw_rate_dps) ||
      !positive(cog_crab_sigma_deg) || !non_negative(cog_current_mps) ||
      !non_negative(cog_interval_s) || !positive(mag_cog_disagree_deg) ||
      !positive(mag_cog_window_s)) {
    return "navigation filter: course-over-ground settings out of range";
  }
  if (!positive(gate_chi2_2dof) || !positive(gate_chi2_1dof)) {
    return "navigation filter: chi-square gates must be > 0";
  }
  if (!positive(max_fix_gap_s)) return "navigation filter: max_fix_gap_s must be > 0";
  if (!positive(start_placement_sigma_m) || !positive(uncalibrated_bias_sigma_m)) {
    return "navigation filter: start_placement_sigma_m and uncalibrated_bias_sigma_m must be > 0";
  }
  return std::nullopt;
}

double PositionCovariance::sigma_along_m(double bearing_deg) const {
  const double b = bearing_deg * core::kRadPerDeg;
  const double n = std::cos(b);
  const double e = std::sin(b);
  return std::sqrt(std::max(0.0, n * n * nn_m2 + 2.0 * n * e * ne_m2 + e * e * ee_m2));
}

double PositionCovariance::sigma_toward_m(core::NavPoint from, core::NavPoint to) const {
  const double dn = to.north_m - from.north_m;
  const double de = to.east_m - from.east_m;
  if (std::hypot(dn, de) < 1e-9) return sigma_major_m();
  return sigma_along_m(std::atan2(de, dn) * core::kDegPerRad);
}

void PositionCovariance::axes(double& major_m, double& minor_m, double& major_bearing_deg) const {
  const double mean = 0.5 * (nn_m2 + ee_m2);
  const double half = 0.5 * (nn_m2 - ee_m2);
  const double r = std::sqrt(half * half + ne_m2 * ne_m2);
  major_m = std::sqrt(std::max(0.0, mean + r));
  minor_m = std::sqrt(std::max(0.0, mean - r));
  major_bearing_deg = 0.5 * std::atan2(2.0 * ne_m2, nn_m2 - ee_m2) * core::kDegPerRad;
}

double PositionCovariance::sigma_major_m() const {
  double major = 0.0;
  double minor = 0.0;
  double bearing = 0.0;
  axes(major, minor, bearing);
  return major;
}

double normal_quantile(double p) {
  // Acklam's algorithm: rational approximations in the central region and the tails.
  static constexpr double a[] = {-3.969683028665376e+01, 2.209460984245205e+02,
                                 -2.759285104469687e+02, 1.383577518672690e+02,
                                 -3.066479806614716e+01, 2.506628277459239e+00};
  static constexpr double b[] = {-5.447609879822406e+01, 1.615858368580409e+02,
                                 -1.556989798598866e+02, 6.680131188771972e+01,
                                 -1.328068155288572e+01};
  static constexpr double c[] = {-7.784894002430293e-03, -3.223964580411365e-01,
                                 -2.400758277161838e+00, -2.549732539343734e+00,
                                 4.374664141464968e+00,  2.938163982698783e+00};
  static constexpr double d[] = {7.784695709041462e-03, 3.224671290700398e-01,
                                 2.445134137142996e+00, 3.754408661907416e+00};
  p = std::clamp(p, 1e-12, 1.0 - 1e-12);
  constexpr double kLow = 0.02425;
  if (p < kLow) {
    const double q = std::sqrt(-2.0 * std::log(p));
    return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
           ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
  }
  if (p > 1.0 - kLow) return -normal_quantile(1.0 - p);
  const double q = p - 0.5;
  const double r = q * q;
  return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
         (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
}

bool confidently_within(core::NavPoint point, const PositionCovariance& cov, core::NavPoint centre,
                        double radius_m, double k_sigma) {
  const double d = core::distance_m(point, centre);
  return d + k_sigma * cov.sigma_toward_m(point, centre) <= radius_m;
}

bool confident_crossing(core::NavPoint position, const PositionCovariance& cov, core::NavPoint left,
                        core::NavPoint right, double k_sigma, double max_across_m) {
  const double dn = right.north_m - left.north_m;
  const double de = right.east_m - left.east_m;
  const double length = std::hypot(dn, de);
  if (length < 1e-9) return false;
  const double along_bearing = std::atan2(de, dn) * core::kDegPerRad;
  const double s =
      ((position.north_m - left.north_m) * dn + (position.east_m - left.east_m) * de) / length;
  const double ks_along = k_sigma * cov.sigma_along_m(along_bearing);
  const double ks_across = k_sigma * cov.sigma_along_m(along_bearing + 90.0);
  return s - ks_along >= 0.0 && s + ks_along <= length && ks_across <= max_across_m;
}

NavFilter::NavFilter(NavFilterParams p) : p_(p) { reset(); }

void NavFilter::reset() {
  x_.setZero();
  P_.setZero();
  const double b0 = p_.initial_gnss_bias_sigma_m;
  P_(kBn, kBn) = b0 * b0;
  P_(kBe, kBe) = b0 * b0;
  const double g0 = p_.initial_gyro_bias_sigma_dps * core::kRadPerDeg;
  P_(kBg, kBg) = g0 * g0;
  P_(kWn, kWn) = P_(kWe, kWe) = p_.gnss_bias_wander_sigma_m * p_.gnss_bias_wander_sigma_m;
  const double m0 = p_.initial_mag_bias_sigma_deg * core::kRadPerDeg;
  P_(kBm, kBm) = m0 * m0;
  P_(kPsi, kPsi) = kPi * kPi;
  const double v0 = p_.initial_velocity_sigma_mps;
  P_(kVn, kVn) = v0 * v0;
  P_(kVe, kVe) = v0 * v0;
  // Position unknown until the first fix (set there).
  P_(kPn, kPn) = 1e6;
  P_(kPe, kPe) = 1e6;
  t_ns_ = core::kNeverNs;
  has_position_ = false;
  has_heading_ = false;
  rate_rps_ = 0.0;
  acc_fwd_mps2_ = 0.0;
  acc_stbd_mps2_ = 0.0;
  inertial_ = false;
  last_fix_ns_ = core::kNeverNs;
  last_cog_ns_ = core::kNeverNs;
  rejected_run_ = 0;
  rejected_heading_run_ = 0;
  last_vel_valid_ = false;
  last_vel_ = {};
  travelled_ = {};
  has_mag_ = false;
  mag_cog_mean_deg_ = 0.0;
  mag_cog_weight_ = 0.0;
  mag_disagrees_ = false;
  counters_ = {};
}

double NavFilter::heading_deg() const { return core::wrap_deg(x_(kPsi) * core::kDegPerRad); }
double NavFilter::heading_sigma_deg() const { return std::sqrt(P_(kPsi, kPsi)) * core::kDegPerRad; }
double NavFilter::yaw_rate_bias_dps() const { return x_(kBg) * core::kDegPerRad; }
double NavFilter::mag_bias_deg() const { return x_(kBm) * core::kDegPerRad; }

PositionCovariance NavFilter::position_covariance() const {
  return {P_(kPn, kPn), 0.5 * (P_(kPn, kPe) + P_(kPe, kPn)), P_(kPe, kPe)};
}

void NavFilter::predict_to(core::TimeNs now_ns) {
  if (t_ns_ == core::kNeverNs) {
    t_ns_ = now_ns;
    return;
  }
  if (now_ns <= t_ns_) return;
  double remaining = core::ns_to_sec(now_ns - t_ns_);
  t_ns_ = now_ns;
  const double qa = p_.accel_noise_mps2 * p_.accel_noise_mps2;
  const double qpsi = std::pow(
      (inertial_ ? p_.heading_walk_deg_per_sqrt_s : p_.heading_walk_no_gyro_deg_per_sqrt_s) *
          core::kRadPerDeg,
      2);
  const double qbg = std::pow(p_.gyro_bias_walk_dps_per_sqrt_s * core::kRadPerDeg, 2);
  const double sw2 = p_.gnss_bias_wander_sigma_m * p_.gnss_bias_wander_sigma_m;
  const double qbm = std::pow(p_.mag_bias_walk_deg_per_sqrt_s * core::kRadPerDeg, 2);
  // A very long gap is one step: the covariance growth is what matters then.
  const int max_steps = 100;
  for (int step = 0; step < max_steps && remaining > 0.0; ++step) {
    const double dt = step + 1 == max_steps ? remaining : std::min(remaining, kMaxStepS);
    remaining -= dt;
    const double psi = x_(kPsi);
    const double c = std::cos(psi);
    const double s = std::sin(psi);
    const bool use_acc = inertial_ && has_heading_;
    const double an = use_acc ? c * acc_fwd_mps2_ - s * acc_stbd_mps2_ : 0.0;
    const double ae = use_acc ? s * acc_fwd_mps2_ + c * acc_stbd_mps2_ : 0.0;

    Matrix F = Matrix::Identity();
    F(kPn, kVn) = dt;
    F(kPe, kVe) = dt;
    if (use_acc) {
      F(kVn, kPsi) = -ae * dt;
      F(kVe, kPsi) = an * dt;
      F(kPn, kPsi) = -0.5 * ae * dt * dt;
      F(kPe, kPsi) = 0.5 * an * dt * dt;
    }
    if (inertial_) F(kPsi, kBg) = -dt;
    const double phi = std::exp(-dt / p_.gnss_bias_tau_s);
    F(kWn, kWn) = F(kWe, kWe) = phi;

    x_(kPn) += x_(kVn) * dt + 0.5 * an * dt * dt;
    x_(kPe) += x_(kVe) * dt + 0.5 * ae * dt * dt;
    x_(kVn) += an * dt;
    x_(kVe) += ae * dt;
    if (inertial_) x_(kPsi) = wrap_rad(x_(kPsi) + (rate_rps_ - x_(kBg)) * dt);
    x_(kWn) *= phi;
    x_(kWe) *= phi;

    Matrix Q = Matrix::Zero();
    Q(kPn, kPn) = Q(kPe, kPe) = qa * dt * dt * dt / 3.0;
    Q(kPn, kVn) = Q(kVn, kPn) = Q(kPe, kVe) = Q(kVe, kPe) = qa * dt * dt / 2.0;
    Q(kVn, kVn) = Q(kVe, kVe) = qa * dt;
    Q(kPsi, kPsi) = qpsi * dt;
    Q(kBg, kBg) = qbg * dt;
    Q(kWn, kWn) = Q(kWe, kWe) = sw2 * (1.0 - phi * phi);
    Q(kBm, kBm) = qbm * dt;
    // Coefficient-wise products: Eigen's blocked GEMM, which it picks for an 11 x 11 product,
    // spends more on packing than on arithmetic at this size.
    const Matrix FP = F.lazyProduct(P_);
    P_ = FP.lazyProduct(F.transpose()) + Q;
  }
  P_ = 0.5 * (P_ + P_.transpose()).eval();
}

template <int M>
NavUpdate NavFilter::update(const Eigen::Matrix<double, M, 1>& innovation,
                            const Eigen::Matrix<double, M, kStates>& H,
                            const Eigen::Matrix<double, M, M>& R, double gate, bool force) {
  const Eigen::Matrix<double, M, kStates> HP = H.lazyProduct(P_);
  const Eigen::Matrix<double, M, M> S = HP.lazyProduct(H.transpose()) + R;
  const Eigen::Matrix<double, M, M> S_inv = S.inverse();
  const double d2 = innovation.dot(S_inv * innovation);
  if (!std::isfinite(d2)) return NavUpdate::kSkipped;
  if (!force && d2 > gate) return NavUpdate::kRejected;
  const Eigen::Matrix<double, kStates, M> K = HP.transpose().lazyProduct(S_inv);
  x_ += K * innovation;
  x_(kPsi) = wrap_rad(x_(kPsi));
  x_(kBm) = wrap_rad(x_(kBm));
  // Joseph form: stays symmetric positive semi-definite with gated, rounded updates.
  const Matrix I_KH = Matrix::Identity() - K.lazyProduct(H);
  const Matrix IP = I_KH.lazyProduct(P_);
  const Eigen::Matrix<double, kStates, M> KR = K.lazyProduct(R);
  P_ = IP.lazyProduct(I_KH.transpose()) + KR.lazyProduct(K.transpose());
  P_ = 0.5 * (P_ + P_.transpose()).eval();
  return force ? NavUpdate::kForced : NavUpdate::kUsed;
}

void NavFilter::add_imu(core::TimeNs stamp_ns, double heading_deg, bool inertial,
                        double yaw_rate_dps, double accel_fwd_g, double accel_stbd_g,
                        double roll_deg, double pitch_deg) {
  predict_to(stamp_ns);
  inertial_ = inertial && std::isfinite(yaw_rate_dps) && std::isfinite(accel_fwd_g) &&
              std::isfinite(accel_stbd_g) && std::isfinite(roll_deg) && std::isfinite(pitch_deg);
  if (inertial_) {
    rate_rps_ = yaw_rate_dps * core::kRadPerDeg;
    // Specific force = acceleration - gravity: at rest x reads sin(pitch), y -sin(roll)cos(pitch).
    const double roll = roll_deg * core::kRadPerDeg;
    const double pitch = pitch_deg * core::kRadPerDeg;
    acc_fwd_mps2_ = kGravityMps2 * (accel_fwd_g - std::sin(pitch));
    acc_stbd_mps2_ = kGravityMps2 * (accel_stbd_g + std::sin(roll) * std::cos(pitch));
  } else {
    rate_rps_ = 0.0;
    acc_fwd_mps2_ = 0.0;
    acc_stbd_mps2_ = 0.0;
  }
  if (!std::isfinite(heading_deg)) return;
  last_mag_deg_ = heading_deg;
  has_mag_ = true;
  const double z = heading_deg * core::kRadPerDeg;
  const double r = p_.mag_noise_deg * core::kRadPerDeg;
  if (!has_heading_) {
    // heading = z - magnetometer bias: the bias's prior spreads into the heading.
    x_(kPsi) = wrap_rad(z - x_(kBm));
    for (int j = 0; j < kStates; ++j) {
      P_(kPsi, j) = P_(j, kPsi) = -P_(kBm, j);
    }
    P_(kPsi, kPsi) = r * r + P_(kBm, kBm);
    has_heading_ = true;
    return;
  }
  Eigen::Matrix<double, 1, kStates> H = Eigen::Matrix<double, 1, kStates>::Zero();
  H(0, kPsi) = 1.0;
  H(0, kBm) = 1.0;
  Eigen::Matrix<double, 1, 1> y;
  y(0) = wrap_rad(z - x_(kPsi) - x_(kBm));
  Eigen::Matrix<double, 1, 1> R;
  R(0, 0) = r * r;
  if (update<1>(y, H, R, p_.gate_chi2_1dof, false) == NavUpdate::kRejected) {
    ++counters_.mag_rejected;
    if (++rejected_heading_run_ > p_.max_rejected_headings) {
      // A second of refused headings: the estimate is lost (a wrong gyro sign or a jump in the
      // field): open the heading's variance by the innovation and take it.
      P_(kPsi, kPsi) += y(0) * y(0);
      (void)update<1>(y, H, R, p_.gate_chi2_1dof, true);
      rejected_heading_run_ = 0;
    }
  } else {
    rejected_heading_run_ = 0;
  }
}

void NavFilter::init_position(core::NavPoint fix, double sigma_m, const msg::GnssFix& q) {
  // position = fix - bias (constant + wander): the bias's uncertainty and correlations carry
  // into the position.
  x_(kPn) = fix.north_m - x_(kBn) - x_(kWn);
  x_(kPe) = fix.east_m - x_(kBe) - x_(kWe);
  for (int j = 0; j < kStates; ++j) {
    P_(kPn, j) = P_(j, kPn) = -(P_(kBn, j) + P_(kWn, j));
    P_(kPe, j) = P_(j, kPe) = -(P_(kBe, j) + P_(kWe, j));
    P_(kVn, j) = P_(j, kVn) = 0.0;
    P_(kVe, j) = P_(j, kVe) = 0.0;
  }
  const auto bias_cov = [this](int a, int wa, int b, int wb) {
    return P_(a, b) + P_(a, wb) + P_(wa, b) + P_(wa, wb);
  };
  P_(kPn, kPn) = sigma_m * sigma_m + bias_cov(kBn, kWn, kBn, kWn);
  P_(kPe, kPe) = sigma_m * sigma_m + bias_cov(kBe, kWe, kBe, kWe);
  P_(kPn, kPe) = P_(kPe, kPn) = bias_cov(kBn, kWn, kBe, kWe);
  if (q.velocity_valid) {
    x_(kVn) = q.vel_north_mps;
    x_(kVe) = q.vel_east_mps;
    const double sv = velocity_sigma_mps(q);
    P_(kVn, kVn) = P_(kVe, kVe) = sv * sv;
  } else {
    x_(kVn) = x_(kVe) = 0.0;
    P_(kVn, kVn) = P_(kVe, kVe) = p_.initial_velocity_sigma_mps * p_.initial_velocity_sigma_mps;
  }
  has_position_ = true;
  rejected_run_ = 0;
}

double NavFilter::velocity_sigma_mps(const msg::GnssFix& q) const {
  // sAcc is the receiver's speed accuracy; per axis it is taken as hAcc is, over sqrt(2).
  if (q.s_acc_mps > 0.0 && std::isfinite(q.s_acc_mps)) {
    return std::max(q.s_acc_mps / std::sqrt(2.0), p_.gnss_velocity_sigma_mps);
  }
  return p_.gnss_velocity_sigma_mps;
}

NavUpdate NavFilter::add_fix(core::TimeNs stamp_ns, core::NavPoint fix,
                             const msg::GnssFix& quality) {
  if (!quality.usable() || !std::isfinite(fix.north_m) || !std::isfinite(fix.east_m)) {
    return NavUpdate::kSkipped;
  }
  predict_to(stamp_ns);
  double floor_m = p_.gnss_sigma_floor_m;
  if (quality.rtk == msg::RtkSolution::kFixed) floor_m = p_.gnss_fixed_sigma_floor_m;
  if (quality.rtk == msg::RtkSolution::kFloat) floor_m = p_.gnss_float_sigma_floor_m;
  const double sigma_m = quality.h_acc_m > 0.0 && std::isfinite(quality.h_acc_m)
                             ? std::max(quality.h_acc_m / std::sqrt(2.0), floor_m)
                             : std::max(p_.gnss_unknown_sigma_m, floor_m);
  const double gap_s =
      last_fix_ns_ == core::kNeverNs ? 0.0 : core::ns_to_sec(stamp_ns - last_fix_ns_);
  const bool vel = quality.velocity_valid && std::isfinite(quality.vel_north_mps) &&
                   std::isfinite(quality.vel_east_mps);
  if (last_vel_valid_ && vel && gap_s > 0.0 && gap_s <= p_.max_fix_gap_s) {
    travelled_.north_m += 0.5 * (last_vel_.north_m + quality.vel_north_mps) * gap_s;
    travelled_.east_m += 0.5 * (last_vel_.east_m + quality.vel_east_mps) * gap_s;
  }
  last_vel_valid_ = vel;
  last_vel_ = {quality.vel_north_mps, quality.vel_east_mps};
  last_fix_ns_ = stamp_ns;
  if (!has_position_ || gap_s > p_.max_fix_gap_s) {
    init_position(fix, sigma_m, quality);
    ++counters_.fixes_used;
    return NavUpdate::kUsed;
  }

  Eigen::Matrix<double, 2, kStates> H = Eigen::Matrix<double, 2, kStates>::Zero();
  H(0, kPn) = H(0, kBn) = H(0, kWn) = 1.0;
  H(1, kPe) = H(1, kBe) = H(1, kWe) = 1.0;
  Eigen::Vector2d y(fix.north_m - x_(kPn) - x_(kBn) - x_(kWn),
                    fix.east_m - x_(kPe) - x_(kBe) - x_(kWe));
  const Eigen::Matrix2d R = Eigen::Matrix2d::Identity() * sigma_m * sigma_m;
  NavUpdate result = update<2>(y, H, R, p_.gate_chi2_2dof, false);
  if (result == NavUpdate::kRejected) {
    ++counters_.fixes_rejected;
    if (++rejected_run_ > p_.max_rejected_fixes) {
      // The receiver insists: the jump is real (or the filter is lost). Open the position
      // covariance by the innovation and take the fix.
      P_(kPn, kPn) += y(0) * y(0);
      P_(kPe, kPe) += y(1) * y(1);
      P_(kPn, kPe) += y(0) * y(1);
      P_(kPe, kPn) += y(0) * y(1);
      result = update<2>(y, H, R, p_.gate_chi2_2dof, true);
      ++counters_.fixes_forced;
      rejected_run_ = 0;
    }
  } else if (result == NavUpdate::kUsed) {
    ++counters_.fixes_used;
    rejected_run_ = 0;
  }
  if (result == NavUpdate::kRejected) return result;

  if (vel) {
    Eigen::Matrix<double, 2, kStates> Hv = Eigen::Matrix<double, 2, kStates>::Zero();
    Hv(0, kVn) = 1.0;
    Hv(1, kVe) = 1.0;
    const Eigen::Vector2d yv(quality.vel_north_mps - x_(kVn), quality.vel_east_mps - x_(kVe));
    const double sv = velocity_sigma_mps(quality);
    (void)update<2>(yv, Hv, Eigen::Matrix2d::Identity() * sv * sv, p_.gate_chi2_2dof, false);
    update_cog(quality);
  }
  return result;
}

void NavFilter::update_cog(const msg::GnssFix& q) {
  if (!has_heading_ || !inertial_) return;
  const double speed = std::hypot(q.vel_north_mps, q.vel_east_mps);
  if (speed < p_.cog_min_speed_mps || speed <= 0.0) return;
  if (std::abs(rate_rps_ - x_(kBg)) > p_.cog_max_yaw_rate_dps * core::kRadPerDeg) return;
  if (last_cog_ns_ != core::kNeverNs &&
      core::ns_to_sec(last_fix_ns_ - last_cog_ns_) < p_.cog_interval_s) {
    return;
  }
  const double dt_s =
      last_cog_ns_ == core::kNeverNs ? 0.0 : core::ns_to_sec(last_fix_ns_ - last_cog_ns_);
  last_cog_ns_ = last_fix_ns_;
  const double cog = std::atan2(q.vel_east_mps, q.vel_north_mps);
  if (has_mag_) {
    // A slow mean of COG - magnetometer over the straight runs: a steady difference well past
    // the crab of the current is a magnetometer problem (calibration, a nearby field).
    const double d = core::wrap_deg(cog * core::kDegPerRad - last_mag_deg_);
    const double alpha = std::clamp(dt_s / p_.mag_cog_window_s, 0.0, 1.0);
    mag_cog_mean_deg_ =
        mag_cog_weight_ == 0.0
            ? d
            : core::wrap_deg(mag_cog_mean_deg_ + alpha * core::wrap_deg(d - mag_cog_mean_deg_));
    mag_cog_weight_ = std::min(1.0, mag_cog_weight_ + alpha);
    mag_disagrees_ =
        mag_cog_weight_ >= 0.5 && std::abs(mag_cog_mean_deg_) > p_.mag_cog_disagree_deg;
  }
  if (!p_.cog_heading_update) return;
  Eigen::Matrix<double, 1, kStates> H = Eigen::Matrix<double, 1, kStates>::Zero();
  H(0, kPsi) = 1.0;
  Eigen::Matrix<double, 1, 1> y;
  y(0) = wrap_rad(cog - x_(kPsi));
  const double sv = velocity_sigma_mps(q) / speed;
  // A water current crabs the boat: its course differs from its heading by up to
  // atan(current / speed), most at low speed (a docking approach).
  const double crab =
      std::hypot(p_.cog_crab_sigma_deg * core::kRadPerDeg, std::atan2(p_.cog_current_mps, speed));
  Eigen::Matrix<double, 1, 1> R;
  R(0, 0) = sv * sv + crab * crab;
  if (update<1>(y, H, R, p_.gate_chi2_1dof, false) == NavUpdate::kUsed) ++counters_.cog_used;
}

NavUpdate NavFilter::add_bias_measurement(core::NavPoint bias_m, double sigma_m) {
  if (!std::isfinite(bias_m.north_m) || !std::isfinite(bias_m.east_m) || !(sigma_m > 0.0)) {
    return NavUpdate::kSkipped;
  }
  Eigen::Matrix<double, 2, kStates> H = Eigen::Matrix<double, 2, kStates>::Zero();
  H(0, kBn) = H(0, kWn) = 1.0;
  H(1, kBe) = H(1, kWe) = 1.0;
  const Eigen::Vector2d y(bias_m.north_m - x_(kBn) - x_(kWn), bias_m.east_m - x_(kBe) - x_(kWe));
  // Not gated: the calibration is the reference the bias is defined by.
  const NavUpdate r =
      update<2>(y, H, Eigen::Matrix2d::Identity() * sigma_m * sigma_m, p_.gate_chi2_2dof, true);
  return r == NavUpdate::kForced ? NavUpdate::kUsed : r;
}

}  // namespace coxswain::guidance
