// SPDX-License-Identifier: Apache-2.0
#pragma once
// One declaration per parameter. A parameter struct (an engine's `...Params`, a device's
// settings) gets one table of ParamSpec rows: key, member, unit, bounds, live-tunable flag and a
// one-line doc; its default is the struct's own member initializer. Everything that reads,
// writes, checks, tunes or documents a parameter (the YAML loader and emitter, live tuning,
// `coxswain config doc`, the JSON Schemas) walks these tables, so names, bounds and defaults
// agree everywhere. Pure data: no I/O, no allocation, usable from the core.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace coxswain::core {

enum class ParamType : std::uint8_t { kReal, kInteger, kBool, kEnum, kText, kTextList };

[[nodiscard]] constexpr std::string_view param_type_name(ParamType t) {
  switch (t) {
    case ParamType::kReal:
      return "number";
    case ParamType::kInteger:
      return "integer";
    case ParamType::kBool:
      return "boolean";
    case ParamType::kEnum:
      return "enum";
    case ParamType::kText:
      return "string";
    case ParamType::kTextList:
      return "list of strings";
  }
  return "unknown";
}

/// One allowed value of an enumerated parameter: its name in files and its numeric value.
struct ParamChoice {
  std::string_view name;
  int value = 0;
  bool live = true;  // false: a file may choose it, live tuning may not
};

/// One parameter of struct S. `key` is relative to the struct's section; a dot nests a map in
/// the file ("score.goal_weight" is `score: {goal_weight: ...}`). Numbers, booleans and enums
/// travel as doubles through get/set (enums as their value, booleans as 0/1); text through
/// get_text/set_text, lists of text through get_list/set_list.
template <class S>
struct ParamSpec {
  std::string_view key;
  ParamType type = ParamType::kReal;
  std::string_view unit;  // "" when dimensionless
  double min = 0.0;       // inclusive bounds (numbers and integers)
  double max = 0.0;
  bool live = false;    // may be changed while the mission runs
  bool secret = false;  // text never written out (a token): printouts and recordings show "(set)"
  std::string_view doc;
  double (*get)(const S&) = nullptr;
  void (*set)(S&, double) = nullptr;
  std::span<const ParamChoice> choices{};  // kEnum
  std::string (*get_text)(const S&) = nullptr;
  void (*set_text)(S&, std::string_view) = nullptr;
  std::vector<std::string> (*get_list)(const S&) = nullptr;
  void (*set_list)(S&, const std::vector<std::string>&) = nullptr;

  /// The value a default-constructed struct holds: what ships unless a file says otherwise.
  [[nodiscard]] double default_value() const { return get(S{}); }
  [[nodiscard]] std::string default_text() const { return get_text(S{}); }
  [[nodiscard]] std::vector<std::string> default_list() const { return get_list(S{}); }
  /// The name of an enum value, or "" when it names none.
  [[nodiscard]] std::string_view choice_name(double value) const {
    for (const ParamChoice& c : choices) {
      if (static_cast<double>(c.value) == value) return c.name;
    }
    return {};
  }
};

namespace detail {
// s.*First.*Rest... : the member at a path of member pointers (a field of a nested struct).
template <auto First, auto... Rest, class T>
constexpr auto& member_at(T& s) {
  if constexpr (sizeof...(Rest) == 0) {
    return s.*First;
  } else {
    return member_at<Rest...>(s.*First);
  }
}
template <class S, auto... Path>
using member_type_t = std::remove_cvref_t<decltype(member_at<Path...>(std::declval<S&>()))>;
}  // namespace detail

/// A real number reached through `get`/`set`, which convert between the member and the file's
/// unit (a window kept in nanoseconds and written in seconds).
template <class S>
constexpr ParamSpec<S> scaled_param(std::string_view key, std::string_view unit, double min,
                                    double max, bool live, std::string_view doc,
                                    double (*get)(const S&), void (*set)(S&, double)) {
  ParamSpec<S> p{};
  p.key = key;
  p.type = ParamType::kReal;
  p.unit = unit;
  p.min = min;
  p.max = max;
  p.live = live;
  p.doc = doc;
  p.get = get;
  p.set = set;
  return p;
}

/// A real number at the member path `Path...` of S.
template <class S, auto... Path>
constexpr ParamSpec<S> real_param(std::string_view key, std::string_view unit, double min,
                                  double max, bool live, std::string_view doc) {
  using M = detail::member_type_t<S, Path...>;
  return scaled_param<S>(
      key, unit, min, max, live, doc,
      [](const S& s) { return static_cast<double>(detail::member_at<Path...>(s)); },
      [](S& s, double v) { detail::member_at<Path...>(s) = static_cast<M>(v); });
}

/// A whole number (a count, a pulse width) at the member path of S.
template <class S, auto... Path>
constexpr ParamSpec<S> int_param(std::string_view key, std::string_view unit, double min,
                                 double max, bool live, std::string_view doc) {
  ParamSpec<S> p = real_param<S, Path...>(key, unit, min, max, live, doc);
  p.type = ParamType::kInteger;
  return p;
}

/// A boolean at the member path of S.
template <class S, auto... Path>
constexpr ParamSpec<S> bool_param(std::string_view key, bool live, std::string_view doc) {
  ParamSpec<S> p{};
  p.key = key;
  p.type = ParamType::kBool;
  p.min = 0.0;
  p.max = 1.0;
  p.live = live;
  p.doc = doc;
  p.get = [](const S& s) { return detail::member_at<Path...>(s) ? 1.0 : 0.0; };
  p.set = [](S& s, double v) { detail::member_at<Path...>(s) = v != 0.0; };
  return p;
}

/// An enumeration at the member path of S; `choices` names every value (a static array).
template <class S, auto... Path>
constexpr ParamSpec<S> enum_param(std::string_view key, std::span<const ParamChoice> choices,
                                  bool live, std::string_view doc) {
  using E = detail::member_type_t<S, Path...>;
  ParamSpec<S> p{};
  p.key = key;
  p.type = ParamType::kEnum;
  p.min = 0.0;
  p.max = 0.0;
  for (const ParamChoice& c : choices) {
    if (static_cast<double>(c.value) > p.max) p.max = static_cast<double>(c.value);
  }
  p.live = live;
  p.doc = doc;
  p.choices = choices;
  p.get = [](const S& s) {
    return static_cast<double>(static_cast<int>(detail::member_at<Path...>(s)));
  };
  p.set = [](S& s, double v) {
    detail::member_at<Path...>(s) = static_cast<E>(static_cast<int>(v));
  };
  return p;
}

/// Text (a device path, an address) at the member path of S. Never live.
template <class S, auto... Path>
constexpr ParamSpec<S> text_param(std::string_view key, std::string_view doc) {
  ParamSpec<S> p{};
  p.key = key;
  p.type = ParamType::kText;
  p.doc = doc;
  p.get = [](const S&) { return 0.0; };
  p.set = [](S&, double) {};
  p.get_text = [](const S& s) { return std::string(detail::member_at<Path...>(s)); };
  p.set_text = [](S& s, std::string_view v) { detail::member_at<Path...>(s) = std::string(v); };
  return p;
}

/// A list of text (host names, origins) at the member path of S. Never live.
template <class S, auto... Path>
constexpr ParamSpec<S> text_list_param(std::string_view key, std::string_view doc) {
  ParamSpec<S> p{};
  p.key = key;
  p.type = ParamType::kTextList;
  p.doc = doc;
  p.get = [](const S&) { return 0.0; };
  p.set = [](S&, double) {};
  p.get_list = [](const S& s) { return detail::member_at<Path...>(s); };
  p.set_list = [](S& s, const std::vector<std::string>& v) { detail::member_at<Path...>(s) = v; };
  return p;
}

/// Text that is never written out (a token).
template <class S, auto... Path>
constexpr ParamSpec<S> secret_param(std::string_view key, std::string_view doc) {
  ParamSpec<S> p = text_param<S, Path...>(key, doc);
  p.secret = true;
  return p;
}

}  // namespace coxswain::core
