// SPDX-License-Identifier: Apache-2.0
#include "sim/dynamics/params.hpp"

#include <cmath>

namespace coxswain::sim::dynamics {
namespace {
constexpr double kOtterLength_m = 2.0;
constexpr double kG = 9.81;
constexpr double kRhoWater = 1025.0;
}  // namespace

DynamicsParams otter_scaled(double length_m) {
  const double l = length_m / kOtterLength_m;
  const double l3 = l * l * l;
  const double l5 = l3 * l * l;
  const double sl = std::sqrt(l);
  DynamicsParams p;
  p.scale = l;
  p.m11_kg = 85.5 * l3;
  p.m22_kg = 162.5 * l3;
  p.m66_kgm2 = 41.4 * l5;
  // Surge: drag at top speed equals bollard thrust; split like the WAM-V (23 % linear).
  const double thrust_n = 24.4 * kG * l3;
  const double top_speed_mps = 3.09 * sl;
  const double linear_fraction = (51.3 * 2.32) / (51.3 * 2.32 + 72.4 * 2.32 * 2.32);
  p.d_u = linear_fraction * thrust_n / top_speed_mps;
  p.d_uu = (1.0 - linear_fraction) * thrust_n / (top_speed_mps * top_speed_mps);
  // Sway: Otter time constant 1 s; cross-flow drag with C_d = 1 over length x draft.
  p.d_v = p.m22_kg / (1.0 * sl);
  p.d_vv = 0.5 * kRhoWater * 1.0 * length_m * (0.195 * l);
  // Yaw: Otter N_r and N_r|r|.
  p.d_r = 41.4 * std::pow(l, 4.5);
  p.d_rr = 414.5 * l5;
  p.thrust_fwd_max_n = thrust_n;
  p.thrust_rev_max_n = 13.6 * kG * l3;
  p.thrust_time_constant_s = 1.0 * sl;
  p.wind_area_side_m2 = 0.2 * length_m * length_m;
  p.wind_area_front_m2 = 0.35 * p.wind_area_side_m2;
  p.wind_cp_forward_m = 0.05 * length_m;
  return p;
}

DynamicsParams make_params(const config::BoatConfig& boat, const DynamicsOverrides& overrides) {
  DynamicsParams p =
      otter_scaled(overrides.length_m > 0.0 ? overrides.length_m : boat.hull.length_m);
  for (std::size_t i = 0; i < std::size(kParamFields); ++i) {
    if (overrides.given[i]) p.*(kParamFields[i].field) = overrides.value[i];
  }
  return p;
}

DynamicsOverrides read_dynamics_overrides(config::MapReader& m) {
  DynamicsOverrides o;
  o.length_m = m.get("scale_from_length_m", 0.0, {0.0, 20.0});
  for (std::size_t i = 0; i < std::size(kParamFields); ++i) {
    if (!m.has(kParamFields[i].key)) continue;
    // The centre of wind pressure may lie behind the centre of gravity; all else is positive.
    const bool signed_value = kParamFields[i].key == "wind_cp_forward_m";
    const config::Bounds<double> bounds =
        signed_value ? config::Bounds<double>{-10.0, 10.0} : config::Bounds<double>{1e-6, 1e6};
    o.value[i] = m.get(kParamFields[i].key, 0.0, bounds);
    o.given[i] = true;
  }
  m.finish();
  return o;
}

Environment read_environment(config::MapReader& m) {
  Environment e;
  if (auto c = m.map("current")) {
    e.current_speed_mps = c->get("speed_mps", 0.0, {0.0, 5.0});
    e.current_toward_deg = c->get("toward_deg", 0.0, {-360.0, 360.0});
    c->finish();
  }
  if (auto w = m.map("wind")) {
    e.wind_speed_mps = w->get("speed_mps", 0.0, {0.0, 30.0});
    e.wind_from_deg = w->get("from_deg", 0.0, {-360.0, 360.0});
    e.gust_std_mps = w->get("gust_std_mps", 0.0, {0.0, 20.0});
    e.gust_time_s = w->get("gust_time_s", 5.0, {0.1, 600.0});
    w->finish();
  }
  if (auto w = m.map("waves")) {
    e.wave_force_n = w->get("force_n", 0.0, {0.0, 1000.0});
    e.wave_period_s = w->get("period_s", 2.0, {0.2, 30.0});
    w->finish();
  }
  m.finish();
  return e;
}

}  // namespace coxswain::sim::dynamics
