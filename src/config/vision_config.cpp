// SPDX-License-Identifier: Apache-2.0
#include "coxswain/config/vision_config.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <string>

#include "coxswain/config/param_tables.hpp"
#include "table_io.hpp"

namespace coxswain::config {
namespace {

using perception::ColourRange;
using perception::VisionParams;

// The shortest text that reads back as the same double: a saved file loads back bit for bit.
std::string round_trip_text(double v) {
  std::array<char, 32> buf{};
  const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return ec == std::errc{} ? std::string(buf.data(), end) : std::to_string(v);
}

// A row's value as the file writes it.
template <class S>
std::string vision_value_text(const core::ParamSpec<S>& row, const S& s) {
  const double v = row.get(s);
  switch (row.type) {
    case core::ParamType::kInteger:
      return std::to_string(std::llround(v));
    case core::ParamType::kBool:
      return v != 0.0 ? "true" : "false";
    case core::ParamType::kEnum:
      return std::string(row.choice_name(v));
    default:
      return round_trip_text(v);
  }
}

}  // namespace

VisionParams read_vision(MapReader& r, const VisionParams& base) {
  VisionParams p = base;
  const std::vector<YAML::Node> colours = r.sequence("colours");
  if (r.has("colours")) p.colour_count = 0;
  for (std::size_t i = 0; i < colours.size(); ++i) {
    std::optional<MapReader> c = r.element(colours[i], i, "colours");
    if (!c) continue;
    ColourRange range;
    (void)c->require<std::string>("colour");  // a range without its colour is no range
    detail::read_table(*c, range, param_table<ColourRange>());
    c->finish();
    if (!p.add_colour(range)) c->error("", "more than VisionParams::kMaxColours colours");
  }
  detail::read_table(r, p, param_table<VisionParams>());
  return p;
}

std::optional<VisionParams> load_vision_file(const std::string& path, ConfigErrors& errors,
                                             const VisionParams& base) {
  const std::optional<YAML::Node> root = load_yaml_file(path, errors);
  if (!root) return std::nullopt;
  MapReader r(*root, path, "", errors);
  if (!r.valid()) return std::nullopt;
  const std::string kind = r.require<std::string>("kind");
  if (kind != "vision") r.error("kind", "must be 'vision', got '" + kind + "'");
  VisionParams p = read_vision(r, base);
  r.finish();
  if (!errors.empty()) return std::nullopt;
  if (const auto e = p.validate()) {
    errors.add({path, 0, "", *e});
    return std::nullopt;
  }
  return p;
}

void write_vision(const VisionParams& p, std::ostream& out) {
  out << "# Camera detector colour model and thresholds (kind: vision). Hue is OpenCV's 8-bit\n"
         "# convention, 0..179 (degrees / 2); saturation and value 0..255. A range with\n"
         "# h_min > h_max wraps through 180/0 (red). Pixels within background.reject_sigma of the\n"
         "# frame's water or sky colour belong to no colour, whatever the boxes say.\n"
         "kind: vision\n"
         "colours:\n";
  for (std::size_t i = 0; i < p.colour_count; ++i) {
    std::string entry;
    for (const core::ParamSpec<ColourRange>& row : param_table<ColourRange>()) {
      entry += (entry.empty() ? "" : ", ") + std::string(row.key) + ": " +
               vision_value_text(row, p.colours[i]);
    }
    out << "  - {" << entry << "}\n";
  }
  // Rows keyed "section.key" are written as a nested map, one section after the other.
  std::string_view section;
  for (const core::ParamSpec<VisionParams>& row : param_table<VisionParams>()) {
    const std::size_t dot = row.key.find('.');
    const std::string_view row_section =
        dot == std::string_view::npos ? std::string_view{} : row.key.substr(0, dot);
    if (row_section != section && !row_section.empty()) out << row_section << ":\n";
    section = row_section;
    out << (section.empty() ? "" : "  ")
        << row.key.substr(dot == std::string_view::npos ? 0 : dot + 1) << ": "
        << vision_value_text(row, p) << "   # " << row.doc << "\n";
  }
}

}  // namespace coxswain::config
