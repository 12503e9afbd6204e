// SPDX-License-Identifier: Apache-2.0
#include "sim/sensors/gnss_sim.hpp"

#include <algorithm>
#include <cmath>

#include "coxswain/core/angles.hpp"

namespace coxswain::sim::sensors {

namespace {
constexpr std::int64_t kGpsEpochUnixS = 315'964'800;  // 1980-01-06
constexpr std::int64_t kGpsLeapS = 18;                // GPS - UTC since 2017
constexpr std::int64_t kWeekMs = 604'800'000;
}  // namespace

std::optional<std::string> GnssSimConfig::validate() const {
  if (!(rate_hz >= 0.1 && rate_hz <= 25.0)) return "gnss rate_hz must be in [0.1, 25]";
  if (!std::isfinite(mount.x_m) || !std::isfinite(mount.y_m)) return "gnss mount must be finite";
  if (!(antenna_height_m >= 0.0 && antenna_height_m <= 10.0)) {
    return "gnss antenna_height_m in [0, 10]";
  }
  if (!(bias_max_m >= 0.0 && bias_max_m <= 50.0)) return "gnss bias_max_m in [0, 50]";
  if (!(bias_mean_m >= 0.0 && bias_mean_m <= bias_max_m)) {
    return "gnss bias_mean_m must be in [0, bias_max_m]";
  }
  if (!std::isfinite(bias_direction_deg)) return "gnss bias_direction_deg must be finite";
  if (!(bias_wander_sigma_m >= 0.0 && bias_wander_sigma_m <= 20.0)) {
    return "gnss bias_wander_sigma_m in [0, 20]";
  }
  if (!(bias_tau_s >= 1.0 && bias_tau_s <= 1e5)) return "gnss bias_tau_s in [1, 1e5]";
  if (!(noise_sigma_m >= 0.0 && noise_sigma_m <= 20.0)) return "gnss noise_sigma_m in [0, 20]";
  if (!(height_noise_sigma_m >= 0.0 && height_noise_sigma_m <= 50.0)) {
    return "gnss height_noise_sigma_m in [0, 50]";
  }
  if (!(velocity_noise_mps >= 0.0 && velocity_noise_mps <= 5.0)) {
    return "gnss velocity_noise_mps in [0, 5]";
  }
  if (!(outage_rate_per_min >= 0.0 && outage_rate_per_min <= 60.0)) {
    return "gnss outage_rate_per_min in [0, 60]";
  }
  if (!(outage_mean_s > 0.0 && outage_mean_s <= 600.0)) return "gnss outage_mean_s in (0, 600]";
  if (!(rtk_fixed_sigma_m >= 0.0 && rtk_fixed_sigma_m <= 0.5)) {
    return "gnss rtk_fixed_sigma_m in [0, 0.5]";
  }
  if (!(rtk_float_sigma_m >= 0.0 && rtk_float_sigma_m <= 5.0)) {
    return "gnss rtk_float_sigma_m in [0, 5]";
  }
  if (!(rtk_float_bias_m >= 0.0 && rtk_float_bias_m <= 5.0)) {
    return "gnss rtk_float_bias_m in [0, 5]";
  }
  if (!(rtk_fix_delay_s >= 0.0 && rtk_fix_delay_s <= 600.0)) {
    return "gnss rtk_fix_delay_s in [0, 600]";
  }
  if (satellites < 4 || satellites > 64) return "gnss satellites in [4, 64]";
  if (!(hdop > 0.0 && hdop <= 50.0)) return "gnss hdop in (0, 50]";
  return {};
}

GnssSim::GnssSim(const GnssSimConfig& config, const core::GeoPoint& origin)
    : config_(config),
      frame_(origin),
      rng_(config.seed),
      period_ns_(static_cast<core::TimeNs>(std::llround(1e9 / config.rate_hz))) {
  // Start the wander in its stationary distribution so the bias does not first settle.
  wander_n_ = rng_.normal(config_.bias_wander_sigma_m);
  wander_e_ = rng_.normal(config_.bias_wander_sigma_m);
  step_bias(0.0);
  if (config_.outage_rate_per_min > 0.0) {
    next_outage_ns_ = core::sec_to_ns(rng_.exponential(60.0 / config_.outage_rate_per_min));
  }
  rtk_fixed_from_ns_ = core::sec_to_ns(config_.rtk_fix_delay_s);
}

void GnssSim::step_bias(double dt_s) {
  if (dt_s > 0.0) {
    // Exact discretisation of the Gauss-Markov process: stays stationary at any step.
    const double phi = std::exp(-dt_s / config_.bias_tau_s);
    const double q = config_.bias_wander_sigma_m * std::sqrt(1.0 - phi * phi);
    wander_n_ = phi * wander_n_ + rng_.normal(q);
    wander_e_ = phi * wander_e_ + rng_.normal(q);
  }
  const double dir = core::deg_to_rad(config_.bias_direction_deg);
  double n = config_.bias_mean_m * std::cos(dir) + wander_n_;
  double e = config_.bias_mean_m * std::sin(dir) + wander_e_;
  const double mag = std::hypot(n, e);
  if (mag > config_.bias_max_m && mag > 0.0) {
    n *= config_.bias_max_m / mag;
    e *= config_.bias_max_m / mag;
  }
  bias_n_ = n;
  bias_e_ = e;
}

bool GnssSim::update(core::TimeNs now_ns, const BoatTruth& truth) {
  const core::TimeNs epoch_ns = now_ns >= 0
                                    ? (now_ns / period_ns_) * period_ns_
                                    : -((-now_ns + period_ns_ - 1) / period_ns_) * period_ns_;
  if (last_epoch_ns_ != core::kNeverNs && epoch_ns <= last_epoch_ns_) return false;
  const double dt_s =
      last_epoch_ns_ == core::kNeverNs ? 0.0 : core::ns_to_sec(epoch_ns - last_epoch_ns_);
  last_epoch_ns_ = epoch_ns;
  step_bias(dt_s);

  // Outages: start when due, last an exponential time; RTK restarts from float afterwards.
  if (next_outage_ns_ != core::kNeverNs && epoch_ns >= next_outage_ns_) {
    outage_until_ns_ = epoch_ns + core::sec_to_ns(rng_.exponential(config_.outage_mean_s));
    next_outage_ns_ =
        outage_until_ns_ + core::sec_to_ns(rng_.exponential(60.0 / config_.outage_rate_per_min));
    rtk_fixed_from_ns_ = outage_until_ns_ + core::sec_to_ns(config_.rtk_fix_delay_s);
  }
  const bool outage = outage_until_ns_ != core::kNeverNs && epoch_ns < outage_until_ns_;

  msg::GnssFix f;
  f.stamp_ns = now_ns;
  f.source = msg::GnssSource::kUbxNavPvt;
  const std::int64_t utc_ns = config_.utc_at_zero_ns + epoch_ns;
  f.utc_ns = utc_ns;
  const std::int64_t gps_ms = (utc_ns / core::kNsPerMs) - kGpsEpochUnixS * 1000 + kGpsLeapS * 1000;
  f.itow_ms = static_cast<std::uint32_t>(((gps_ms % kWeekMs) + kWeekMs) % kWeekMs);

  if (outage) {
    // The receiver keeps reporting epochs without a solution (NAV-PVT fixType 0, no gnssFixOK),
    // repeating its last position as u-blox does.
    f.fix_type = msg::FixType::kNoFix;
    f.fix_ok = false;
    f.lat_deg = fix_.lat_deg;
    f.lon_deg = fix_.lon_deg;
    f.height_msl_m = fix_.height_msl_m;
    f.h_acc_m = 50.0 + rng_.uniform(0.0, 10.0);
    f.v_acc_m = 2.0 * f.h_acc_m;
    f.hdop = 99.99;
    f.satellites = static_cast<std::uint8_t>(rng_.uniform(0.0, 3.99));
    f.velocity_valid = false;
    fix_ = f;
    return true;
  }

  msg::RtkSolution rtk = msg::RtkSolution::kNone;
  double sigma = config_.noise_sigma_m;
  double bias_n = bias_n_;
  double bias_e = bias_e_;
  if (config_.rtk != RtkMode::kOff) {
    const bool fixed = config_.rtk == RtkMode::kFixed && epoch_ns >= rtk_fixed_from_ns_;
    rtk = fixed ? msg::RtkSolution::kFixed : msg::RtkSolution::kFloat;
    sigma = fixed ? config_.rtk_fixed_sigma_m : config_.rtk_float_sigma_m;
    // Corrections remove the slowly varying error; a float solution keeps a little of it.
    const double keep =
        fixed
            ? 0.0
            : std::min(1.0, config_.rtk_float_bias_m / std::max(1e-9, std::hypot(bias_n, bias_e)));
    bias_n *= keep;
    bias_e *= keep;
  }
  const core::NavPoint antenna =
      core::body_to_nav(truth.pose, {config_.mount.x_m, config_.mount.y_m});
  const core::NavPoint measured{antenna.north_m + bias_n + rng_.normal(sigma),
                                antenna.east_m + bias_e + rng_.normal(sigma)};
  const double v_sigma =
      rtk == msg::RtkSolution::kNone ? config_.height_noise_sigma_m : 2.0 * sigma;
  const core::GeoPoint geo =
      frame_.to_geo(measured, config_.antenna_height_m + rng_.normal(v_sigma));
  f.fix_type = msg::FixType::k3D;
  f.fix_ok = true;
  f.diff_soln = rtk != msg::RtkSolution::kNone;
  f.rtk = rtk;
  f.lat_deg = geo.lat_deg;
  f.lon_deg = geo.lon_deg;
  f.height_msl_m = geo.height_m;
  // hAcc: the receiver's 1-sigma horizontal estimate; it knows its noise, not the bias.
  f.h_acc_m = std::max(0.001, std::sqrt(2.0) * sigma);
  f.v_acc_m = std::max(0.001, 1.5 * v_sigma);
  f.hdop = config_.hdop;
  const int sats = config_.satellites + static_cast<int>(std::lround(rng_.normal(1.0)));
  f.satellites = static_cast<std::uint8_t>(std::clamp(sats, 4, 64));

  // Velocity of the antenna: the boat's plus the lever arm's swing as it turns.
  const double r = core::deg_to_rad(truth.yaw_rate_dps);
  const double psi = core::deg_to_rad(truth.pose.heading_deg);
  const double lx = config_.mount.x_m;
  const double ly = config_.mount.y_m;
  const double vx_body = -r * ly;  // omega x lever arm, z down
  const double vy_body = r * lx;
  const double vn = truth.vel_north_mps + vx_body * std::cos(psi) - vy_body * std::sin(psi) +
                    rng_.normal(config_.velocity_noise_mps);
  const double ve = truth.vel_east_mps + vx_body * std::sin(psi) + vy_body * std::cos(psi) +
                    rng_.normal(config_.velocity_noise_mps);
  f.velocity_valid = true;
  f.s_acc_mps = std::max(0.001, std::sqrt(2.0) * config_.velocity_noise_mps);  // as hAcc
  f.vel_north_mps = vn;
  f.vel_east_mps = ve;
  f.vel_down_mps = rng_.normal(config_.velocity_noise_mps);
  f.ground_speed_mps = std::hypot(vn, ve);
  f.course_deg = core::wrap_deg(core::rad_to_deg(std::atan2(ve, vn)));
  fix_ = f;
  return true;
}

}  // namespace coxswain::sim::sensors
