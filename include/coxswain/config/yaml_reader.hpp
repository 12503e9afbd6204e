// SPDX-License-Identifier: Apache-2.0
#pragma once
// Typed, validating access to YAML config maps. Every error names the file, the line and the full
// key ("actuators.servo.max_deg"); keys that were never read are errors too, so a misspelt key
// cannot silently fall back to a default (Cartographer's rule). Parse, validate, then construct:
// nothing here throws to the caller; errors are collected and reported together.
#include <yaml-cpp/yaml.h>

#include "coxswain/config/config_errors.hpp"

#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace coxswain::config {

/// Inclusive numeric bounds for a value; unset ends are open.
template <class T>
struct Bounds {
  T min = std::numeric_limits<T>::lowest();
  T max = std::numeric_limits<T>::max();
};

/// Reads one YAML map. Call `finish()` after reading every key to report unknown ones.
class MapReader {
 public:
  MapReader(const YAML::Node& node, std::string file, std::string path, ConfigErrors& errors);

  [[nodiscard]] bool valid() const { return valid_; }
  [[nodiscard]] bool has(std::string_view key) const;
  [[nodiscard]] const std::string& file() const { return file_; }
  [[nodiscard]] ConfigErrors& errors() const { return *errors_; }

  /// Optional scalar: `fallback` when the key is absent, an error when it has the wrong type or is
  /// out of bounds (then `fallback` is returned so validation can continue).
  template <class T>
  T get(std::string_view key, T fallback, Bounds<T> bounds = {});
  /// Required scalar: an error when absent.
  template <class T>
  T require(std::string_view key, Bounds<T> bounds = {});
  /// A string that must be one of `choices` (each with its value).
  template <class E>
  E get_enum(std::string_view key, E fallback,
             std::initializer_list<std::pair<std::string_view, E>> choices);

  /// A nested map; nullopt (and, when required, an error) when absent or not a map.
  std::optional<MapReader> map(std::string_view key, bool required = false);
  /// A sequence; empty (and, when required, an error) when absent or not a sequence.
  std::vector<YAML::Node> sequence(std::string_view key, bool required = false);
  /// A reader for one element of a sequence that must be a map.
  std::optional<MapReader> element(const YAML::Node& node, std::size_t index,
                                   std::string_view sequence_key);

  /// Reports every key of this map that was never read. Idempotent.
  void finish();

  /// Records an error at `key` (or at this map when `key` is empty).
  void error(std::string_view key, std::string message) const;

 private:
  [[nodiscard]] std::string full_key(std::string_view key) const;
  [[nodiscard]] int line_of(std::string_view key) const;
  std::optional<YAML::Node> find(std::string_view key);

  YAML::Node node_;
  std::string file_;
  std::string path_;
  ConfigErrors* errors_;
  std::set<std::string, std::less<>> seen_;
  bool valid_ = true;
  bool finished_ = false;
};

/// The largest config file read (boat, devices, mission, course, sensors): far above the largest
/// shipped file and a 20,000-obstacle course, small enough that a wrong file is refused at once.
inline constexpr std::uintmax_t kMaxConfigFileBytes = 8U << 20U;

/// The most values (maps, lists and scalars, every alias counted each time it is used) a config
/// document may expand to: a 20,000-obstacle course has about 300,000. Aliases of aliases can
/// make a 4 KiB file expand to billions, which every reader would walk.
inline constexpr std::size_t kMaxConfigNodes = 2'000'000;
/// The deepest nesting of maps and lists in a config file (the shipped ones nest 5 deep).
inline constexpr int kMaxConfigDepth = 64;

/// Loads a YAML file holding exactly one document; records the issue and returns nullopt on a
/// syntax error, an unreadable, empty or over-long (`max_bytes`) file, a second document, a
/// duplicate key anywhere (each duplicate with its line), nesting deeper than kMaxConfigDepth or
/// more than kMaxConfigNodes values once aliases are expanded.
std::optional<YAML::Node> load_yaml_file(const std::string& path, ConfigErrors& errors,
                                         std::uintmax_t max_bytes = kMaxConfigFileBytes);

/// True for an optional sign and decimal digits without a leading zero ("0", "-12", "115200");
/// false for "0115200" (octal to yaml-cpp), "0x1C" and anything else.
[[nodiscard]] bool is_decimal_integer(std::string_view text);

// ---- template implementations -------------------------------------------------------------

namespace detail {
template <class T>
std::string type_name() {
  if constexpr (std::is_same_v<T, bool>) {
    return "true or false";
  } else if constexpr (std::is_integral_v<T>) {
    return "an integer";
  } else if constexpr (std::is_floating_point_v<T>) {
    return "a number";
  } else {
    return "a string";
  }
}
template <class T>
std::string to_text(const T& v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
}  // namespace detail

template <class T>
T MapReader::get(std::string_view key, T fallback, Bounds<T> bounds) {
  const std::optional<YAML::Node> found = find(key);
  if (!found) return fallback;
  const YAML::Node& value = *found;
  if (!value.IsScalar()) {
    error(key, "expected " + detail::type_name<T>() + ", got a " +
                   (value.IsMap()        ? "map"
                    : value.IsSequence() ? "sequence"
                                         : "null"));
    return fallback;
  }
  if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
    if (!is_decimal_integer(value.Scalar())) {
      error(key, "expected a decimal integer, got '" + value.Scalar() + "'");
      return fallback;
    }
  }
  T out{};
  try {
    out = value.as<T>();
  } catch (const YAML::Exception&) {
    error(key, "expected " + detail::type_name<T>() + ", got '" + value.Scalar() + "'");
    return fallback;
  }
  if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
    if constexpr (std::is_floating_point_v<T>) {
      if (!(out == out)) {
        error(key, "must be a finite number");
        return fallback;
      }
    }
    if (out < bounds.min || out > bounds.max) {
      std::string range = "must be";
      if (bounds.min != std::numeric_limits<T>::lowest())
        range += " >= " + detail::to_text(bounds.min);
      if (bounds.min != std::numeric_limits<T>::lowest() &&
          bounds.max != std::numeric_limits<T>::max())
        range += " and";
      if (bounds.max != std::numeric_limits<T>::max())
        range += " <= " + detail::to_text(bounds.max);
      error(key, range + ", got " + detail::to_text(out));
      return fallback;
    }
  }
  return out;
}

template <class T>
T MapReader::require(std::string_view key, Bounds<T> bounds) {
  if (!has(key)) {
    error(key, "is required");
    seen_.emplace(key);
    return T{};
  }
  return get<T>(key, T{}, bounds);
}

template <class E>
E MapReader::get_enum(std::string_view key, E fallback,
                      std::initializer_list<std::pair<std::string_view, E>> choices) {
  if (!has(key)) {
    seen_.emplace(key);
    return fallback;
  }
  const std::string text = get<std::string>(key, std::string{});
  for (const auto& [name, value] : choices) {
    if (text == name) return value;
  }
  std::string list;
  for (const auto& choice : choices) {
    if (!list.empty()) list += ", ";
    list += choice.first;
  }
  error(key, "must be one of: " + list + "; got '" + text + "'");
  return fallback;
}

}  // namespace coxswain::config
