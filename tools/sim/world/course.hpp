// SPDX-License-Identifier: Apache-2.0
#pragma once
// Course files (config/courses/*.yaml, `kind: course`): loading with the project's validating
// YAML reader (file:line:key errors, unknown keys rejected), writing them back, and geometry
// checks shared by the loader and the generator.
//
// Coordinate scheme, one for every course file: every position is [north_m, east_m] in metres
// in the navigation frame whose origin is the file's `origin:` (lat/lon). Headings in degrees,
// 0 = north, clockwise. Docks are given by their mouth, entry heading, width and depth; the
// loader builds each slip's side and back walls and places the marker on the back wall.
#include <string>

#include "coxswain/config/yaml_reader.hpp"
#include "sim/dynamics/params.hpp"
#include "sim/world/world.hpp"

namespace coxswain::sim::world {

/// A course file as loaded: the world plus the simulator-only sections.
struct Course {
  World world;
  dynamics::Environment environment;     // `environment:` (current, wind, waves)
  dynamics::DynamicsOverrides dynamics;  // `dynamics:` (overrides of the scaled-Otter defaults)
};

/// The most obstacles (buoys plus wall and dock-wall segments) a course may have; more are
/// refused with the count.
inline constexpr std::size_t kMaxCourseObstacles = 50'000;

/// Loads and validates a course file; problems go to `errors` (then the result must not be used).
Course load_course_file(const std::string& path, config::ConfigErrors& errors);
/// The world of a course file (see load_course_file).
World load_course(const std::string& path, config::ConfigErrors& errors);

/// Checks the geometry of a world: polylines with >= 2 distinct points, radii > 0, gates not
/// degenerate, docks with positive size, regions with >= 3 points, start not inside or touching
/// an obstacle (within `start_clearance_m`). Problems are added to `errors` against `file`.
void validate_world(const World& world, config::ConfigErrors& errors,
                    double start_clearance_m = 0.3);

/// The walls of a slip (left finger, back, right finger) from its mouth, heading, width, depth
/// and finger width (a finger wider than 0 is a closed outline outward of the slip), and its
/// marker placed on the back wall facing out. Fills dock.walls and dock.marker.center.
void build_dock_geometry(Dock& dock, double wall_height_m = 0.5);

/// The course as a YAML file load_course_file() accepts (comments name the scheme).
std::string to_course_yaml(const Course& course);

std::string_view course_kind_name(CourseKind kind);

}  // namespace coxswain::sim::world
