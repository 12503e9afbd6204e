// SPDX-License-Identifier: Apache-2.0
// The reference page, the JSON Schemas and the flat parameter list, all walked from the tables.
#include "coxswain/config/reference.hpp"

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <type_traits>

#include "coxswain/config/param_tables.hpp"

namespace coxswain::config {
namespace {

using nlohmann::json;

template <class S>
json default_of(const core::ParamSpec<S>& row) {
  switch (row.type) {
    case core::ParamType::kReal:
      return row.default_value();
    case core::ParamType::kInteger:
      return static_cast<long long>(std::llround(row.default_value()));
    case core::ParamType::kBool:
      return row.default_value() != 0.0;
    case core::ParamType::kEnum:
      return std::string(row.choice_name(row.default_value()));
    case core::ParamType::kText:
      return row.secret ? std::string{} : row.default_text();
    case core::ParamType::kTextList:
      return row.default_list();
  }
  return nullptr;
}

template <class S>
std::string default_text(const core::ParamSpec<S>& row) {
  const json d = default_of(row);
  return d.is_string() ? "`" + d.get<std::string>() + "`" : d.dump();
}

// The schema of one value.
template <class S>
json value_schema(const core::ParamSpec<S>& row) {
  json v;
  std::string description(row.doc);
  if (!row.unit.empty()) description += " [" + std::string(row.unit) + "]";
  if (row.live) description += " (live-tunable)";
  v["description"] = description;
  v["default"] = default_of(row);
  switch (row.type) {
    case core::ParamType::kReal:
      v["type"] = "number";
      v["minimum"] = row.min;
      v["maximum"] = row.max;
      break;
    case core::ParamType::kInteger:
      v["type"] = "integer";
      v["minimum"] = static_cast<long long>(row.min);
      v["maximum"] = static_cast<long long>(row.max);
      break;
    case core::ParamType::kBool:
      v["type"] = "boolean";
      break;
    case core::ParamType::kEnum: {
      v["type"] = "string";
      json names = json::array();
      for (const core::ParamChoice& c : row.choices) names.push_back(std::string(c.name));
      v["enum"] = names;
      break;
    }
    case core::ParamType::kText:
      v["type"] = "string";
      break;
    case core::ParamType::kTextList:
      v["type"] = "array";
      v["items"] = {{"type", "string"}};
      break;
  }
  return v;
}

json object_schema() {
  json o;
  o["type"] = "object";
  o["properties"] = json::object();
  o["additionalProperties"] = false;
  return o;
}

// Adds the rows of a table to an object schema, nesting maps at the dots of the keys.
template <class S>
void add_rows(json& object, std::span<const core::ParamSpec<S>> table) {
  for (const core::ParamSpec<S>& row : table) {
    json* at = &object;
    std::string_view key = row.key;
    for (std::size_t dot = key.find('.'); dot != std::string_view::npos; dot = key.find('.')) {
      const std::string sub(key.substr(0, dot));
      json& props = (*at)["properties"];
      if (!props.contains(sub)) props[sub] = object_schema();
      at = &props[sub];
      key = key.substr(dot + 1);
    }
    (*at)["properties"][std::string(key)] = value_schema(row);
  }
}

json geo_schema() {
  json g = object_schema();
  g["properties"]["lat_deg"] = {{"type", "number"}, {"minimum", -90}, {"maximum", 90}};
  g["properties"]["lon_deg"] = {{"type", "number"}, {"minimum", -180}, {"maximum", 180}};
  g["properties"]["height_m"] = {{"type", "number"}};
  g["required"] = {"lat_deg", "lon_deg"};
  return g;
}

json colour_names(bool with_unknown) {
  json names = json::array();
  for (const core::ParamChoice& c : colour_choices()) {
    if (with_unknown || c.value != 0) names.push_back(std::string(c.name));
  }
  return names;
}

json schema_root(std::string_view kind) {
  json s = object_schema();
  s["$schema"] = "https://json-schema.org/draft/2020-12/schema";
  s["title"] = "coxswain " + std::string(kind) + " file";
  s["properties"]["kind"] = {{"const", std::string(kind)}};
  s["required"] = json::array({"kind"});
  return s;
}

json boat_schema() {
  json s = schema_root("boat");
  add_rows(s, param_table<BoatConfig>());
  s["required"] = {"kind", "hull", "mounts", "actuators"};
  return s;
}

json devices_schema() {
  json s = schema_root("devices");
  const DevicesConfig devices{};
  for_each_devices_section(devices, [&](std::string_view key, const auto& section) {
    using S = std::remove_cvref_t<decltype(section)>;
    json sec = object_schema();
    add_rows(sec, param_table<S>());
    s["properties"][std::string(key)] = sec;
  });
  s["required"] = {"kind", "lidar", "imu", "gnss", "arduino", "camera"};
  return s;
}

json mission_schema() {
  json s = schema_root("mission");
  s["properties"]["name"] = {
      {"type", "string"}, {"pattern", "^[A-Za-z0-9_-]+$"}, {"description", "names the run folder"}};
  s["properties"]["origin"] = geo_schema();
  json frame = object_schema();
  frame["properties"]["zero_heading_deg"] = {
      {"type", "number"},
      {"minimum", -180},
      {"maximum", 180},
      {"description", "true heading of the course frame's 0 deg [deg]"}};
  s["properties"]["course_frame"] = frame;
  const MissionConfig mission{};
  for_each_mission_section(mission, [&](std::string_view key, const auto& section) {
    using S = std::remove_cvref_t<decltype(section)>;
    if (key.empty()) {
      add_rows(s, param_table<S>());
      return;
    }
    json sec = object_schema();
    add_rows(sec, param_table<S>());
    if constexpr (std::is_same_v<S, guidance::PlanningConfig>) {
      json corners = {{"type", "array"}, {"items", geo_schema()}, {"minItems", 3}};
      sec["properties"]["boundary"] = corners;
      json polygon = object_schema();
      polygon["properties"]["corners"] = corners;
      sec["properties"]["no_go"] = {{"type", "array"}, {"items", polygon}};
    }
    if constexpr (std::is_same_v<S, Course2Config>) {
      sec["properties"]["colours"] = {{"type", "array"},
                                      {"items", {{"enum", colour_names(false)}}},
                                      {"minItems", 1},
                                      {"maxItems", 8}};
    }
    s["properties"][std::string(key)] = sec;
  });
  json task = object_schema();
  json& p = task["properties"];
  p["type"] = {{"enum", {"hopping", "obstacle_course", "course1", "course2", "docking"}}};
  p["name"] = {{"type", "string"}};
  p["time_limit_s"] = {{"type", "number"}, {"minimum", 1}, {"maximum", 7200}};
  p["on_timeout"] = {{"enum", {"next_task", "finish"}}};
  p["style"] = {{"enum", {"kaboat2022", "course3"}}};
  p["dock_heading_deg"] = {{"type", "number"}, {"minimum", -180}, {"maximum", 180}};
  p["waypoints"] = {{"type", "array"}, {"items", geo_schema()}, {"maxItems", 64}};
  p["slips"] = {{"type", "array"}, {"items", geo_schema()}, {"maxItems", 8}};
  p["target_colour"] = {{"enum", colour_names(true)}};
  p["target_shape"] = {{"enum", {"unknown", "triangle", "rectangle", "cross", "circle"}}};
  task["required"] = {"type"};
  s["properties"]["tasks"] = {{"type", "array"}, {"items", task}, {"minItems", 1}};
  s["required"] = {"kind", "name", "origin", "tasks"};
  return s;
}

json vision_schema() {
  json s = schema_root("vision");
  add_rows(s, param_table<perception::VisionParams>());
  json range = object_schema();
  add_rows(range, param_table<perception::ColourRange>());
  range["required"] = {"colour"};
  s["properties"]["colours"] = {
      {"type", "array"}, {"items", range}, {"maxItems", perception::VisionParams::kMaxColours}};
  return s;
}

// Visits every (file kind, section, table) in a fixed order.
template <class F>
void for_each_table(F&& f) {
  f(std::string_view{"boat"}, std::string_view{}, BoatConfig{});
  const DevicesConfig devices{};
  for_each_devices_section(devices, [&](std::string_view key, const auto& section) {
    f(std::string_view{"devices"}, key, section);
  });
  const MissionConfig mission{};
  for_each_mission_section(mission, [&](std::string_view key, const auto& section) {
    f(std::string_view{"mission"}, key, section);
  });
  f(std::string_view{"vision"}, std::string_view{}, perception::VisionParams{});
  f(std::string_view{"vision"}, std::string_view{"colours[]"}, perception::ColourRange{});
}

std::string full_key(std::string_view section, std::string_view key) {
  return section.empty() ? std::string(key) : std::string(section) + "." + std::string(key);
}

}  // namespace

std::string parameter_reference_markdown() {
  std::ostringstream out;
  out << "# Parameter reference\n\n"
         "Generated from the parameter tables by `coxswain config doc`; every key, its type, "
         "unit, bounds and default (the value that ships when a file leaves the key out). "
         "Live-tunable keys can be changed while the mission runs (Foxglove's parameter panel) "
         "under the name `section.key` shown here. Dotted keys are nested maps in the file.\n";
  std::string_view last_kind;
  for_each_table([&](std::string_view kind, std::string_view section, const auto& value) {
    using S = std::remove_cvref_t<decltype(value)>;
    if (kind != last_kind) {
      out << "\n## " << kind << " file (`kind: " << kind << "`)\n";
      last_kind = kind;
    }
    out << "\n### "
        << (section.empty() ? std::string("top level") : "`" + std::string(section) + "`")
        << "\n\n| key | type | unit | range | default | live | meaning |\n"
           "| --- | --- | --- | --- | --- | --- | --- |\n";
    for (const core::ParamSpec<S>& row : param_table<S>()) {
      std::string range;
      if (row.type == core::ParamType::kReal || row.type == core::ParamType::kInteger) {
        std::ostringstream r;
        r << row.min << " .. " << row.max;
        range = r.str();
      } else if (row.type == core::ParamType::kEnum) {
        for (const core::ParamChoice& c : row.choices) {
          range += (range.empty() ? "" : ", ") + std::string(c.name);
        }
      }
      out << "| `" << full_key(section, row.key) << "` | " << core::param_type_name(row.type)
          << " | " << row.unit << " | " << range << " | " << default_text(row) << " | "
          << (row.live ? "yes" : "") << " | " << row.doc << " |\n";
    }
  });
  out << "\nStructure not in the tables: a mission file's `name`, `origin` (lat_deg, lon_deg, "
         "height_m), `course_frame.zero_heading_deg`, `course2.colours`, `planning.boundary` and "
         "`planning.no_go` (lists of corners) and `tasks` (type, "
         "name, time_limit_s, on_timeout, style, dock_heading_deg, waypoints, slips, "
         "target_colour, target_shape); a vision file's `colours` is a list of entries, one per "
         "colour, each with the `colours[]` keys above (`colour` required); see the shipped "
         "files in config/.\n";
  return out.str();
}

std::string parameters_json() {
  json list = json::array();
  for_each_table([&](std::string_view kind, std::string_view section, const auto& value) {
    using S = std::remove_cvref_t<decltype(value)>;
    for (const core::ParamSpec<S>& row : param_table<S>()) {
      json p;
      p["kind"] = std::string(kind);
      p["key"] = full_key(section, row.key);
      p["type"] = std::string(core::param_type_name(row.type));
      p["unit"] = std::string(row.unit);
      if (row.type == core::ParamType::kReal || row.type == core::ParamType::kInteger) {
        p["min"] = row.min;
        p["max"] = row.max;
      }
      p["default"] = default_of(row);
      p["live"] = row.live;
      p["doc"] = std::string(row.doc);
      if (row.type == core::ParamType::kEnum) {
        json names = json::array();
        for (const core::ParamChoice& c : row.choices) names.push_back(std::string(c.name));
        p["values"] = names;
      }
      list.push_back(p);
    }
  });
  return list.dump(2) + "\n";
}

std::optional<std::string> json_schema(std::string_view kind) {
  if (kind == "boat") return boat_schema().dump(2) + "\n";
  if (kind == "devices") return devices_schema().dump(2) + "\n";
  if (kind == "mission") return mission_schema().dump(2) + "\n";
  if (kind == "vision") return vision_schema().dump(2) + "\n";
  return std::nullopt;
}

}  // namespace coxswain::config
