// SPDX-License-Identifier: Apache-2.0
#pragma once
// The simulated boat: actuators (servo-turned stern thruster, or twin fixed thrusters, driven by
// pulse widths as the Arduino applies them), environment disturbances and Fossen's planar 3-DOF
// manoeuvring model  M dnu_r/dt + C(nu_r) nu_r + D(nu_r) nu_r = tau  integrated by RK4 at a fixed
// step. nu_r = nu - nu_current (constant irrotational current), so the boat drifts with the water.
// The model's reference point is the centre of gravity at mid-hull; poses reported to others are
// of the body origin (the sensor reference at the bow, config hull.bow_overhang_m). Deterministic:
// the same parameters, seed and pulse sequence give bit-identical states. Not thread-safe.
#include <array>
#include <cstdint>

#include "coxswain/config/config.hpp"
#include "coxswain/core/frames.hpp"
#include "coxswain/core/time.hpp"
#include "sim/dynamics/params.hpp"
#include "sim/rng/rng.hpp"

namespace coxswain::sim::dynamics {

/// Thrust of one ESC-driven thruster from its pulse width: zero inside the ESC deadband
/// [reverse_start_us, forward_start_us], then growing with the square of the normalised command
/// (thrust ~ n|n| with rpm ~ command) up to max_fwd_n at max_us, or max_rev_n at min_us
/// (asymmetric reverse; zero when reverse is not allowed). Pure function.
double thrust_from_pulse(const config::ThrusterConfig& esc, std::uint16_t pulse_us,
                         double max_fwd_n, double max_rev_n);

/// Servo deflection the servo moves to for a pulse (positive = bow to starboard), before slew.
double servo_target_deg(const config::ServoConfig& servo, std::uint16_t pulse_us);

/// A rate-limited hobby servo with a deadband: it ignores a command within deadband_us of where it
/// is heading already, and slews at rate_deg_per_s.
class ServoModel {
 public:
  explicit ServoModel(const config::ServoConfig& config) : config_(config) {}
  void command(std::uint16_t pulse_us);
  void step(double dt_s);
  [[nodiscard]] double angle_deg() const { return angle_deg_; }

 private:
  config::ServoConfig config_;
  std::uint16_t target_pulse_us_ = 0;
  double target_deg_ = 0.0;
  double angle_deg_ = 0.0;
};

/// Body-frame generalised force (surge N, sway N, yaw N m) about the centre of gravity.
struct Tau {
  double x_n = 0.0;
  double y_n = 0.0;
  double n_nm = 0.0;
};

/// Boat kinematic and kinetic state at the centre of gravity. Velocities relative to the water.
struct BoatState {
  double north_m = 0.0;
  double east_m = 0.0;
  double psi_rad = 0.0;  // heading, wrapped into (-pi, pi]
  double u_r_mps = 0.0;  // surge relative to the water
  double v_r_mps = 0.0;  // sway relative to the water
  double r_radps = 0.0;  // yaw rate, positive to starboard
};

/// Everything true about the boat at one instant: what sensors sample and scoring judges. Small
/// and trivially copyable.
struct TruthState {
  core::TimeNs stamp_ns = 0;
  core::NavPose pose;          // body origin (bow sensor reference), heading in (-180, 180]
  core::NavPoint cg;           // centre of gravity (mid-hull)
  double vel_north_mps = 0.0;  // velocity over ground of the centre of gravity
  double vel_east_mps = 0.0;
  double u_mps = 0.0;  // body-frame velocity over ground (x forward, y starboard)
  double v_mps = 0.0;
  double yaw_rate_dps = 0.0;                // positive to starboard (clockwise)
  double accel_forward_mps2 = 0.0;          // body-frame acceleration of the centre of gravity
  double accel_starboard_mps2 = 0.0;        // over ground (what an accelerometer senses, less g)
  std::array<std::uint16_t, 2> pulse_us{};  // pulses the actuators received (Arduino outputs)
  double servo_deg = 0.0;                   // servo deflection (servo_thruster layout)
  std::array<double, 2> thrust_n{};         // thrust of each thruster (channel order)
};

/// Velocity over ground (north, east, m/s) of a point fixed to the hull at `point` (navigation
/// frame, at this instant): the centre of gravity's plus the yaw rate's swing of the arm from
/// it. A sensor reports the velocity of where it sits, which differs in a turn.
[[nodiscard]] core::NavPoint velocity_at(const TruthState& truth, core::NavPoint point);

/// Current, gusting wind and wave-like forces, all seeded. step() advances the random parts.
class Disturbances {
 public:
  Disturbances(const Environment& env, std::uint64_t seed);
  /// Advances the gust process by dt_s (call once per dynamics step).
  void step(double dt_s);
  /// Current velocity in the navigation frame.
  [[nodiscard]] double current_north_mps() const { return current_north_; }
  [[nodiscard]] double current_east_mps() const { return current_east_; }
  /// Wind velocity (where the air goes) in the navigation frame, mean plus gust.
  [[nodiscard]] std::array<double, 2> wind_ne_mps() const;
  [[nodiscard]] bool has_wind() const {
    return env_.wind_speed_mps > 0.0 || env_.gust_std_mps > 0.0;
  }
  /// Wave-like body-frame force at time t_s (a sum of three seeded sinusoids per axis).
  [[nodiscard]] Tau wave_tau(double t_s) const;

 private:
  Environment env_;
  Rng rng_;
  double current_north_ = 0.0;
  double current_east_ = 0.0;
  double gust_mps_ = 0.0;
  std::array<double, 9> wave_phase_{};
  std::array<double, 3> wave_freq_{};
};

/// The 3-DOF boat with its actuators. Units SI; step size fixed at construction.
class BoatModel {
 public:
  BoatModel(const config::BoatConfig& boat, const DynamicsParams& params, const Environment& env,
            std::uint64_t seed, double dt_s = 0.01);

  /// Places the boat (body origin at `pose`) at rest relative to the ground.
  void reset(const core::NavPose& pose);
  /// The pulses the Arduino applies from now on (channel order of msg::ActuatorLayout).
  void set_pulses(const std::array<std::uint16_t, 2>& pulse_us);
  /// One fixed step of dt_s.
  void step();
  /// A contact with something fixed to the ground (wall, dock, buoy): the hull overlaps it by
  /// `depth_m` along `normal` (unit, navigation frame, from the obstacle into the boat) at
  /// `point` (navigation frame). Moves the boat out by depth_m along normal, then, when the
  /// contact point moves into the obstacle, applies the impulse along normal (rigid-body masses
  /// incl. added mass, about the centre of gravity) that leaves it moving out at `restitution`
  /// times its speed into it. No friction: motion along the obstacle is kept. Returns the speed
  /// of the contact point into the obstacle before the impulse (0 when separating). The
  /// impulse, spread over the step, is part of the sensed acceleration (truth().accel_*).
  double resolve_contact(core::NavPoint normal, core::NavPoint point, double depth_m,
                         double restitution);

  [[nodiscard]] const BoatState& state() const { return state_; }
  [[nodiscard]] TruthState truth() const;
  [[nodiscard]] double dt_s() const { return dt_s_; }
  [[nodiscard]] core::TimeNs time_ns() const { return steps_ * dt_ns_; }
  [[nodiscard]] const DynamicsParams& params() const { return params_; }
  /// Distance from the body origin (bow) back to the centre of gravity.
  [[nodiscard]] double cg_aft_of_origin_m() const { return cg_aft_m_; }
  /// Actuator force for given thrusts and servo angle (exposed for tests).
  [[nodiscard]] Tau actuator_tau(const std::array<double, 2>& thrust_n, double servo_deg) const;

 private:
  using Vec6 = std::array<double, 6>;
  [[nodiscard]] Vec6 derivative(const Vec6& x, const Tau& tau_ext) const;
  [[nodiscard]] Tau environment_tau(const Vec6& x) const;

  config::BoatConfig boat_;
  DynamicsParams params_;
  Disturbances disturbances_;
  ServoModel servo_;
  double dt_s_;
  core::TimeNs dt_ns_;
  std::int64_t steps_ = 0;
  double cg_aft_m_;
  double thruster_x_m_;  // thruster position relative to the CG (negative: astern)
  BoatState state_;
  std::array<std::uint16_t, 2> pulses_{};
  std::array<double, 2> thrust_n_{};
  std::array<double, 2> accel_body_{};
};

}  // namespace coxswain::sim::dynamics
