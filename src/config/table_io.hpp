// SPDX-License-Identifier: Apache-2.0
#pragma once
// Reading and writing a parameter struct through its table: one reader and one emitter for
// every struct, so a row added to a table is read, checked and printed with no other change.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "coxswain/config/yaml_reader.hpp"
#include "coxswain/core/param_table.hpp"

namespace coxswain::config::detail {

template <class S>
void read_row(MapReader& m, S& s, const core::ParamSpec<S>& row, std::string_view key) {
  switch (row.type) {
    case core::ParamType::kReal:
      row.set(s, m.get<double>(key, row.get(s), {row.min, row.max}));
      return;
    case core::ParamType::kInteger: {
      const auto fallback = static_cast<long long>(std::llround(row.get(s)));
      const Bounds<long long> bounds{static_cast<long long>(row.min),
                                     static_cast<long long>(row.max)};
      row.set(s, static_cast<double>(m.get<long long>(key, fallback, bounds)));
      return;
    }
    case core::ParamType::kBool:
      row.set(s, m.get<bool>(key, row.get(s) != 0.0) ? 1.0 : 0.0);
      return;
    case core::ParamType::kText:
      row.set_text(s, m.get<std::string>(key, row.get_text(s)));
      return;
    case core::ParamType::kTextList: {
      if (!m.has(key)) return;
      std::vector<std::string> items;
      for (const YAML::Node& item : m.sequence(key)) {
        if (!item.IsScalar()) {
          m.error(key, "must be a list of strings");
          return;
        }
        items.push_back(item.Scalar());
      }
      row.set_list(s, items);
      return;
    }
    case core::ParamType::kEnum: {
      if (!m.has(key)) return;
      const std::string text = m.get<std::string>(key, std::string{});
      for (const core::ParamChoice& c : row.choices) {
        if (text == c.name) {
          row.set(s, static_cast<double>(c.value));
          return;
        }
      }
      std::string list;
      for (const core::ParamChoice& c : row.choices) {
        if (!list.empty()) list += ", ";
        list += c.name;
      }
      m.error(key, "must be one of: " + list + "; got '" + text + "'");
      return;
    }
  }
}

// Walks the rows of `table` under `prefix` ("" or "score."): `leaf(row, key)` for a key with no
// further dot, `group(sub, child_prefix)` once for each nested map (a dot in the key), in the
// order the rows first name them.
template <class S, class Leaf, class Group>
void visit_rows(std::span<const core::ParamSpec<S>> table, const std::string& prefix, Leaf&& leaf,
                Group&& group) {
  std::vector<std::string_view> opened;
  for (const core::ParamSpec<S>& row : table) {
    if (!row.key.starts_with(prefix)) continue;
    const std::string_view rest = row.key.substr(prefix.size());
    const std::size_t dot = rest.find('.');
    if (dot == std::string_view::npos) {
      leaf(row, rest);
      continue;
    }
    const std::string_view sub = rest.substr(0, dot);
    bool seen = false;
    for (std::string_view o : opened) seen |= o == sub;
    if (seen) continue;
    opened.push_back(sub);
    group(sub, prefix + std::string(sub) + ".");
  }
}

// Reads the rows under `prefix` from `m`; nested maps are opened once and checked for unknown
// keys.
template <class S>
void read_rows(MapReader& m, S& s, std::span<const core::ParamSpec<S>> table,
               const std::string& prefix) {
  visit_rows(
      table, prefix,
      [&](const core::ParamSpec<S>& row, std::string_view key) { read_row(m, s, row, key); },
      [&](std::string_view sub, const std::string& child_prefix) {
        if (auto child = m.map(sub)) {
          read_rows(*child, s, table, child_prefix);
          child->finish();
        }
      });
}

/// Reads every row of `table` from the map `m` into `s` (unknown keys are left to the caller's
/// `finish()`, so a section may hold hand-read keys too).
template <class S>
void read_table(MapReader& m, S& s, std::span<const core::ParamSpec<S>> table) {
  read_rows(m, s, table, std::string{});
}

template <class S>
void emit_row(YAML::Emitter& out, const S& s, const core::ParamSpec<S>& row, std::string_view key) {
  out << YAML::Key << std::string(key) << YAML::Value;
  switch (row.type) {
    case core::ParamType::kReal:
      out << row.get(s);
      return;
    case core::ParamType::kInteger:
      out << static_cast<long long>(std::llround(row.get(s)));
      return;
    case core::ParamType::kBool:
      out << (row.get(s) != 0.0);
      return;
    case core::ParamType::kEnum:
      out << std::string(row.choice_name(row.get(s)));
      return;
    case core::ParamType::kText: {
      const std::string text = row.get_text(s);
      // A secret is never written: this text goes into every recording.
      out << (row.secret ? std::string(text.empty() ? "" : "(set)") : text);
      return;
    }
    case core::ParamType::kTextList:
      out << YAML::Flow << row.get_list(s);
      return;
  }
}

template <class S>
void emit_rows(YAML::Emitter& out, const S& s, std::span<const core::ParamSpec<S>> table,
               const std::string& prefix) {
  visit_rows(
      table, prefix,
      [&](const core::ParamSpec<S>& row, std::string_view key) { emit_row(out, s, row, key); },
      [&](std::string_view sub, const std::string& child_prefix) {
        out << YAML::Key << std::string(sub) << YAML::Value << YAML::BeginMap;
        emit_rows(out, s, table, child_prefix);
        out << YAML::EndMap;
      });
}

/// Writes every row of `table` as keys of the map being emitted.
template <class S>
void emit_table(YAML::Emitter& out, const S& s, std::span<const core::ParamSpec<S>> table) {
  emit_rows(out, s, table, std::string{});
}

}  // namespace coxswain::config::detail
