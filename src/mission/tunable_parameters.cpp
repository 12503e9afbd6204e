// SPDX-License-Identifier: Apache-2.0
#include "coxswain/mission/tunable_parameters.hpp"

#include "coxswain/config/param_tables.hpp"

#include <bit>
#include <cmath>
#include <cstdio>
#include <string>

namespace coxswain::mission {
namespace {

// Every live row of one struct's table, as named parameters of `group` ("section.key").
template <class S>
void add_live_rows(std::vector<TunableSpec>& out, std::string_view section, TunableGroup group,
                   S TunableParameters::*member) {
  for (const core::ParamSpec<S>& row : config::param_table<S>()) {
    if (!row.live) continue;
    const core::ParamSpec<S>* spec = &row;  // tables are static: the pointer stays valid
    TunableSpec t;
    t.name = std::string(section) + "." + std::string(row.key);
    t.group = group;
    t.min = row.min;
    t.max = row.max;
    t.integer = row.type != core::ParamType::kReal;
    t.boolean = row.type == core::ParamType::kBool;
    t.unit = std::string(row.unit);
    t.doc = std::string(row.doc);
    if (row.type == core::ParamType::kEnum) {
      t.max = 0.0;
      for (const core::ParamChoice& c : row.choices) {
        if (!c.live) continue;
        t.choices.emplace_back(c.name);
        if (static_cast<double>(c.value) > t.max) t.max = static_cast<double>(c.value);
      }
    }
    t.get = [member, spec](const TunableParameters& p) { return spec->get(p.*member); };
    t.set = [member, spec](TunableParameters& p, double v) { spec->set(p.*member, v); };
    out.push_back(std::move(t));
  }
}

// One live row of a colour's entry in the camera detectors' parameters (its HSV bounds), as
// "vision.<colour>.<key>", with the row's bounds and words.
TunableSpec colour_row(msg::Colour colour, const core::ParamSpec<perception::ColourRange>* spec) {
  TunableSpec t;
  t.name = "vision." + std::string(msg::colour_name(colour)) + "." + std::string(spec->key);
  t.group = TunableGroup::kVision;
  t.min = spec->min;
  t.max = spec->max;
  t.integer = spec->type != core::ParamType::kReal;
  t.unit = std::string(spec->unit);
  t.doc = std::string(spec->doc);
  t.get = [colour, spec](const TunableParameters& p) {
    const int i = p.vision.find_colour(colour);
    return i < 0 ? std::nan("") : spec->get(p.vision.colours[static_cast<std::size_t>(i)]);
  };
  t.set = [colour, spec](TunableParameters& p, double v) {
    const int i = p.vision.find_colour(colour);
    if (i >= 0) spec->set(p.vision.colours[static_cast<std::size_t>(i)], v);
  };
  return t;
}

std::vector<TunableSpec> build_specs() {
  using G = TunableGroup;
  using P = TunableParameters;
  std::vector<TunableSpec> s;
  add_live_rows(s, "heading_pid", G::kHeadingPid, &P::heading_pid);
  add_live_rows(s, "clustering", G::kClustering, &P::clustering);
  add_live_rows(s, "avoidance", G::kAvoidance, &P::avoidance);
  add_live_rows(s, "speed", G::kSpeed, &P::speed);
  // Vision: the live rows (the HSV box) of every colour the detectors search.
  const perception::VisionParams vision = perception::VisionParams::defaults();
  for (std::size_t i = 0; i < vision.colour_count; ++i) {
    for (const core::ParamSpec<perception::ColourRange>& row :
         config::param_table<perception::ColourRange>()) {
      if (row.live) s.push_back(colour_row(vision.colours[i].colour, &row));
    }
  }
  return s;
}

bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

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
  if (auto e = p.clustering.validate()) return "clustering: " + *e;
  if (auto e = p.avoidance.validate()) return "avoidance: " + *e;
  if (auto e = p.speed.validate()) return "speed: " + *e;
  if (auto e = p.vision.validate()) return "vision: " + *e;
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
