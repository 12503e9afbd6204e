// SPDX-License-Identifier: Apache-2.0
#pragma once
// The names, ranges and accessors of the mission's live-tunable parameters (TunableParameters):
// what the live view's Foxglove parameter interface offers, what the flight recorder writes on
// /params when a set is applied, and what replay applies back at the same tick. One table, so the
// three agree. Pure data and functions; the table is built once and never changes (thread-safe to
// read from any thread).
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "coxswain/mission/mission_core.hpp"

namespace coxswain::mission {

/// Which engine a parameter belongs to (the engines whose parameters changed are rebuilt).
enum class TunableGroup : std::uint8_t {
  kHeadingPid = 0,
  kClustering,
  kAvoidance,
  kSpeed,
  kVision
};

/// One named parameter, e.g. "heading_pid.kp_per_deg", "avoidance.score.goal_weight",
/// "vision.red.h_min": the live rows of the parameter tables (config/param_tables.hpp), named
/// as in the mission file, with the tables' bounds. Values travel as doubles; `integer` ones
/// (counts, booleans, enumerations) must be whole numbers.
struct TunableSpec {
  std::string name;
  TunableGroup group = TunableGroup::kHeadingPid;
  double min = 0.0;
  double max = 0.0;
  bool integer = false;
  bool boolean = false;              // 0 or 1, written true/false in a file
  std::string unit;                  // "" when dimensionless
  std::string doc;                   // one line
  std::vector<std::string> choices;  // an enumeration's names, by value (0, 1, ...)
  std::function<double(const TunableParameters&)> get;
  std::function<void(TunableParameters&, double)> set;
};

/// Every tunable parameter, in a stable order (groups as in TunableGroup).
[[nodiscard]] const std::vector<TunableSpec>& tunable_specs();
/// The spec of `name`, or null.
[[nodiscard]] const TunableSpec* find_tunable(std::string_view name);

/// Empty when every engine accepts the set, else the first problem ("avoidance: ...").
[[nodiscard]] std::string validate_tunables(const TunableParameters& params);

/// Empty when `value` is a valid value of `spec` (finite, within the range, whole when it must
/// be), else why not.
[[nodiscard]] std::string check_tunable(const TunableSpec& spec, double value);

/// Sets `name` to `value` in `params` after checking its range and the whole set's validity.
/// Returns an empty string when set, else why not (`params` unchanged then).
[[nodiscard]] std::string set_tunable(TunableParameters& params, std::string_view name,
                                      double value);

/// True when a named parameter of `group` differs between `a` and `b` (bit for bit).
[[nodiscard]] bool tunables_differ(const TunableParameters& a, const TunableParameters& b,
                                   TunableGroup group);

}  // namespace coxswain::mission
