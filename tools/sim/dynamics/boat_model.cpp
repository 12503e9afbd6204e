// SPDX-License-Identifier: Apache-2.0
#include "sim/dynamics/boat_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "coxswain/core/angles.hpp"

namespace coxswain::sim::dynamics {
namespace {

constexpr double kRhoAir = 1.225;
constexpr double kWindDragCoefficient = 1.0;  // bluff above-water body; our choice
// Moment arm of the wave-like yaw moment (our choice: waves turn a small hull a little).
constexpr double kWaveYawArmM = 0.15;

}  // namespace

double thrust_from_pulse(const config::ThrusterConfig& esc, std::uint16_t pulse_us,
                         double max_fwd_n, double max_rev_n) {
  const int p = pulse_us;
  if (p > esc.forward_start_us) {
    const double span = static_cast<double>(esc.max_us - esc.forward_start_us);
    const double s = std::min(1.0, static_cast<double>(p - esc.forward_start_us) / span);
    return max_fwd_n * s * s;
  }
  if (p < esc.reverse_start_us && esc.reverse_allowed && esc.reverse_start_us > esc.min_us) {
    const double span = static_cast<double>(esc.reverse_start_us - esc.min_us);
    const double s = std::min(1.0, static_cast<double>(esc.reverse_start_us - p) / span);
    return -max_rev_n * s * s;
  }
  return 0.0;
}

double servo_target_deg(const config::ServoConfig& servo, std::uint16_t pulse_us) {
  const double offset = static_cast<double>(pulse_us) - static_cast<double>(servo.center_us);
  const double half_span = offset >= 0.0 ? static_cast<double>(servo.max_us - servo.center_us)
                                         : static_cast<double>(servo.center_us - servo.min_us);
  const double fraction = std::clamp(offset / half_span, -1.0, 1.0);
  const double deg = fraction * servo.max_deflection_deg;
  return servo.reversed ? -deg : deg;
}

void ServoModel::command(std::uint16_t pulse_us) {
  if (target_pulse_us_ == 0) target_pulse_us_ = config_.center_us;
  const int diff = static_cast<int>(pulse_us) - static_cast<int>(target_pulse_us_);
  if (std::abs(diff) <= static_cast<int>(config_.deadband_us)) return;
  target_pulse_us_ = pulse_us;
  target_deg_ = servo_target_deg(config_, pulse_us);
}

void ServoModel::step(double dt_s) {
  const double max_move = config_.rate_deg_per_s * dt_s;
  angle_deg_ += std::clamp(target_deg_ - angle_deg_, -max_move, max_move);
}

Disturbances::Disturbances(const Environment& env, std::uint64_t seed) : env_(env), rng_(seed) {
  const double toward = core::deg_to_rad(env.current_toward_deg);
  current_north_ = env.current_speed_mps * std::cos(toward);
  current_east_ = env.current_speed_mps * std::sin(toward);
  Rng waves = rng_.split();
  for (double& phase : wave_phase_) phase = waves.uniform(0.0, 2.0 * std::numbers::pi);
  // Three frequencies around the dominant one, fixed ratios (a crude spectrum).
  const double w0 = 2.0 * std::numbers::pi / env.wave_period_s;
  wave_freq_ = {0.8 * w0, 1.0 * w0, 1.3 * w0};
  if (env.gust_std_mps > 0.0) gust_mps_ = env.gust_std_mps * rng_.normal();
}

void Disturbances::step(double dt_s) {
  if (env_.gust_std_mps <= 0.0) return;
  // First-order Gauss-Markov: stationary standard deviation gust_std, correlation time gust_time.
  const double a = std::exp(-dt_s / env_.gust_time_s);
  gust_mps_ = a * gust_mps_ + env_.gust_std_mps * std::sqrt(1.0 - a * a) * rng_.normal();
}

std::array<double, 2> Disturbances::wind_ne_mps() const {
  const double speed = std::max(0.0, env_.wind_speed_mps + gust_mps_);
  const double toward = core::deg_to_rad(env_.wind_from_deg + 180.0);
  return {speed * std::cos(toward), speed * std::sin(toward)};
}

Tau Disturbances::wave_tau(double t_s) const {
  if (env_.wave_force_n <= 0.0) return {};
  std::array<double, 3> axis{};
  for (std::size_t a = 0; a < 3; ++a) {
    for (std::size_t k = 0; k < 3; ++k) {
      axis[a] += std::sin(wave_freq_[k] * t_s + wave_phase_[a * 3 + k]);
    }
  }
  const double amp = env_.wave_force_n / 3.0;
  return {amp * axis[0], amp * axis[1], amp * kWaveYawArmM * axis[2]};
}

BoatModel::BoatModel(const config::BoatConfig& boat, const DynamicsParams& params,
                     const Environment& env, std::uint64_t seed, double dt_s)
    : boat_(boat),
      params_(params),
      disturbances_(env, seed),
      servo_(boat.actuators.servo),
      dt_s_(dt_s),
      dt_ns_(core::sec_to_ns(dt_s)),
      cg_aft_m_(0.5 * boat.hull.length_m - boat.hull.bow_overhang_m),
      thruster_x_m_(-0.5 * boat.hull.length_m) {
  pulses_ = {boat.actuators.layout == msg::ActuatorLayout::kServoThruster
                 ? boat.actuators.servo.center_us
                 : boat.actuators.thruster.neutral_us,
             boat.actuators.thruster.neutral_us};
  reset({});
}

void BoatModel::reset(const core::NavPose& pose) {
  const double psi = core::deg_to_rad(core::wrap_deg(pose.heading_deg));
  state_ = {};
  state_.psi_rad = psi;
  state_.north_m = pose.position.north_m - cg_aft_m_ * std::cos(psi);
  state_.east_m = pose.position.east_m - cg_aft_m_ * std::sin(psi);
  // At rest over ground = moving against the current relative to the water.
  const double cn = disturbances_.current_north_mps();
  const double ce = disturbances_.current_east_mps();
  state_.u_r_mps = -(std::cos(psi) * cn + std::sin(psi) * ce);
  state_.v_r_mps = -(-std::sin(psi) * cn + std::cos(psi) * ce);
  thrust_n_ = {};
  accel_body_ = {};
}

void BoatModel::set_pulses(const std::array<std::uint16_t, 2>& pulse_us) {
  pulses_ = pulse_us;
  if (boat_.actuators.layout == msg::ActuatorLayout::kServoThruster) servo_.command(pulse_us[0]);
}

Tau BoatModel::actuator_tau(const std::array<double, 2>& thrust_n, double servo_deg) const {
  Tau tau;
  if (boat_.actuators.layout == msg::ActuatorLayout::kServoThruster) {
    // The thruster turns with the servo; positive deflection pushes the stern to port, so the
    // bow swings to starboard.
    const double d = core::deg_to_rad(servo_deg);
    const double t = thrust_n[1];
    tau.x_n = t * std::cos(d);
    tau.y_n = -t * std::sin(d);
    tau.n_nm = thruster_x_m_ * tau.y_n;
  } else {
    // Port thruster at y = -w/2, starboard at +w/2, both at the stern, pushing along x.
    const double half = 0.5 * boat_.actuators.twin_track_width_m;
    tau.x_n = thrust_n[0] + thrust_n[1];
    tau.n_nm = half * (thrust_n[0] - thrust_n[1]);
  }
  return tau;
}

Tau BoatModel::environment_tau(const Vec6& x) const {
  // In still air the hull's air drag is under 1 % of its water drag: left out, which keeps the
  // calm-weather model exactly the hand-computable one.
  if (!disturbances_.has_wind()) return {};
  const double c = std::cos(x[2]);
  const double s = std::sin(x[2]);
  // Ground velocity of the CG, then the air relative to the boat.
  const double vn = c * x[3] - s * x[4] + disturbances_.current_north_mps();
  const double ve = s * x[3] + c * x[4] + disturbances_.current_east_mps();
  const auto wind = disturbances_.wind_ne_mps();
  const double wn = wind[0] - vn;
  const double we = wind[1] - ve;
  const double wx = c * wn + s * we;
  const double wy = -s * wn + c * we;
  const double w = std::hypot(wx, wy);
  const double q = 0.5 * kRhoAir * kWindDragCoefficient * w;
  Tau tau;
  tau.x_n = q * params_.wind_area_front_m2 * wx;
  tau.y_n = q * params_.wind_area_side_m2 * wy;
  tau.n_nm = params_.wind_cp_forward_m * tau.y_n;
  return tau;
}

BoatModel::Vec6 BoatModel::derivative(const Vec6& x, const Tau& tau_ext) const {
  const DynamicsParams& p = params_;
  const double c = std::cos(x[2]);
  const double s = std::sin(x[2]);
  const double u = x[3];
  const double v = x[4];
  const double r = x[5];
  const Tau env = environment_tau(x);
  const double tx = tau_ext.x_n + env.x_n;
  const double ty = tau_ext.y_n + env.y_n;
  const double tn = tau_ext.n_nm + env.n_nm;
  Vec6 d{};
  d[0] = c * u - s * v + disturbances_.current_north_mps();
  d[1] = s * u + c * v + disturbances_.current_east_mps();
  d[2] = r;
  // M nu_r' = tau - C(nu_r) nu_r - D(nu_r) nu_r with diagonal M:
  // C(nu) nu = [-m22 v r, m11 u r, (m22 - m11) u v].
  d[3] = (tx + p.m22_kg * v * r - p.d_u * u - p.d_uu * u * std::abs(u)) / p.m11_kg;
  d[4] = (ty - p.m11_kg * u * r - p.d_v * v - p.d_vv * v * std::abs(v)) / p.m22_kg;
  d[5] = (tn - (p.m22_kg - p.m11_kg) * u * v - p.d_r * r - p.d_rr * r * std::abs(r)) / p.m66_kgm2;
  return d;
}

void BoatModel::step() {
  const double dt = dt_s_;
  // Actuators first (held over the step): servo slew, thrust lag toward the pulse's thrust.
  servo_.step(dt);
  const auto& act = boat_.actuators;
  std::array<double, 2> target{};
  if (act.layout == msg::ActuatorLayout::kServoThruster) {
    target[1] = thrust_from_pulse(act.thruster, pulses_[1], params_.thrust_fwd_max_n,
                                  params_.thrust_rev_max_n);
  } else {
    for (std::size_t i = 0; i < 2; ++i) {
      target[i] = thrust_from_pulse(act.thruster, pulses_[i], 0.5 * params_.thrust_fwd_max_n,
                                    0.5 * params_.thrust_rev_max_n);
    }
  }
  const double lag = 1.0 - std::exp(-dt / params_.thrust_time_constant_s);
  for (std::size_t i = 0; i < 2; ++i) thrust_n_[i] += (target[i] - thrust_n_[i]) * lag;
  disturbances_.step(dt);

  const Tau act_tau = actuator_tau(thrust_n_, servo_.angle_deg());
  const double t0 = static_cast<double>(steps_) * dt;
  auto with_waves = [&](double t) {
    const Tau w = disturbances_.wave_tau(t);
    return Tau{act_tau.x_n + w.x_n, act_tau.y_n + w.y_n, act_tau.n_nm + w.n_nm};
  };
  const Vec6 x0{state_.north_m, state_.east_m,  state_.psi_rad,
                state_.u_r_mps, state_.v_r_mps, state_.r_radps};
  auto add = [](const Vec6& a, const Vec6& b, double k) {
    Vec6 out{};
    for (std::size_t i = 0; i < 6; ++i) out[i] = a[i] + k * b[i];
    return out;
  };
  const Tau tau_mid = with_waves(t0 + 0.5 * dt);
  const Vec6 k1 = derivative(x0, with_waves(t0));
  const Vec6 k2 = derivative(add(x0, k1, 0.5 * dt), tau_mid);
  const Vec6 k3 = derivative(add(x0, k2, 0.5 * dt), tau_mid);
  const Vec6 k4 = derivative(add(x0, k3, dt), with_waves(t0 + dt));
  Vec6 x1{};
  for (std::size_t i = 0; i < 6; ++i) {
    x1[i] = x0[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
  }
  ++steps_;
  state_ = {x1[0], x1[1], core::wrap_rad(x1[2]), x1[3], x1[4], x1[5]};
  // Body acceleration over ground of the CG: nu_r' + r x nu_r (the current is constant).
  const Vec6 d = derivative(x1, with_waves(t0 + dt));
  accel_body_ = {d[3] - x1[5] * x1[4], d[4] + x1[5] * x1[3]};
}

double BoatModel::resolve_contact(core::NavPoint normal, core::NavPoint point, double depth_m,
                                  double restitution) {
  // Lever arm of the contact point from the centre of gravity, before the push-out (the push
  // moves both alike).
  const double rn = point.north_m - state_.north_m;
  const double re = point.east_m - state_.east_m;
  state_.north_m += normal.north_m * depth_m;
  state_.east_m += normal.east_m * depth_m;
  const double c = std::cos(state_.psi_rad);
  const double s = std::sin(state_.psi_rad);
  // Body frame (x forward, y starboard).
  const double rx = c * rn + s * re;
  const double ry = -s * rn + c * re;
  const double nx = c * normal.north_m + s * normal.east_m;
  const double ny = -s * normal.north_m + c * normal.east_m;
  const double cn = disturbances_.current_north_mps();
  const double ce = disturbances_.current_east_mps();
  // Velocity over ground of the contact point: the obstacle is fixed to the ground, not the water.
  const double u = state_.u_r_mps + c * cn + s * ce;
  const double v = state_.v_r_mps - s * cn + c * ce;
  const double r = state_.r_radps;
  const double vn = (u - r * ry) * nx + (v + r * rx) * ny;
  if (vn >= 0.0) return 0.0;
  const double arm = rx * ny - ry * nx;  // yaw moment of a unit force along normal
  const double k =
      nx * nx / params_.m11_kg + ny * ny / params_.m22_kg + arm * arm / params_.m66_kgm2;
  const double j = -(1.0 + restitution) * vn / k;
  state_.u_r_mps += j * nx / params_.m11_kg;
  state_.v_r_mps += j * ny / params_.m22_kg;
  state_.r_radps += j * arm / params_.m66_kgm2;
  // An accelerometer feels the contact force too: the impulse spread over the step. Pinned
  // against a wall with thrust on, the two cancel and the sensed acceleration is about zero.
  accel_body_[0] += j * nx / params_.m11_kg / dt_s_;
  accel_body_[1] += j * ny / params_.m22_kg / dt_s_;
  return -vn;
}

core::NavPoint velocity_at(const TruthState& truth, core::NavPoint point) {
  // omega (about z down) x arm: clockwise yaw swings a point ahead of the centre to starboard.
  const double r = core::deg_to_rad(truth.yaw_rate_dps);
  const double arm_n = point.north_m - truth.cg.north_m;
  const double arm_e = point.east_m - truth.cg.east_m;
  return {truth.vel_north_mps - r * arm_e, truth.vel_east_mps + r * arm_n};
}

TruthState BoatModel::truth() const {
  TruthState t;
  t.stamp_ns = time_ns();
  const double c = std::cos(state_.psi_rad);
  const double s = std::sin(state_.psi_rad);
  t.cg = {state_.north_m, state_.east_m};
  t.pose.position = {state_.north_m + cg_aft_m_ * c, state_.east_m + cg_aft_m_ * s};
  t.pose.heading_deg = core::wrap_deg(core::rad_to_deg(state_.psi_rad));
  t.vel_north_mps = c * state_.u_r_mps - s * state_.v_r_mps + disturbances_.current_north_mps();
  t.vel_east_mps = s * state_.u_r_mps + c * state_.v_r_mps + disturbances_.current_east_mps();
  t.u_mps = c * t.vel_north_mps + s * t.vel_east_mps;
  t.v_mps = -s * t.vel_north_mps + c * t.vel_east_mps;
  t.yaw_rate_dps = core::rad_to_deg(state_.r_radps);
  t.accel_forward_mps2 = accel_body_[0];
  t.accel_starboard_mps2 = accel_body_[1];
  t.pulse_us = pulses_;
  t.servo_deg = servo_.angle_deg();
  t.thrust_n = thrust_n_;
  return t;
}

}  // namespace coxswain::sim::dynamics
