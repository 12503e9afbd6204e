// SPDX-License-Identifier: Apache-2.0
#include "sim/world/course.hpp"

#include <cmath>
#include <iomanip>
#include <set>
#include <sstream>

#include "coxswain/core/angles.hpp"
#include "sim/world/geometry.hpp"

namespace coxswain::sim::world {
namespace {

using config::Bounds;
using config::ConfigErrors;
using config::MapReader;

constexpr Bounds<double> kCoord{-100000.0, 100000.0};
constexpr Bounds<double> kHeading{-360.0, 360.0};

msg::Colour read_colour(MapReader& m, std::string_view key, msg::Colour fallback) {
  return m.get_enum(key, fallback,
                    {{"red", msg::Colour::kRed},
                     {"green", msg::Colour::kGreen},
                     {"blue", msg::Colour::kBlue},
                     {"yellow", msg::Colour::kYellow},
                     {"orange", msg::Colour::kOrange},
                     {"purple", msg::Colour::kPurple},
                     {"black", msg::Colour::kBlack},
                     {"white", msg::Colour::kWhite}});
}

msg::Shape read_shape(MapReader& m, std::string_view key, msg::Shape fallback) {
  return m.get_enum(key, fallback,
                    {{"triangle", msg::Shape::kTriangle},
                     {"rectangle", msg::Shape::kRectangle},
                     {"cross", msg::Shape::kCross},
                     {"circle", msg::Shape::kCircle}});
}

// A point written as [north_m, east_m], from its two items.
std::optional<core::NavPoint> parse_point_items(const YAML::Node& north, const YAML::Node& east) {
  try {
    core::NavPoint p{north.as<double>(), east.as<double>()};
    if (!std::isfinite(p.north_m) || !std::isfinite(p.east_m)) return std::nullopt;
    if (std::abs(p.north_m) > kCoord.max || std::abs(p.east_m) > kCoord.max) return std::nullopt;
    return p;
  } catch (const YAML::Exception&) {
    return std::nullopt;
  }
}

std::optional<core::NavPoint> parse_point(const YAML::Node& node) {
  if (!node.IsSequence() || node.size() != 2) return std::nullopt;
  return parse_point_items(node[0], node[1]);
}

core::NavPoint read_point(MapReader& m, std::string_view key) {
  if (!m.has(key)) {
    m.error(key, "is required: a point [north_m, east_m]");
    (void)m.sequence(key);
    return {};
  }
  // The items are read where they are: a new node holding them would merge the whole
  // document's node pool into its own, once per point (quadratic in the course's size).
  const std::vector<YAML::Node> items = m.sequence(key);
  const auto p = items.size() == 2 ? parse_point_items(items[0], items[1]) : std::nullopt;
  if (!p) {
    m.error(key, "must be a point [north_m, east_m] of two finite numbers");
    return {};
  }
  return *p;
}

std::vector<core::NavPoint> read_points(MapReader& m, std::string_view key, std::size_t min_count) {
  std::vector<core::NavPoint> out;
  const std::vector<YAML::Node> items = m.sequence(key, true);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const auto p = parse_point(items[i]);
    if (!p) {
      m.error(key, "item " + std::to_string(i) + " must be a point [north_m, east_m]");
      continue;
    }
    out.push_back(*p);
  }
  if (out.size() < min_count) {
    m.error(key, "needs at least " + std::to_string(min_count) + " points, got " +
                     std::to_string(out.size()));
  }
  return out;
}

void check_unique(MapReader& m, std::string_view key, std::set<std::string>& names,
                  const std::string& name) {
  if (name.empty()) return;
  if (!names.insert(name).second) m.error(key, "name '" + name + "' is used twice");
}

// ---- The `conditions:` block (the venue's sensor conditions). Kept apart from the rest of the
// format so other blocks can be added beside it without touching this one.
void read_conditions(MapReader& m, SensorConditions& c) {
  const auto opt = [](MapReader& r, std::string_view key, Bounds<double> b,
                      std::optional<double>& out) {
    if (r.has(key)) out = r.get<double>(key, 0.0, b);
  };
  if (auto g = m.map("gnss")) {
    opt(*g, "bias_mean_m", {0.0, 50.0}, c.gnss_bias_mean_m);
    opt(*g, "bias_direction_deg", {-360.0, 360.0}, c.gnss_bias_direction_deg);
    opt(*g, "bias_wander_sigma_m", {0.0, 20.0}, c.gnss_bias_wander_sigma_m);
    opt(*g, "bias_tau_s", {1.0, 1e5}, c.gnss_bias_tau_s);
    opt(*g, "bias_max_m", {0.0, 50.0}, c.gnss_bias_max_m);
    opt(*g, "noise_sigma_m", {0.0, 20.0}, c.gnss_noise_sigma_m);
    if (c.gnss_bias_mean_m && c.gnss_bias_max_m && *c.gnss_bias_mean_m > *c.gnss_bias_max_m) {
      g->error("bias_mean_m", "must not exceed bias_max_m");
    }
    g->finish();
  }
  if (auto k = m.map("camera")) {
    if (k->has("venue")) {
      // The camera's venue presets (sim/sensors/camera_sim.hpp; a test checks that each of these
      // names one).
      c.camera_venue = std::string(k->get_enum<std::string_view>("venue", "pool",
                                                                 {{"pool", "pool"},
                                                                  {"harbour", "harbour"},
                                                                  {"overcast", "overcast"},
                                                                  {"low_sun", "low_sun"}}));
    }
    if (k->has("glare")) c.camera_glare = k->get<bool>("glare", false);
    opt(*k, "glare_gain", {0.1, 10.0}, c.camera_glare_gain);
    opt(*k, "glare_saturation_loss", {0.0, 1.0}, c.camera_glare_saturation_loss);
    opt(*k, "sun_bearing_deg", {-360.0, 360.0}, c.camera_sun_bearing_deg);
    opt(*k, "sun_elevation_deg", {-10.0, 90.0}, c.camera_sun_elevation_deg);
    opt(*k, "sun_blob_radius_px", {0.0, 2000.0}, c.camera_sun_blob_radius_px);
    if (k->has("blur_kernel_px")) {
      const int px = k->get<int>("blur_kernel_px", 0, {0, 31});
      if (px != 0 && (px < 3 || px % 2 == 0)) {
        k->error("blur_kernel_px", "must be 0 (off) or odd 3..31");
      }
      c.camera_blur_kernel_px = px;
    }
    opt(*k, "noise_sigma", {0.0, 100.0}, c.camera_noise_sigma);
    k->finish();
  }
  m.finish();
}

void write_conditions(std::ostream& o, const SensorConditions& c) {
  if (!c.any()) return;
  o << "conditions:\n";
  const auto item = [&o](bool& first, std::string_view key, const auto& v) {
    if (!v) return;
    o << (first ? "{" : ", ") << key << ": " << *v;
    first = false;
  };
  bool first = true;
  o << "  gnss: ";
  item(first, "bias_mean_m", c.gnss_bias_mean_m);
  item(first, "bias_direction_deg", c.gnss_bias_direction_deg);
  item(first, "bias_wander_sigma_m", c.gnss_bias_wander_sigma_m);
  item(first, "bias_tau_s", c.gnss_bias_tau_s);
  item(first, "bias_max_m", c.gnss_bias_max_m);
  item(first, "noise_sigma_m", c.gnss_noise_sigma_m);
  o << (first ? "{}" : "}") << "\n";
  first = true;
  o << "  camera: ";
  if (c.camera_venue) {
    o << "{venue: " << *c.camera_venue;
    first = false;
  }
  if (c.camera_glare) {
    o << (first ? "{" : ", ") << "glare: " << (*c.camera_glare ? "true" : "false");
    first = false;
  }
  item(first, "glare_gain", c.camera_glare_gain);
  item(first, "glare_saturation_loss", c.camera_glare_saturation_loss);
  item(first, "sun_bearing_deg", c.camera_sun_bearing_deg);
  item(first, "sun_elevation_deg", c.camera_sun_elevation_deg);
  item(first, "sun_blob_radius_px", c.camera_sun_blob_radius_px);
  item(first, "blur_kernel_px", c.camera_blur_kernel_px);
  item(first, "noise_sigma", c.camera_noise_sigma);
  o << (first ? "{}" : "}") << "\n";
}

}  // namespace

std::string_view course_kind_name(CourseKind kind) {
  switch (kind) {
    case CourseKind::kHopping:
      return "hopping";
    case CourseKind::kObstacle:
      return "obstacle";
    case CourseKind::kDocking:
      return "docking";
    case CourseKind::kKaboat2026:
      return "kaboat2026";
  }
  return "hopping";
}

void build_dock_geometry(Dock& dock, double wall_height_m) {
  const core::NavPoint fwd = heading_unit(dock.entry_heading_deg);
  const core::NavPoint right = heading_unit(dock.entry_heading_deg + 90.0);
  const double hw = 0.5 * dock.width_m;
  const core::NavPoint mouth_left = add(dock.entrance, scale(right, -hw));
  const core::NavPoint mouth_right = add(dock.entrance, scale(right, hw));
  const core::NavPoint back_left = add(mouth_left, scale(fwd, dock.depth_m));
  const core::NavPoint back_right = add(mouth_right, scale(fwd, dock.depth_m));
  dock.walls.clear();
  const double fw = dock.finger_width_m;
  if (fw > 0.0) {
    const core::NavPoint out_left = scale(right, -fw);
    const core::NavPoint out_right = scale(right, fw);
    dock.walls.push_back(
        {{mouth_left, back_left, add(back_left, out_left), add(mouth_left, out_left), mouth_left},
         wall_height_m});
    dock.walls.push_back({{add(back_left, out_left), add(back_right, out_right)}, wall_height_m});
    dock.walls.push_back({{mouth_right, add(mouth_right, out_right), add(back_right, out_right),
                           back_right, mouth_right},
                          wall_height_m});
  } else {
    dock.walls.push_back({{mouth_left, back_left}, wall_height_m});
    dock.walls.push_back({{back_left, back_right}, wall_height_m});
    dock.walls.push_back({{back_right, mouth_right}, wall_height_m});
  }
  dock.marker.center = add(dock.entrance, scale(fwd, dock.depth_m));
  dock.marker.facing_deg = core::wrap_deg(dock.entry_heading_deg + 180.0);
}

void validate_world(const World& w, ConfigErrors& errors, double start_clearance_m) {
  auto issue = [&](const std::string& key, const std::string& message) {
    errors.add({w.file, 0, key, message});
  };
  std::size_t obstacles = w.buoys.size();
  for (const Wall& wall : w.walls) obstacles += wall.points.size() > 1 ? wall.points.size() - 1 : 0;
  for (const Dock& d : w.docks) {
    for (const Wall& wall : d.walls)
      obstacles += wall.points.size() > 1 ? wall.points.size() - 1 : 0;
  }
  if (obstacles > kMaxCourseObstacles) {
    issue("", "has " + std::to_string(obstacles) +
                  " obstacles (buoys and wall segments); a course "
                  "may have at most " +
                  std::to_string(kMaxCourseObstacles));
  }
  for (std::size_t i = 0; i < w.walls.size(); ++i) {
    const auto& pts = w.walls[i].points;
    const std::string key = "walls[" + std::to_string(i) + "]";
    if (pts.size() < 2) issue(key, "a wall needs at least 2 points");
    for (std::size_t k = 1; k < pts.size(); ++k) {
      if (core::distance_m(pts[k - 1], pts[k]) < 1e-6) {
        issue(key, "points " + std::to_string(k - 1) + " and " + std::to_string(k) +
                       " coincide (degenerate segment)");
      }
    }
  }
  for (std::size_t i = 0; i < w.buoys.size(); ++i) {
    if (!(w.buoys[i].radius_m > 0.0))
      issue("buoys[" + std::to_string(i) + "]", "radius must be > 0");
  }
  for (std::size_t i = 0; i < w.gates.size(); ++i) {
    if (core::distance_m(w.gates[i].left, w.gates[i].right) < 0.5) {
      issue("gates[" + std::to_string(i) + "]", "left and right must be at least 0.5 m apart");
    }
  }
  for (std::size_t i = 0; i < w.regions.size(); ++i) {
    if (w.regions[i].polygon.size() < 3) {
      issue("regions[" + std::to_string(i) + "]", "a region polygon needs at least 3 points");
    }
  }
  for (std::size_t i = 0; i < w.waypoints.size(); ++i) {
    if (!(w.waypoints[i].radius_m > 0.0)) {
      issue("waypoints[" + std::to_string(i) + "]", "radius must be > 0");
    }
  }
  // The start must be clear of every obstacle.
  const core::NavPoint s = w.start.position;
  auto near_wall = [&](const Wall& wall) {
    for (std::size_t k = 1; k < wall.points.size(); ++k) {
      if (point_segment_distance(s, wall.points[k - 1], wall.points[k]) < start_clearance_m) {
        return true;
      }
    }
    return false;
  };
  for (std::size_t i = 0; i < w.walls.size(); ++i) {
    if (near_wall(w.walls[i])) {
      issue("start", "lies on or within " + std::to_string(start_clearance_m) + " m of walls[" +
                         std::to_string(i) + "]");
    }
  }
  for (std::size_t i = 0; i < w.buoys.size(); ++i) {
    if (core::distance_m(s, w.buoys[i].center) < w.buoys[i].radius_m + start_clearance_m) {
      issue("start", "lies inside or next to buoys[" + std::to_string(i) + "]");
    }
  }
  for (std::size_t i = 0; i < w.docks.size(); ++i) {
    for (const Wall& wall : w.docks[i].walls) {
      if (near_wall(wall)) issue("start", "lies on a wall of docks[" + std::to_string(i) + "]");
    }
  }
  if (w.kind == CourseKind::kDocking && w.target_colour != msg::Colour::kUnknown) {
    bool found = false;
    for (const Dock& d : w.docks) {
      found = found || (d.marker.colour == w.target_colour && d.marker.shape == w.target_shape);
    }
    if (!found) issue("target", "no dock carries the target marker");
  }
  if (w.kind == CourseKind::kKaboat2026 && w.target_colour != msg::Colour::kUnknown) {
    // 2026 course 2: the target is the colour of an object (a buoy) to recognise.
    bool found = false;
    for (const Buoy& b : w.buoys) found = found || b.colour == w.target_colour;
    if (!found) issue("target", "no buoy has the target colour to recognise");
  }
}

Course load_course_file(const std::string& path, ConfigErrors& errors) {
  Course course;
  World& w = course.world;
  w.file = path;
  const auto doc = config::load_yaml_file(path, errors);
  if (!doc) return course;
  MapReader root(*doc, path, "", errors);
  if (!root.valid()) return course;
  const auto kind = root.require<std::string>("kind");
  if (!kind.empty() && kind != "course") {
    // Another kind of config file: its keys would only add noise.
    root.error("kind", "must be 'course' in this file, got '" + kind + "'");
    return course;
  }
  const std::size_t errors_before = errors.size();
  w.name = root.require<std::string>("name");
  w.kind = root.get_enum("type", CourseKind::kHopping,
                         {{"hopping", CourseKind::kHopping},
                          {"obstacle", CourseKind::kObstacle},
                          {"docking", CourseKind::kDocking},
                          {"kaboat2026", CourseKind::kKaboat2026}});
  if (!root.has("type"))
    root.error("type", "is required: hopping, obstacle, docking or kaboat2026");
  if (auto o = root.map("origin", true)) {
    w.origin.lat_deg = o->require<double>("lat_deg", {-90.0, 90.0});
    w.origin.lon_deg = o->require<double>("lon_deg", {-180.0, 180.0});
    w.origin.height_m = o->get("height_m", 0.0, {-1000.0, 10000.0});
    o->finish();
  }
  w.declination_deg = root.get("declination_deg", 0.0, {-180.0, 180.0});
  if (auto s = root.map("start", true)) {
    w.start.position = read_point(*s, "at");
    w.start.heading_deg = core::wrap_deg(s->require<double>("heading_deg", kHeading));
    s->finish();
  }
  const auto walls = root.sequence("walls");
  for (std::size_t i = 0; i < walls.size(); ++i) {
    auto m = root.element(walls[i], i, "walls");
    if (!m) continue;
    Wall wall;
    wall.points = read_points(*m, "points", 2);
    wall.height_m = m->get("height_m", 0.5, {0.01, 20.0});
    m->finish();
    w.walls.push_back(std::move(wall));
  }
  const auto buoys = root.sequence("buoys");
  for (std::size_t i = 0; i < buoys.size(); ++i) {
    auto m = root.element(buoys[i], i, "buoys");
    if (!m) continue;
    Buoy b;
    b.center = read_point(*m, "at");
    b.radius_m = m->get("radius_m", 0.25, {0.01, 10.0});
    b.height_m = m->get("height_m", 0.6, {0.01, 10.0});
    b.colour = read_colour(*m, "colour", msg::Colour::kOrange);
    m->finish();
    w.buoys.push_back(b);
  }
  std::set<std::string> names;
  const auto gates = root.sequence("gates");
  for (std::size_t i = 0; i < gates.size(); ++i) {
    auto m = root.element(gates[i], i, "gates");
    if (!m) continue;
    Gate g;
    g.name = m->require<std::string>("name");
    check_unique(*m, "name", names, g.name);
    g.left = read_point(*m, "left");
    g.right = read_point(*m, "right");
    m->finish();
    w.gates.push_back(g);
  }
  const auto docks = root.sequence("docks");
  for (std::size_t i = 0; i < docks.size(); ++i) {
    auto m = root.element(docks[i], i, "docks");
    if (!m) continue;
    Dock d;
    d.name = m->require<std::string>("name");
    check_unique(*m, "name", names, d.name);
    d.entrance = read_point(*m, "entrance");
    d.entry_heading_deg = core::wrap_deg(m->require<double>("entry_heading_deg", kHeading));
    d.width_m = m->get("width_m", 1.6, {0.2, 20.0});
    d.depth_m = m->get("depth_m", 2.0, {0.2, 20.0});
    d.finger_width_m = m->get("finger_width_m", 0.3, {0.0, 5.0});
    const double wall_height = m->get("wall_height_m", 0.5, {0.01, 20.0});
    if (auto mk = m->map("marker", true)) {
      d.marker.colour = read_colour(*mk, "colour", msg::Colour::kRed);
      d.marker.shape = read_shape(*mk, "shape", msg::Shape::kTriangle);
      if (!mk->has("colour")) mk->error("colour", "is required");
      if (!mk->has("shape")) mk->error("shape", "is required");
      d.marker.size_m = mk->get("size_m", 0.6, {0.05, 5.0});
      d.marker.height_m = mk->get("height_m", 1.0, {0.0, 10.0});
      mk->finish();
    }
    m->finish();
    build_dock_geometry(d, wall_height);
    w.docks.push_back(std::move(d));
  }
  const auto wps = root.sequence("waypoints");
  for (std::size_t i = 0; i < wps.size(); ++i) {
    auto m = root.element(wps[i], i, "waypoints");
    if (!m) continue;
    Waypoint wp;
    wp.name = m->require<std::string>("name");
    check_unique(*m, "name", names, wp.name);
    wp.position = read_point(*m, "at");
    wp.radius_m = m->get("radius_m", 2.0, {0.1, 100.0});
    m->finish();
    w.waypoints.push_back(wp);
  }
  const auto regions = root.sequence("regions");
  for (std::size_t i = 0; i < regions.size(); ++i) {
    auto m = root.element(regions[i], i, "regions");
    if (!m) continue;
    Region r;
    r.name = m->require<std::string>("name");
    check_unique(*m, "name", names, r.name);
    r.polygon = read_points(*m, "polygon", 3);
    r.time_limit_s = m->get("time_limit_s", 0.0, {0.0, 86400.0});
    m->finish();
    w.regions.push_back(std::move(r));
  }
  if (auto t = root.map("target")) {
    w.target_colour = read_colour(*t, "colour", msg::Colour::kUnknown);
    w.target_shape = read_shape(*t, "shape", msg::Shape::kUnknown);
    if (!t->has("colour")) t->error("colour", "is required");
    if (w.kind == CourseKind::kDocking && !t->has("shape")) t->error("shape", "is required");
    t->finish();
  }
  if (auto e = root.map("environment")) course.environment = dynamics::read_environment(*e);
  if (auto d = root.map("dynamics")) course.dynamics = dynamics::read_dynamics_overrides(*d);
  if (auto c = root.map("conditions")) read_conditions(*c, w.conditions);
  root.finish();
  if (w.kind == CourseKind::kKaboat2026 && w.regions.size() != 3) {
    root.error("regions", "a kaboat2026 course needs exactly 3 regions (course 1, 2, 3)");
  }
  if (w.kind == CourseKind::kDocking && w.docks.empty()) {
    root.error("docks", "a docking course needs at least one dock");
  }
  if (w.kind == CourseKind::kHopping && w.waypoints.empty()) {
    root.error("waypoints", "a hopping course needs at least one waypoint");
  }
  // Geometry is checked only on a structurally sound file, so its messages are not noise.
  if (errors.size() == errors_before) validate_world(w, errors);
  return course;
}

World load_course(const std::string& path, ConfigErrors& errors) {
  return load_course_file(path, errors).world;
}

namespace {
std::string pt(core::NavPoint p) {
  std::ostringstream s;
  s << std::setprecision(12) << "[" << p.north_m << ", " << p.east_m << "]";
  return s.str();
}
}  // namespace

std::string to_course_yaml(const Course& course) {
  const World& w = course.world;
  std::ostringstream o;
  o << std::setprecision(12);
  o << "# SPDX-License-Identifier: Apache-2.0\n"
    << "# Positions are [north_m, east_m] in metres in the navigation frame of `origin`;\n"
    << "# headings in degrees, 0 = north, clockwise.\n"
    << "kind: course\n"
    << "name: " << w.name << "\n"
    << "type: " << course_kind_name(w.kind) << "\n"
    << "origin: {lat_deg: " << w.origin.lat_deg << ", lon_deg: " << w.origin.lon_deg
    << ", height_m: " << w.origin.height_m << "}\n"
    << "declination_deg: " << w.declination_deg << "\n"
    << "start: {at: " << pt(w.start.position) << ", heading_deg: " << w.start.heading_deg << "}\n";
  if (w.target_colour != msg::Colour::kUnknown) {
    o << "target: {colour: " << msg::colour_name(w.target_colour);
    if (w.target_shape != msg::Shape::kUnknown) o << ", shape: " << msg::shape_name(w.target_shape);
    o << "}\n";
  }
  o << "walls:\n";
  for (const Wall& wall : w.walls) {
    o << "  - {height_m: " << wall.height_m << ", points: [";
    for (std::size_t i = 0; i < wall.points.size(); ++i) o << (i ? ", " : "") << pt(wall.points[i]);
    o << "]}\n";
  }
  o << "buoys:\n";
  for (const Buoy& b : w.buoys) {
    o << "  - {at: " << pt(b.center) << ", radius_m: " << b.radius_m << ", height_m: " << b.height_m
      << ", colour: " << msg::colour_name(b.colour) << "}\n";
  }
  o << "gates:\n";
  for (const Gate& g : w.gates) {
    o << "  - {name: " << g.name << ", left: " << pt(g.left) << ", right: " << pt(g.right) << "}\n";
  }
  o << "docks:\n";
  for (const Dock& d : w.docks) {
    const double wall_height = d.walls.empty() ? 0.5 : d.walls.front().height_m;
    o << "  - {name: " << d.name << ", entrance: " << pt(d.entrance)
      << ", entry_heading_deg: " << d.entry_heading_deg << ", width_m: " << d.width_m
      << ", depth_m: " << d.depth_m << ", finger_width_m: " << d.finger_width_m
      << ", wall_height_m: " << wall_height
      << ",\n     marker: {colour: " << msg::colour_name(d.marker.colour)
      << ", shape: " << msg::shape_name(d.marker.shape) << ", size_m: " << d.marker.size_m
      << ", height_m: " << d.marker.height_m << "}}\n";
  }
  o << "waypoints:\n";
  for (const Waypoint& wp : w.waypoints) {
    o << "  - {name: " << wp.name << ", at: " << pt(wp.position) << ", radius_m: " << wp.radius_m
      << "}\n";
  }
  o << "regions:\n";
  for (const Region& r : w.regions) {
    o << "  - {name: " << r.name << ", time_limit_s: " << r.time_limit_s << ", polygon: [";
    for (std::size_t i = 0; i < r.polygon.size(); ++i) o << (i ? ", " : "") << pt(r.polygon[i]);
    o << "]}\n";
  }
  const dynamics::Environment& e = course.environment;
  o << "environment:\n"
    << "  current: {speed_mps: " << e.current_speed_mps << ", toward_deg: " << e.current_toward_deg
    << "}\n"
    << "  wind: {speed_mps: " << e.wind_speed_mps << ", from_deg: " << e.wind_from_deg
    << ", gust_std_mps: " << e.gust_std_mps << ", gust_time_s: " << e.gust_time_s << "}\n"
    << "  waves: {force_n: " << e.wave_force_n << ", period_s: " << e.wave_period_s << "}\n";
  write_conditions(o, w.conditions);
  bool any = course.dynamics.length_m > 0.0;
  for (bool g : course.dynamics.given) any = any || g;
  if (any) {
    o << "dynamics:\n";
    if (course.dynamics.length_m > 0.0) {
      o << "  scale_from_length_m: " << course.dynamics.length_m << "\n";
    }
    for (std::size_t i = 0; i < std::size(dynamics::kParamFields); ++i) {
      if (course.dynamics.given[i]) {
        o << "  " << dynamics::kParamFields[i].key << ": " << course.dynamics.value[i] << "\n";
      }
    }
  }
  return o.str();
}

}  // namespace coxswain::sim::world
