// SPDX-License-Identifier: Apache-2.0
#include "sim/world/generator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "sim/rng/rng.hpp"
#include "sim/world/geometry.hpp"

namespace coxswain::sim::world {
namespace {

using core::NavPoint;

// Millimetre rounding so a generated course survives the YAML round trip exactly.
double mm(double v) { return std::round(v * 1000.0) / 1000.0; }
NavPoint mm(NavPoint p) { return {mm(p.north_m), mm(p.east_m)}; }

Wall rectangle_wall(double n0, double n1, double e0, double e1, double height_m = 0.5) {
  return {{{n0, e0}, {n0, e1}, {n1, e1}, {n1, e0}, {n0, e0}}, height_m};
}

std::vector<NavPoint> rectangle(double n0, double n1, double e0, double e1) {
  return {{n0, e0}, {n0, e1}, {n1, e1}, {n1, e0}};
}

constexpr std::array<msg::Colour, 3> kDockColours{msg::Colour::kRed, msg::Colour::kGreen,
                                                  msg::Colour::kBlue};
constexpr std::array<msg::Shape, 3> kDockShapes{msg::Shape::kTriangle, msg::Shape::kCross,
                                                msg::Shape::kCircle};

// Three docks side by side on a north wall at `back_n`, 3.1 m apart, mouths facing south.
// Markers are three distinct colour/shape pairs; the target is one of them.
void add_docks(World& w, Rng& rng, double back_n, double center_e, bool draw_target) {
  std::array<std::size_t, 3> colour_order{0, 1, 2};
  std::array<std::size_t, 3> shape_order{0, 1, 2};
  for (std::size_t i = 2; i > 0; --i) {
    std::swap(colour_order[i], colour_order[rng.below(i + 1)]);
    std::swap(shape_order[i], shape_order[rng.below(i + 1)]);
  }
  const char* names[] = {"A", "B", "C"};
  for (std::size_t i = 0; i < 3; ++i) {
    Dock d;
    d.name = names[i];
    d.depth_m = 2.0;
    d.width_m = 1.6;
    d.entry_heading_deg = 0.0;
    d.entrance = mm(NavPoint{back_n - d.depth_m, center_e + (static_cast<double>(i) - 1.0) * 3.1});
    d.marker.colour = kDockColours[colour_order[i]];
    d.marker.shape = kDockShapes[shape_order[i]];
    d.marker.size_m = 0.6;
    d.marker.height_m = 1.0;
    build_dock_geometry(d);
    w.docks.push_back(d);
  }
  if (draw_target) {
    const Dock& t = w.docks[rng.below(3)];
    w.target_colour = t.marker.colour;
    w.target_shape = t.marker.shape;
  }
}

// Buoys scattered in a box, apart from each other and from keep-out points.
void scatter_buoys(World& w, Rng& rng, int count, double n0, double n1, double e0, double e1,
                   double min_gap_m, const std::vector<NavPoint>& keep_out, double keep_out_m) {
  int placed = 0;
  for (int tries = 0; placed < count && tries < count * 200; ++tries) {
    Buoy b;
    b.radius_m = mm(rng.uniform(0.2, 0.35));
    b.center = mm(NavPoint{rng.uniform(n0, n1), rng.uniform(e0, e1)});
    b.height_m = 0.6;
    b.colour = rng.below(2) == 0 ? msg::Colour::kOrange : msg::Colour::kYellow;
    bool ok = true;
    for (const Buoy& o : w.buoys) {
      ok = ok && core::distance_m(o.center, b.center) >= o.radius_m + b.radius_m + min_gap_m;
    }
    for (const NavPoint& k : keep_out) ok = ok && core::distance_m(k, b.center) >= keep_out_m;
    if (!ok) continue;
    w.buoys.push_back(b);
    ++placed;
  }
}

World draw_hopping(Rng& rng) {
  World w;
  w.kind = CourseKind::kHopping;
  const double length = 40.0;
  const double width = 30.0;
  w.walls.push_back(rectangle_wall(-3.0, length, -0.5 * width, 0.5 * width));
  w.start = {{0.0, 0.0}, 0.0};
  const int count = 3 + static_cast<int>(rng.below(2));
  std::vector<NavPoint> pts;
  for (int tries = 0; static_cast<int>(pts.size()) < count && tries < 1000; ++tries) {
    const NavPoint p = mm(NavPoint{rng.uniform(8.0, length - 5.0),
                                   rng.uniform(-0.5 * width + 4.0, 0.5 * width - 4.0)});
    bool ok = true;
    for (const NavPoint& q : pts) ok = ok && core::distance_m(p, q) >= 8.0;
    if (ok) pts.push_back(p);
  }
  for (std::size_t i = 0; i < pts.size(); ++i) {
    w.waypoints.push_back({"wp" + std::to_string(i + 1), pts[i], 2.0});
  }
  w.regions.push_back({"hopping", rectangle(-3.0, length, -0.5 * width, 0.5 * width), 300.0});
  return w;
}

World draw_obstacle(Rng& rng, bool narrow) {
  World w;
  w.kind = CourseKind::kObstacle;
  const double length = narrow ? 30.0 : 40.0;
  const double width = narrow ? 8.0 : 14.0;
  const double hw = 0.5 * width;
  w.walls.push_back(rectangle_wall(-3.0, length + 3.0, -hw, hw));
  w.start = {{0.0, 0.0}, 0.0};
  w.gates.push_back({"start", {3.0, -1.5}, {3.0, 1.5}});
  w.gates.push_back({"finish", {length, -1.5}, {length, 1.5}});
  const int count =
      narrow ? 6 + static_cast<int>(rng.below(4)) : 12 + static_cast<int>(rng.below(6));
  scatter_buoys(w, rng, count, 6.0, length - 3.0, -hw + 0.5, hw - 0.5, 1.0,
                {w.gates[0].left, w.gates[0].right, w.gates[1].left, w.gates[1].right}, 1.5);
  w.regions.push_back(
      {narrow ? "preliminary" : "final", rectangle(-3.0, length + 3.0, -hw, hw), 300.0});
  return w;
}

// Buoys along a polyline, `spacing_m` apart centre to centre (from its first point, the last
// point always included): a wall the lidar sees as separate returns.
void buoy_line(World& w, const std::vector<NavPoint>& pts, double spacing_m, double radius_m,
               msg::Colour colour) {
  auto put = [&](NavPoint p) {
    for (const Buoy& b : w.buoys) {
      if (core::distance_m(b.center, p) < 0.5 * spacing_m) return;  // a shared corner
    }
    Buoy b;
    b.center = mm(p);
    b.radius_m = radius_m;
    b.height_m = 0.6;
    b.colour = colour;
    w.buoys.push_back(b);
  };
  for (std::size_t k = 1; k < pts.size(); ++k) {
    const double len = core::distance_m(pts[k - 1], pts[k]);
    const int n = std::max(1, static_cast<int>(std::ceil(len / spacing_m)));
    for (int i = 0; i <= n; ++i) {
      put(add(pts[k - 1], scale(sub(pts[k], pts[k - 1]), static_cast<double>(i) / n)));
    }
  }
}

// The shared frame of the obstacle families: a 40 m x 20 m field, the start gate 3 m ahead of
// the start, the finish gate at the far end, both on the straight line east = 0.
World obstacle_family_field(double length, double hw) {
  World w;
  w.kind = CourseKind::kObstacle;
  w.walls.push_back(rectangle_wall(-3.0, length + 3.0, -hw, hw));
  w.start = {{0.0, 0.0}, 0.0};
  w.gates.push_back({"start", {3.0, -1.5}, {3.0, 1.5}});
  w.gates.push_back({"finish", {length, -1.5}, {length, 1.5}});
  w.regions.push_back({"final", rectangle(-3.0, length + 3.0, -hw, hw), 300.0});
  return w;
}

World draw_dead_end(Rng& rng) {
  const double length = 40.0;
  const double hw = 10.0;
  World w = obstacle_family_field(length, hw);
  const double c = mm(rng.uniform(-1.5, 1.5));       // the U's centre line (east)
  const double a = mm(rng.uniform(2.5, 3.5));        // its inner half-width
  const double mouth = mm(rng.uniform(11.0, 15.0));  // north of its open end
  const double back = mm(mouth + rng.uniform(5.0, 8.0));
  const double side = rng.below(2) == 0 ? -1.0 : 1.0;  // the wing closes this side
  const bool buoys = rng.below(2) == 0;
  const std::vector<NavPoint> u{{mouth, c - a}, {back, c - a}, {back, c + a}, {mouth, c + a}};
  const std::vector<NavPoint> wing{{back, c + side * a}, {back, side * hw}};
  if (buoys) {
    const msg::Colour colour = rng.below(2) == 0 ? msg::Colour::kOrange : msg::Colour::kYellow;
    buoy_line(w, u, 0.8, 0.25, colour);
    buoy_line(w, wing, 0.8, 0.25, colour);
  } else {
    w.walls.push_back({u, 0.5});
    w.walls.push_back({wing, 0.5});
  }
  // A few buoys in the open water past the enclosure.
  scatter_buoys(w, rng, 2 + static_cast<int>(rng.below(4)), back + 2.5, length - 3.0, -hw + 1.0,
                hw - 1.0, 1.5, {w.gates[1].left, w.gates[1].right}, 2.0);
  return w;
}

World draw_gap_wall(Rng& rng) {
  const double length = 40.0;
  const double hw = 10.0;
  World w = obstacle_family_field(length, hw);
  const double line_n = mm(rng.uniform(14.0, 24.0));
  const double gap = mm(rng.uniform(2.4, 3.2));
  const double side = rng.below(2) == 0 ? -1.0 : 1.0;
  const double gap_c = mm(side * rng.uniform(4.0, hw - 1.0 - 0.5 * gap));
  const double g0 = gap_c - 0.5 * gap;
  const double g1 = gap_c + 0.5 * gap;
  const bool buoys = rng.below(2) == 0;
  const std::vector<NavPoint> west{{line_n, -hw}, {line_n, g0}};
  const std::vector<NavPoint> east{{line_n, g1}, {line_n, hw}};
  if (buoys) {
    const msg::Colour colour = rng.below(2) == 0 ? msg::Colour::kOrange : msg::Colour::kYellow;
    // From the gap outward, so the gap keeps its drawn width.
    buoy_line(w, {west[1], west[0]}, 0.8, 0.25, colour);
    buoy_line(w, east, 0.8, 0.25, colour);
  } else {
    w.walls.push_back({west, 0.5});
    w.walls.push_back({east, 0.5});
  }
  const NavPoint gap_mid{line_n, gap_c};
  scatter_buoys(w, rng, 2 + static_cast<int>(rng.below(3)), 6.0, line_n - 3.0, -hw + 1.0, hw - 1.0,
                1.5, {w.gates[0].left, w.gates[0].right, gap_mid}, 3.0);
  scatter_buoys(w, rng, 2 + static_cast<int>(rng.below(3)), line_n + 3.0, length - 3.0, -hw + 1.0,
                hw - 1.0, 1.5, {w.gates[1].left, w.gates[1].right, gap_mid}, 3.0);
  return w;
}

World draw_docking(Rng& rng) {
  World w;
  w.kind = CourseKind::kDocking;
  // The 2022 pool: about 35 m x 9.3 m, docks on the far (north) end.
  const double length = 35.0;
  const double hw = 0.5 * 9.3;
  w.walls.push_back(rectangle_wall(0.0, length, -hw, hw));
  w.start = {{2.0, mm(rng.uniform(-1.5, 1.5))}, 0.0};
  add_docks(w, rng, length, 0.0, true);
  for (const Dock& d : w.docks) {
    w.waypoints.push_back({"decision_" + d.name, mm(add(d.entrance, NavPoint{-4.0, 0.0})), 1.0});
  }
  // A few buoys in the open water on the way (none near the docks).
  scatter_buoys(w, rng, static_cast<int>(rng.below(4)), 8.0, length - 10.0, -hw + 1.0, hw - 1.0,
                1.5, {w.start.position}, 3.0);
  w.regions.push_back({"docking", rectangle(0.0, length, -hw, hw), 300.0});
  return w;
}

World draw_2026(Rng& rng) {
  World w;
  w.kind = CourseKind::kKaboat2026;
  w.walls.push_back(rectangle_wall(-3.0, 72.0, -12.0, 12.0));
  w.start = {{0.0, 0.0}, 0.0};
  // Course 1: a buoy field before the first waypoint.
  const NavPoint wp1{26.0, mm(rng.uniform(-2.0, 2.0))};
  scatter_buoys(w, rng, 8 + static_cast<int>(rng.below(5)), 7.0, 21.0, -8.0, 8.0, 1.2,
                {w.start.position, wp1}, 3.0);
  // Course 2: the purple buoy ~45 deg to starboard of the course, the coloured object to
  // recognise to its port (west), then the second waypoint.
  Buoy purple;
  purple.center = mm(NavPoint{rng.uniform(34.0, 38.0), rng.uniform(5.0, 7.0)});
  purple.radius_m = 0.3;
  purple.height_m = 0.8;
  purple.colour = msg::Colour::kPurple;
  w.buoys.push_back(purple);
  Buoy object;
  object.center = mm(NavPoint{rng.uniform(38.0, 42.0), rng.uniform(-9.0, -6.0)});
  object.radius_m = 0.3;
  object.height_m = 0.8;
  object.colour = kDockColours[rng.below(3)];
  w.buoys.push_back(object);
  w.target_colour = object.colour;
  const NavPoint wp2{46.0, mm(rng.uniform(-3.0, 3.0))};
  w.waypoints.push_back({"wp1", wp1, 2.0});
  w.waypoints.push_back({"wp2", wp2, 2.0});
  // Course 3: one slip at the far end (docking by lidar, no marker to match).
  Dock d;
  d.name = "dock";
  d.entry_heading_deg = 0.0;
  d.width_m = 1.6;
  d.depth_m = 2.0;
  d.entrance = mm(NavPoint{70.0, rng.uniform(-6.0, 6.0)});
  d.marker.colour = msg::Colour::kWhite;
  d.marker.shape = msg::Shape::kRectangle;
  build_dock_geometry(d);
  w.docks.push_back(d);
  w.regions.push_back({"course1", rectangle(-3.0, 30.0, -12.0, 12.0), 180.0});
  w.regions.push_back({"course2", rectangle(30.0, 50.0, -12.0, 12.0), 120.0});
  w.regions.push_back({"course3", rectangle(50.0, 72.0, -12.0, 12.0), 300.0});
  return w;
}

struct Grid {
  double n0 = 0.0;
  double e0 = 0.0;
  double cell = 0.1;
  int rows = 0;
  int cols = 0;
  std::vector<std::uint8_t> blocked;
  [[nodiscard]] int index(NavPoint p) const {
    const int r = static_cast<int>(std::floor((p.north_m - n0) / cell));
    const int c = static_cast<int>(std::floor((p.east_m - e0) / cell));
    if (r < 0 || c < 0 || r >= rows || c >= cols) return -1;
    return r * cols + c;
  }
};

}  // namespace

std::optional<GeneratorKind> find_generator_kind(std::string_view name) {
  for (const GeneratorKind& k : kGeneratorKinds) {
    if (k.name == name) return k;
  }
  return std::nullopt;
}

bool straight_line_blocked(const World& world, double clearance_m) {
  std::vector<NavPoint> route{world.start.position};
  if (!world.gates.empty()) {
    for (const Gate& g : world.gates) route.push_back(scale(add(g.left, g.right), 0.5));
  } else {
    for (const Waypoint& wp : world.waypoints) route.push_back(wp.position);
  }
  auto near_polyline = [&](NavPoint a, NavPoint b, const Wall& wall) {
    for (std::size_t k = 1; k < wall.points.size(); ++k) {
      if (segment_segment_distance(a, b, wall.points[k - 1], wall.points[k]) < clearance_m) {
        return true;
      }
    }
    return false;
  };
  for (std::size_t i = 1; i < route.size(); ++i) {
    const NavPoint a = route[i - 1];
    const NavPoint b = route[i];
    for (const Buoy& buoy : world.buoys) {
      if (point_segment_distance(buoy.center, a, b) < buoy.radius_m + clearance_m) return true;
    }
    for (const Wall& wall : world.walls) {
      if (near_polyline(a, b, wall)) return true;
    }
    for (const Dock& d : world.docks) {
      for (const Wall& wall : d.walls) {
        if (near_polyline(a, b, wall)) return true;
      }
    }
  }
  return false;
}

bool course_is_solvable(const World& world, double beam_m, double margin_m, std::string* why) {
  const double inflate = 0.5 * beam_m + margin_m;
  // Segments and circles to keep clear of.
  std::vector<std::pair<NavPoint, NavPoint>> segments;
  for (const Wall& wall : world.walls) {
    for (std::size_t k = 1; k < wall.points.size(); ++k) {
      segments.emplace_back(wall.points[k - 1], wall.points[k]);
    }
  }
  for (const Dock& d : world.docks) {
    for (const Wall& wall : d.walls) {
      for (std::size_t k = 1; k < wall.points.size(); ++k) {
        segments.emplace_back(wall.points[k - 1], wall.points[k]);
      }
    }
  }
  double n_min = world.start.position.north_m;
  double n_max = n_min;
  double e_min = world.start.position.east_m;
  double e_max = e_min;
  auto extend = [&](NavPoint p) {
    n_min = std::min(n_min, p.north_m);
    n_max = std::max(n_max, p.north_m);
    e_min = std::min(e_min, p.east_m);
    e_max = std::max(e_max, p.east_m);
  };
  for (const auto& s : segments) {
    extend(s.first);
    extend(s.second);
  }
  for (const Buoy& b : world.buoys) extend(b.center);
  for (const Waypoint& wp : world.waypoints) extend(wp.position);
  Grid g;
  g.n0 = n_min - 2.0;
  g.e0 = e_min - 2.0;
  const double rows_d = std::ceil((n_max - n_min + 4.0) / g.cell);
  const double cols_d = std::ceil((e_max - e_min + 4.0) / g.cell);
  if (rows_d * cols_d > static_cast<double>(kMaxSolvableCells)) {
    if (why != nullptr) {
      *why = "the course spans " + std::to_string(std::lround(n_max - n_min)) + " m x " +
             std::to_string(std::lround(e_max - e_min)) + " m; the check covers at most " +
             std::to_string(kMaxSolvableCells / 1'000'000) + " million 0.1 m cells (1 km x 1 km)";
    }
    return false;
  }
  g.rows = static_cast<int>(rows_d);
  g.cols = static_cast<int>(cols_d);
  // One byte per cell: 0 free, 1 blocked, 2 reached from the start.
  g.blocked.assign(static_cast<std::size_t>(g.rows) * static_cast<std::size_t>(g.cols), 0);
  // Rasterise each obstacle over its own bounding box only (the grid is large, obstacles small):
  // the whole check is linear in the obstacles and in the grid's cells.
  auto mark = [&](double bn0, double bn1, double be0, double be1, const auto& blocked_at) {
    const int r0 = std::max(0, static_cast<int>(std::floor((bn0 - g.n0) / g.cell)));
    const int r1 = std::min(g.rows - 1, static_cast<int>(std::floor((bn1 - g.n0) / g.cell)));
    const int c0 = std::max(0, static_cast<int>(std::floor((be0 - g.e0) / g.cell)));
    const int c1 = std::min(g.cols - 1, static_cast<int>(std::floor((be1 - g.e0) / g.cell)));
    for (int r = r0; r <= r1; ++r) {
      for (int c = c0; c <= c1; ++c) {
        const NavPoint p{g.n0 + (r + 0.5) * g.cell, g.e0 + (c + 0.5) * g.cell};
        if (blocked_at(p)) {
          g.blocked[static_cast<std::size_t>(r) * static_cast<std::size_t>(g.cols) +
                    static_cast<std::size_t>(c)] = 1;
        }
      }
    }
  };
  for (const Buoy& b : world.buoys) {
    const double reach = b.radius_m + inflate;
    const double reach2 = reach * reach;
    mark(b.center.north_m - reach, b.center.north_m + reach, b.center.east_m - reach,
         b.center.east_m + reach, [&](NavPoint p) {
           const double dn = p.north_m - b.center.north_m;
           const double de = p.east_m - b.center.east_m;
           return dn * dn + de * de < reach2;
         });
  }
  for (const auto& segment : segments) {
    const NavPoint a = segment.first;  // clang 14 cannot capture structured bindings
    const NavPoint b = segment.second;
    mark(std::min(a.north_m, b.north_m) - inflate, std::max(a.north_m, b.north_m) + inflate,
         std::min(a.east_m, b.east_m) - inflate, std::max(a.east_m, b.east_m) + inflate,
         [&](NavPoint p) { return point_segment_distance(p, a, b) < inflate; });
  }
  const int start = g.index(world.start.position);
  if (start < 0 || g.blocked[static_cast<std::size_t>(start)] != 0) {
    if (why != nullptr) *why = "the start has no clearance for the hull";
    return false;
  }
  // Scanline flood fill from the start (4-connected): each free run of a row is filled at once
  // and seeds the free runs above and below it, so memory stays small and access sequential.
  std::uint8_t* const cells = g.blocked.data();
  const auto at = [&](int r, int c) -> std::uint8_t& {
    return cells[static_cast<std::size_t>(r) * static_cast<std::size_t>(g.cols) +
                 static_cast<std::size_t>(c)];
  };
  std::vector<std::pair<int, int>> seeds{{start / g.cols, start % g.cols}};
  while (!seeds.empty()) {
    const auto [r, c] = seeds.back();
    seeds.pop_back();
    if (at(r, c) != 0) continue;
    int lo = c;
    while (lo > 0 && at(r, lo - 1) == 0) --lo;
    int hi = c;
    while (hi + 1 < g.cols && at(r, hi + 1) == 0) ++hi;
    for (int k = lo; k <= hi; ++k) at(r, k) = 2;
    for (const int rr : {r - 1, r + 1}) {
      if (rr < 0 || rr >= g.rows) continue;
      bool in_run = false;
      for (int k = lo; k <= hi; ++k) {
        const bool free = at(rr, k) == 0;
        if (free && !in_run) seeds.emplace_back(rr, k);
        in_run = free;
      }
    }
  }
  auto reachable = [&](NavPoint p, const std::string& name) {
    // A goal counts when any free cell within 0.3 m of it was reached.
    for (double dn = -0.3; dn <= 0.3; dn += g.cell) {
      for (double de = -0.3; de <= 0.3; de += g.cell) {
        const int i = g.index({p.north_m + dn, p.east_m + de});
        if (i >= 0 && cells[static_cast<std::size_t>(i)] == 2) return true;
      }
    }
    if (why != nullptr) *why = name + " cannot be reached with the hull's clearance";
    return false;
  };
  for (const Waypoint& wp : world.waypoints) {
    if (!reachable(wp.position, "waypoint " + wp.name)) return false;
  }
  for (const Gate& gate : world.gates) {
    if (!reachable(scale(add(gate.left, gate.right), 0.5), "gate " + gate.name)) return false;
  }
  for (const Dock& d : world.docks) {
    if (d.width_m < beam_m + 2.0 * margin_m) {
      if (why != nullptr) *why = "dock " + d.name + " is narrower than the hull plus margins";
      return false;
    }
    const NavPoint front = add(d.entrance, scale(heading_unit(d.entry_heading_deg), -1.5));
    if (!reachable(front, "the water in front of dock " + d.name)) return false;
  }
  if (world.kind == CourseKind::kKaboat2026) {
    for (const Buoy& b : world.buoys) {
      if (b.colour != msg::Colour::kPurple) continue;
      const double ring = b.radius_m + inflate + 1.0;
      for (int k = 0; k < 8; ++k) {
        const NavPoint p = add(b.center, scale(heading_unit(45.0 * k), ring));
        if (!reachable(p, "the circle around the purple buoy")) return false;
      }
    }
  }
  return true;
}

Course check_course_file(const std::string& path, config::ConfigErrors& errors, double beam_m,
                         double margin_m) {
  Course c = load_course_file(path, errors);
  std::string why;
  if (errors.empty() && !course_is_solvable(c.world, beam_m, margin_m, &why)) {
    char hull[96];
    (void)std::snprintf(hull, sizeof hull,
                        "not solvable for a %.1f m hull with %.1f m margins: ", beam_m, margin_m);
    errors.add({path, 0, "", hull + why});
  }
  return c;
}

Course generate_course(CourseKind kind, std::uint64_t seed, const GeneratorParams& params) {
  Rng rng(seed);
  for (int attempt = 0; attempt < params.max_attempts; ++attempt) {
    Rng draw = rng.split();
    World w;
    switch (kind) {
      case CourseKind::kHopping:
        w = draw_hopping(draw);
        break;
      case CourseKind::kObstacle:
        if (params.family == Family::kDeadEnd) {
          w = draw_dead_end(draw);
        } else if (params.family == Family::kGapWall) {
          w = draw_gap_wall(draw);
        } else {
          w = draw_obstacle(draw, params.narrow);
        }
        break;
      case CourseKind::kDocking:
        w = draw_docking(draw);
        break;
      case CourseKind::kKaboat2026:
        w = draw_2026(draw);
        break;
    }
    w.origin = params.origin;
    std::string family_name(course_kind_name(kind));
    for (const GeneratorKind& k : kGeneratorKinds) {
      if (k.kind == kind && k.family == params.family) family_name = k.name;
    }
    w.name = family_name + "-seed-" + std::to_string(seed);
    config::ConfigErrors errors;
    validate_world(w, errors);
    if (!errors.empty()) continue;
    if (!course_is_solvable(w, params.hull_beam_m, params.margin_m)) continue;
    Course course;
    course.world = std::move(w);
    return course;
  }
  throw std::runtime_error("no solvable course found for seed " + std::to_string(seed));
}

}  // namespace coxswain::sim::world
