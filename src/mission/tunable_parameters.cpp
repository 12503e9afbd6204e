// SPDX-License-Identifier: Apache-2.0
#include "coxswain/mission/tunable_parameters.hpp"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

namespace coxswain::mission {
namespace {

// A double field of one group, by member pointers (outer struct member, then its field).
template <class Outer, class Field>
TunableSpec real(std::string name, TunableGroup group, double min, double max,
                 Outer TunableParameters::*outer, Field Outer::*field) {
  return {
      std::move(name),
      group,
      min,
      max,
      false,
      [outer, field](const TunableParameters& p) { return static_cast<double>(p.*outer.*field); },
      [outer, field](TunableParameters& p, double v) { p.*outer.*field = static_cast<Field>(v); }};
}

// A whole-number field (unsigned counts, enums) of one group.
template <class Outer, class Field>
TunableSpec whole(std::string name, TunableGroup group, double min, double max,
                  Outer TunableParameters::*outer, Field Outer::*field) {
  TunableSpec s = real(std::move(name), group, min, max, outer, field);
  s.integer = true;
  return s;
}

// An enum field, stored as its underlying value.
template <class Outer, class Enum>
TunableSpec enumerated(std::string name, TunableGroup group, double max,
                       Outer TunableParameters::*outer, Enum Outer::*field) {
  return {std::move(name),
          group,
          0.0,
          max,
          true,
          [outer, field](const TunableParameters& p) {
            return static_cast<double>(static_cast<int>(p.*outer.*field));
          },
          [outer, field](TunableParameters& p, double v) {
            p.*outer.*field = static_cast<Enum>(static_cast<int>(v));
          }};
}

// One bound of a colour's HSV range in the camera detectors' parameters.
TunableSpec hsv(msg::Colour colour, const char* bound, double max,
                std::uint8_t perception::HsvRange::*field) {
  std::string name = "vision." + std::string(msg::colour_name(colour)) + "." + bound;
  return {
      std::move(name),
      TunableGroup::kVision,
      0.0,
      max,
      true,
      [colour, field](const TunableParameters& p) {
        const int i = p.vision.find_colour(colour);
        return i < 0
                   ? std::nan("")
                   : static_cast<double>(p.vision.colours[static_cast<std::size_t>(i)].hsv.*field);
      },
      [colour, field](TunableParameters& p, double v) {
        const int i = p.vision.find_colour(colour);
        if (i >= 0) {
          p.vision.colours[static_cast<std::size_t>(i)].hsv.*field = static_cast<std::uint8_t>(v);
        }
      }};
}

std::vector<TunableSpec> build_specs() {
  using G = TunableGroup;
  using P = TunableParameters;
  using control::HeadingPidParams;
  using control::SpeedScheduleParams;
  using guidance::AvoidanceParams;
  using perception::LidarClusterParams;
  std::vector<TunableSpec> s;
  // Heading PID (turn command per degree of heading error).
  s.push_back(real("heading_pid.kp_per_deg", G::kHeadingPid, 0.0, 1.0, &P::heading_pid,
                   &HeadingPidParams::kp_per_deg));
  s.push_back(real("heading_pid.ki_per_deg_s", G::kHeadingPid, 0.0, 0.5, &P::heading_pid,
                   &HeadingPidParams::ki_per_deg_s));
  s.push_back(real("heading_pid.kd_per_dps", G::kHeadingPid, 0.0, 1.0, &P::heading_pid,
                   &HeadingPidParams::kd_per_dps));
  s.push_back(real("heading_pid.output_limit", G::kHeadingPid, 0.05, 1.0, &P::heading_pid,
                   &HeadingPidParams::output_limit));
  s.push_back(real("heading_pid.integral_limit", G::kHeadingPid, 0.0, 1.0, &P::heading_pid,
                   &HeadingPidParams::integral_limit));
  // Lidar clustering.
  s.push_back(real("clustering.group_gap_m", G::kClustering, 0.01, 2.0, &P::clustering,
                   &LidarClusterParams::group_gap_m));
  s.push_back(real("clustering.group_gap_per_m", G::kClustering, 0.0, 0.5, &P::clustering,
                   &LidarClusterParams::group_gap_per_m));
  s.push_back(whole("clustering.min_group_points", G::kClustering, 1.0, 100.0, &P::clustering,
                    &LidarClusterParams::min_group_points));
  s.push_back(real("clustering.split_distance_m", G::kClustering, 0.01, 2.0, &P::clustering,
                   &LidarClusterParams::split_distance_m));
  s.push_back(real("clustering.wall_min_length_m", G::kClustering, 0.05, 10.0, &P::clustering,
                   &LidarClusterParams::wall_min_length_m));
  s.push_back(real("clustering.max_range_m", G::kClustering, 1.0, 40.0, &P::clustering,
                   &LidarClusterParams::max_range_m));
  // Avoidance (strategy: 0 selection, 1 score, 2 risk_bin; all_blocked: 0 stop, 1 back_off).
  const auto av = [&](const char* field, double min, double max, double AvoidanceParams::*m) {
    s.push_back(real(std::string("avoidance.") + field, G::kAvoidance, min, max, &P::avoidance, m));
  };
  s.push_back(enumerated("avoidance.strategy", G::kAvoidance, 2.0, &P::avoidance,
                         &AvoidanceParams::strategy));
  av("detection_range_m", 0.5, 30.0, &AvoidanceParams::detection_range_m);
  av("half_beam_m", 0.0, 2.0, &AvoidanceParams::half_beam_m);
  av("clearance_m", 0.0, 2.0, &AvoidanceParams::clearance_m);
  av("slow_down_range_m", 0.1, 20.0, &AvoidanceParams::slow_down_range_m);
  av("min_speed_factor", 0.0, 1.0, &AvoidanceParams::min_speed_factor);
  av("shrink_factor", 0.05, 0.95, &AvoidanceParams::shrink_factor);
  av("min_detection_range_m", 0.1, 30.0, &AvoidanceParams::min_detection_range_m);
  av("blocked_speed_factor", 0.0, 1.0, &AvoidanceParams::blocked_speed_factor);
  s.push_back(enumerated("avoidance.all_blocked", G::kAvoidance, 1.0, &P::avoidance,
                         &AvoidanceParams::all_blocked_policy));
  av("back_off_speed_factor", 0.0, 1.0, &AvoidanceParams::back_off_speed_factor);
  av("hysteresis_deg", 0.0, 90.0, &AvoidanceParams::hysteresis_deg);
  av("hold_time_s", 0.0, 10.0, &AvoidanceParams::hold_time_s);
  av("score_goal_weight", 0.01, 10.0, &AvoidanceParams::score_goal_weight);
  av("score_distance_weight", 0.0, 10.0, &AvoidanceParams::score_distance_weight);
  av("score_angle_weight", 0.0, 10.0, &AvoidanceParams::score_angle_weight);
  av("score_block_range_m", 0.0, 30.0, &AvoidanceParams::score_block_range_m);
  av("risk_gain_per_m", 0.01, 20.0, &AvoidanceParams::risk_gain_per_m);
  av("risk_offset", -10.0, 10.0, &AvoidanceParams::risk_offset);
  av("risk_max", 0.001, 1000.0, &AvoidanceParams::risk_max);
  av("risk_threshold", 1e-6, 100.0, &AvoidanceParams::risk_threshold);
  // Speed schedule (thrust fraction by distance to go, then the rise/fall rate limit).
  const auto sp = [&](const char* field, double min, double max, double SpeedScheduleParams::*m) {
    s.push_back(real(std::string("speed.") + field, G::kSpeed, min, max, &P::speed, m));
  };
  sp("min_thrust_frac", 0.0, 1.0, &SpeedScheduleParams::min_thrust_frac);
  sp("max_thrust_frac", 0.0, 1.0, &SpeedScheduleParams::max_thrust_frac);
  sp("slow_distance_m", 0.0, 50.0, &SpeedScheduleParams::slow_distance_m);
  sp("fast_distance_m", 0.0, 100.0, &SpeedScheduleParams::fast_distance_m);
  sp("rise_per_s", 0.01, 10.0, &SpeedScheduleParams::rise_per_s);
  sp("fall_per_s", 0.01, 10.0, &SpeedScheduleParams::fall_per_s);
  // Vision: the HSV box of every colour the detectors search (OpenCV 8-bit: hue 0..179,
  // saturation and value 0..255; h_min > h_max wraps through 180, as red does).
  const perception::VisionParams vision = perception::VisionParams::defaults();
  for (std::size_t i = 0; i < vision.colour_count; ++i) {
    const msg::Colour c = vision.colours[i].colour;
    s.push_back(hsv(c, "h_min", 179.0, &perception::HsvRange::h_min));
    s.push_back(hsv(c, "h_max", 179.0, &perception::HsvRange::h_max));
    s.push_back(hsv(c, "s_min", 255.0, &perception::HsvRange::s_min));
    s.push_back(hsv(c, "s_max", 255.0, &perception::HsvRange::s_max));
    s.push_back(hsv(c, "v_min", 255.0, &perception::HsvRange::v_min));
    s.push_back(hsv(c, "v_max", 255.0, &perception::HsvRange::v_max));
  }
  return s;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

const std::vector<TunableSpec>& tunable_specs() {
  static const std::vector<TunableSpec> specs = build_specs();
  return specs;
}

const TunableSpec* find_tunable(std::string_view name) {
  for (const TunableSpec& spec : tunable_specs()) {
    if (spec.name == name) return &spec;
  }
  return nullptr;
}

std::string validate_tunables(const TunableParameters& p) {
  if (auto e = p.heading_pid.validate()) return "heading_pid: " + *e;
  if (auto e = p.clustering.validate(); !e.empty()) return "clustering: " + e;
  if (auto e = p.avoidance.validate(); !e.empty()) return "avoidance: " + e;
  if (auto e = p.speed.validate()) return "speed: " + *e;
  if (auto e = p.vision.validate(); !e.empty()) return "vision: " + e;
  return {};
}

std::string check_tunable(const TunableSpec& spec, double value) {
  if (!std::isfinite(value) || value < spec.min || value > spec.max) {
    char range[96];
    (void)std::snprintf(range, sizeof range, " must be within [%g, %g]", spec.min, spec.max);
    return spec.name + range;
  }
  if (spec.integer && std::floor(value) != value) return spec.name + " must be a whole number";
  return {};
}

std::string set_tunable(TunableParameters& params, std::string_view name, double value) {
  const TunableSpec* spec = find_tunable(name);
  if (spec == nullptr) return "unknown parameter '" + std::string(name) + "'";
  if (std::string e = check_tunable(*spec, value); !e.empty()) return e;
  TunableParameters candidate = params;
  spec->set(candidate, value);
  if (std::string e = validate_tunables(candidate); !e.empty()) return std::string(name) + ": " + e;
  params = candidate;
  return {};
}

bool tunables_differ(const TunableParameters& a, const TunableParameters& b, TunableGroup group) {
  for (const TunableSpec& spec : tunable_specs()) {
    if (spec.group == group && !same_bits(spec.get(a), spec.get(b))) return true;
  }
  return false;
}

}  // namespace coxswain::mission
