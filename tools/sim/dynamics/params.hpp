// SPDX-License-Identifier: Apache-2.0
#pragma once
// Parameters of the simulated boat's 3-DOF manoeuvring model (surge, sway, yaw; Fossen's form,
// docs/simulator.md) and of its environment. Plain data; see otter_scaled() for
// where every default comes from.
#include <array>
#include <cstdint>
#include <iterator>
#include <string_view>

#include "coxswain/config/config.hpp"
#include "coxswain/config/yaml_reader.hpp"

namespace coxswain::sim::dynamics {

/// Hydrodynamic and actuator constants, SI units, body axes x forward, y starboard, z down.
/// Damping coefficients are positive magnitudes (force opposes motion): X = -(d_u u + d_uu u|u|).
struct DynamicsParams {
  double scale = 0.6;              // Froude ratio lambda = L_boat / L_otter used to derive the rest
  double m11_kg = 18.47;           // surge mass incl. added mass
  double m22_kg = 35.10;           // sway mass incl. added mass
  double m66_kgm2 = 3.219;         // yaw inertia incl. added inertia
  double d_u = 5.054;              // linear surge damping, N s/m
  double d_uu = 6.914;             // quadratic surge damping, N s^2/m^2
  double d_v = 45.31;              // linear sway damping, N s/m
  double d_vv = 71.96;             // quadratic (cross-flow) sway damping, N s^2/m^2
  double d_r = 4.156;              // linear yaw damping, N m s
  double d_rr = 32.23;             // quadratic yaw damping, N m s^2
  double thrust_fwd_max_n = 51.7;  // bollard thrust of the whole propulsion, forward
  double thrust_rev_max_n = 28.82;        // and in reverse
  double thrust_time_constant_s = 0.775;  // first-order lag from command to thrust
  double wind_area_front_m2 = 0.1008;     // above-water projected areas (wind forces)
  double wind_area_side_m2 = 0.288;
  double wind_cp_forward_m = 0.06;  // centre of wind pressure ahead of the centre of gravity
};

/// Derives every parameter from Fossen's Otter USV (L = 2.0 m) by Froude scaling to `length_m`
/// (lambda = length_m / 2.0): masses and forces lambda^3, yaw inertia lambda^5, times and speeds
/// sqrt(lambda), linear surge/sway damping lambda^2.5, linear yaw damping lambda^4.5, quadratic
/// surge/sway damping lambda^2, quadratic yaw damping lambda^5. Sources and choices:
/// - M11 85.5 kg, M22 162.5 kg, M66 41.4 kg m^2 (Otter incl. added mass; the small M26 coupling
///   is dropped, which keeps M diagonal).
/// - Surge: the Otter's top speed 3.09 m/s at its bollard thrust 2 x 12.2 kgf = 239 N fixes the
///   total drag at top speed; it is split between linear and quadratic terms in the proportion
///   of the VRX WAM-V at its top speed (xU 51.3 * 2.32 = 119 N vs xUU 72.4 * 2.32^2 = 390 N,
///   23 % linear), because the Otter model has only a linear term and a real hull is mostly
///   quadratic at speed.
/// - Sway: linear d_v = M22 / T_sway with the Otter's T_sway = 1 s; quadratic by cross-flow drag
///   0.5 rho C_d L T (C_d = 1.0, rho = 1025, Otter draft 0.195 m) at the scaled size.
/// - Yaw: Otter N_r = 41.4 N m s (T_yaw = 1 s), N_r|r| = 414.5 N m s^2.
/// - Thrust: Otter bollard 24.4 kgf forward, 13.6 kgf reverse, first-order lag 1 s.
/// - Wind areas (our choice, no source): side 0.2 L x L, front 0.35 of that, centre of pressure
///   0.05 L ahead of the centre of gravity (the boat weathervanes slowly).
/// The defaults below are otter_scaled(1.2), the hull of config/boat.yaml.
DynamicsParams otter_scaled(double length_m);

/// Names of the parameters a `dynamics:` section may override (YAML keys = field names).
struct ParamField {
  std::string_view key;
  double DynamicsParams::*field;
};
inline constexpr ParamField kParamFields[] = {
    {"m11_kg", &DynamicsParams::m11_kg},
    {"m22_kg", &DynamicsParams::m22_kg},
    {"m66_kgm2", &DynamicsParams::m66_kgm2},
    {"d_u", &DynamicsParams::d_u},
    {"d_uu", &DynamicsParams::d_uu},
    {"d_v", &DynamicsParams::d_v},
    {"d_vv", &DynamicsParams::d_vv},
    {"d_r", &DynamicsParams::d_r},
    {"d_rr", &DynamicsParams::d_rr},
    {"thrust_fwd_max_n", &DynamicsParams::thrust_fwd_max_n},
    {"thrust_rev_max_n", &DynamicsParams::thrust_rev_max_n},
    {"thrust_time_constant_s", &DynamicsParams::thrust_time_constant_s},
    {"wind_area_front_m2", &DynamicsParams::wind_area_front_m2},
    {"wind_area_side_m2", &DynamicsParams::wind_area_side_m2},
    {"wind_cp_forward_m", &DynamicsParams::wind_cp_forward_m},
};

/// The water and air around the boat (a course file's `environment:` section). All disturbances
/// are zero by default; their random parts are drawn from the run's seed.
struct Environment {
  double current_speed_mps = 0.0;   // uniform, constant, irrotational
  double current_toward_deg = 0.0;  // direction the water flows to (navigation heading)
  double wind_speed_mps = 0.0;      // mean wind
  double wind_from_deg = 0.0;       // direction the wind blows from
  double gust_std_mps = 0.0;        // standard deviation of the gusts (Gauss-Markov process)
  double gust_time_s = 5.0;         // correlation time of the gusts
  double wave_force_n = 0.0;        // amplitude of the wave-like force (sum of sinusoids)
  double wave_period_s = 2.0;       // dominant period of those sinusoids
};

/// Overrides from a `dynamics:` section: which fields were given and their values.
struct DynamicsOverrides {
  double length_m = 0.0;  // scale from this hull length instead of the boat's (0 = the boat's)
  std::array<double, std::size(kParamFields)> value{};
  std::array<bool, std::size(kParamFields)> given{};
};

/// The parameters for `boat`: Otter scaled to its hull (or overrides.length_m), then overrides.
DynamicsParams make_params(const config::BoatConfig& boat, const DynamicsOverrides& overrides);

/// Reads a `dynamics:` map (keys of kParamFields plus `scale_from_length_m`); errors to `m`.
DynamicsOverrides read_dynamics_overrides(config::MapReader& m);
/// Reads an `environment:` map.
Environment read_environment(config::MapReader& m);

}  // namespace coxswain::sim::dynamics
