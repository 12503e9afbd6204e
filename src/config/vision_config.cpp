// SPDX-License-Identifier: Apache-2.0
#include "coxswain/config/vision_config.hpp"

#include <array>
#include <charconv>
#include <string>

namespace coxswain::config {
namespace {

using perception::VisionParams;

constexpr std::array<msg::Colour, 8> kColours{
    msg::Colour::kRed,  msg::Colour::kOrange, msg::Colour::kYellow, msg::Colour::kGreen,
    msg::Colour::kBlue, msg::Colour::kPurple, msg::Colour::kBlack,  msg::Colour::kWhite};

std::uint8_t byte(MapReader& r, std::string_view key, std::uint8_t fallback, int max) {
  return static_cast<std::uint8_t>(r.get<int>(key, fallback, {0, max}));
}

// The shortest text that reads back as the same double: a saved file loads back bit for bit.
std::string num(double v) {
  std::array<char, 32> buf{};
  const auto [end, ec] = std::to_chars(buf.data(), buf.data() + buf.size(), v);
  return ec == std::errc{} ? std::string(buf.data(), end) : std::to_string(v);
}

}  // namespace

VisionParams read_vision(MapReader& r, const VisionParams& base) {
  VisionParams p = base;
  const std::vector<YAML::Node> colours = r.sequence("colours");
  if (r.has("colours")) p.colour_count = 0;
  for (std::size_t i = 0; i < colours.size(); ++i) {
    std::optional<MapReader> c = r.element(colours[i], i, "colours");
    if (!c) continue;
    perception::ColourRange range;
    const std::string name = c->require<std::string>("colour");
    for (const msg::Colour k : kColours) {
      if (name == msg::colour_name(k)) range.colour = k;
    }
    if (range.colour == msg::Colour::kUnknown) {
      c->error("colour", "must be one of red, orange, yellow, green, blue, purple, black, white");
    }
    range.hsv.h_min = byte(*c, "h_min", range.hsv.h_min, 179);
    range.hsv.h_max = byte(*c, "h_max", range.hsv.h_max, 179);
    range.hsv.s_min = byte(*c, "s_min", range.hsv.s_min, 255);
    range.hsv.s_max = byte(*c, "s_max", range.hsv.s_max, 255);
    range.hsv.v_min = byte(*c, "v_min", range.hsv.v_min, 255);
    range.hsv.v_max = byte(*c, "v_max", range.hsv.v_max, 255);
    range.markers = c->get<bool>("markers", range.markers);
    range.buoys = c->get<bool>("buoys", range.buoys);
    c->finish();
    if (!p.add_colour(range)) c->error("", "more than VisionParams::kMaxColours colours");
  }
  p.blur_kernel_px = r.get<int>("blur_kernel_px", p.blur_kernel_px);
  p.open_kernel_px = r.get<int>("open_kernel_px", p.open_kernel_px);
  p.close_kernel_px = r.get<int>("close_kernel_px", p.close_kernel_px);
  p.min_area_fraction = r.get<double>("min_area_fraction", p.min_area_fraction);
  p.buoy_min_area_fraction = r.get<double>("buoy_min_area_fraction", p.buoy_min_area_fraction);
  p.buoy_min_solidity = r.get<double>("buoy_min_solidity", p.buoy_min_solidity);
  p.edge_margin_px = r.get<int>("edge_margin_px", p.edge_margin_px);
  p.buoy_reject_edge = r.get<bool>("buoy_reject_edge", p.buoy_reject_edge);
  if (std::optional<MapReader> b = r.map("background")) {
    perception::BackgroundParams& g = p.background;
    g.enabled = b->get<bool>("enabled", g.enabled);
    g.strips = b->get<int>("strips", g.strips);
    g.sample_step_px = b->get<int>("sample_step_px", g.sample_step_px);
    g.min_share = b->get<double>("min_share", g.min_share);
    g.reject_sigma = b->get<double>("reject_sigma", g.reject_sigma);
    g.min_sigma = b->get<double>("min_sigma", g.min_sigma);
    g.max_sigma = b->get<double>("max_sigma", g.max_sigma);
    g.max_saturation = b->get<int>("max_saturation", g.max_saturation);
    b->finish();
  }
  if (std::optional<MapReader> s = r.map("shape")) {
    perception::ShapeParams& h = p.shape;
    h.approx_epsilon_fraction =
        s->get<double>("approx_epsilon_fraction", h.approx_epsilon_fraction);
    h.convex_min_solidity = s->get<double>("convex_min_solidity", h.convex_min_solidity);
    h.cross_max_solidity = s->get<double>("cross_max_solidity", h.cross_max_solidity);
    h.cross_min_solidity = s->get<double>("cross_min_solidity", h.cross_min_solidity);
    h.cross_min_defect_depth = s->get<double>("cross_min_defect_depth", h.cross_min_defect_depth);
    h.triangle_max_extent = s->get<double>("triangle_max_extent", h.triangle_max_extent);
    h.rectangle_min_extent = s->get<double>("rectangle_min_extent", h.rectangle_min_extent);
    h.circle_min_circularity = s->get<double>("circle_min_circularity", h.circle_min_circularity);
    h.circle_max_extent = s->get<double>("circle_max_extent", h.circle_max_extent);
    h.min_fill_ratio = s->get<double>("min_fill_ratio", h.min_fill_ratio);
    h.island_min_hole_fraction =
        s->get<double>("island_min_hole_fraction", h.island_min_hole_fraction);
    s->finish();
  }
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
    const perception::ColourRange& c = p.colours[i];
    out << "  - {colour: " << msg::colour_name(c.colour) << ", h_min: " << int{c.hsv.h_min}
        << ", h_max: " << int{c.hsv.h_max} << ", s_min: " << int{c.hsv.s_min}
        << ", s_max: " << int{c.hsv.s_max} << ", v_min: " << int{c.hsv.v_min}
        << ", v_max: " << int{c.hsv.v_max} << ", markers: " << (c.markers ? "true" : "false")
        << ", buoys: " << (c.buoys ? "true" : "false") << "}\n";
  }
  const perception::BackgroundParams& g = p.background;
  const perception::ShapeParams& s = p.shape;
  out << "blur_kernel_px: " << p.blur_kernel_px << "          # Gaussian pre-blur, odd; 0 = off\n"
      << "open_kernel_px: " << p.open_kernel_px << "          # opening removes specks; 0 = off\n"
      << "close_kernel_px: " << p.close_kernel_px << "         # closing fills pinholes; 0 = off\n"
      << "min_area_fraction: " << num(p.min_area_fraction) << "   # smallest marker, of the frame\n"
      << "buoy_min_area_fraction: " << num(p.buoy_min_area_fraction) << "\n"
      << "buoy_min_solidity: " << num(p.buoy_min_solidity) << "\n"
      << "edge_margin_px: " << p.edge_margin_px << "          # shapes this close to the border "
      << "are cut\n"
      << "buoy_reject_edge: " << (p.buoy_reject_edge ? "true" : "false") << "\n"
      << "background:                 # per-frame water and sky model, strip by strip\n"
      << "  enabled: " << (g.enabled ? "true" : "false") << "\n"
      << "  strips: " << g.strips << "   # horizontal strips, each with its own model\n"
      << "  sample_step_px: " << g.sample_step_px << "\n"
      << "  min_share: " << num(g.min_share) << "   # the dominant colour's share of the band\n"
      << "  reject_sigma: " << num(g.reject_sigma) << "   # Mahalanobis radius rejected\n"
      << "  min_sigma: " << num(g.min_sigma) << "   # grey levels\n"
      << "  max_sigma: " << num(g.max_sigma) << "   # grey levels\n"
      << "  max_saturation: " << g.max_saturation
      << "   # 0..255; a more saturated band is a marker up close\n"
      << "shape:\n"
      << "  approx_epsilon_fraction: " << num(s.approx_epsilon_fraction) << "\n"
      << "  convex_min_solidity: " << num(s.convex_min_solidity) << "\n"
      << "  cross_max_solidity: " << num(s.cross_max_solidity) << "\n"
      << "  cross_min_solidity: " << num(s.cross_min_solidity) << "\n"
      << "  cross_min_defect_depth: " << num(s.cross_min_defect_depth) << "\n"
      << "  triangle_max_extent: " << num(s.triangle_max_extent) << "\n"
      << "  rectangle_min_extent: " << num(s.rectangle_min_extent) << "\n"
      << "  circle_min_circularity: " << num(s.circle_min_circularity) << "\n"
      << "  circle_max_extent: " << num(s.circle_max_extent) << "\n"
      << "  min_fill_ratio: " << num(s.min_fill_ratio) << "\n"
      << "  island_min_hole_fraction: " << num(s.island_min_hole_fraction) << "\n";
}

}  // namespace coxswain::config
