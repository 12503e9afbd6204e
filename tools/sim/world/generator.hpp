// SPDX-License-Identifier: Apache-2.0
#pragma once
// Random courses of each kind from a seed, always solvable, and the clearance check that proves
// it: a grid flood fill from the start over water at least (half-beam + margin) away from every
// obstacle must reach every goal (waypoints, gate centres, the water in front of every dock,
// a ring around the 2026 purple buoy). A drawn layout that fails is discarded and redrawn from
// the same random stream, so the result depends on the seed only. Pure functions.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "sim/world/course.hpp"
#include "sim/world/world.hpp"

namespace coxswain::sim::world {

/// Layout families. kStandard is each kind's own layout (unchanged, the same course per seed as
/// before families existed). The others are obstacle courses (2022 obstacle rules: a start gate,
/// a finish gate) drawn to defeat a purely reactive avoider:
/// - kDeadEnd: an enclosure (a U of walls or of buoys too close together for the hull) open
///   toward the boat, astride the straight line from the start to the finish, with a wing from
///   its back to the field wall on one side, so the only way round is the other side;
/// - kGapWall: a wall or buoy line across the whole field, its one gap well off the straight
///   line, with a few buoys scattered before and after it.
enum class Family : std::uint8_t { kStandard = 0, kDeadEnd, kGapWall };

/// A name `--kind` accepts: the kind (rules) and layout family it draws.
struct GeneratorKind {
  std::string_view name;
  CourseKind kind;
  Family family;
};
inline constexpr GeneratorKind kGeneratorKinds[] = {
    {"hopping", CourseKind::kHopping, Family::kStandard},
    {"obstacle", CourseKind::kObstacle, Family::kStandard},
    {"docking", CourseKind::kDocking, Family::kStandard},
    {"kaboat2026", CourseKind::kKaboat2026, Family::kStandard},
    {"deadend", CourseKind::kObstacle, Family::kDeadEnd},
    {"gapwall", CourseKind::kObstacle, Family::kGapWall},
};
/// The entry of kGeneratorKinds called `name`, if any.
std::optional<GeneratorKind> find_generator_kind(std::string_view name);

struct GeneratorParams {
  double hull_beam_m = 0.8;  // config/boat.yaml hull.beam_m
  double margin_m = 0.3;     // extra clearance on each side of the hull
  bool narrow = false;       // obstacle: the narrow preliminary field instead of the final
  core::GeoPoint origin{35.069500, 128.828000, 0.0};  // navigation frame origin
  int max_attempts = 200;
  Family family = Family::kStandard;  // kDeadEnd and kGapWall draw obstacle courses
};

/// A course of `kind` (params.family: its layout family) drawn from `seed`. Throws
/// std::runtime_error only if no solvable layout was found in max_attempts (never observed with the
/// default sizes).
Course generate_course(CourseKind kind, std::uint64_t seed, const GeneratorParams& params = {});

/// True when a boat of beam `beam_m` with `margin_m` each side can reach every goal of `world`
/// from its start (grid flood fill, cell 0.1 m). On false, `why` names the first unreachable goal.
/// The segment from the start to the first gate centre and on through every gate centre in
/// order (or through the waypoints in order) comes within `clearance_m` of a wall, dock or buoy:
/// a boat that simply steered at each goal would run into something.
bool straight_line_blocked(const World& world, double clearance_m);

/// The largest grid course_is_solvable() fills: 100 million 0.1 m cells (1 km x 1 km, 100 MB).
/// A course spanning more is refused with the reason, not checked.
inline constexpr std::size_t kMaxSolvableCells = 100'000'000;

bool course_is_solvable(const World& world, double beam_m, double margin_m,
                        std::string* why = nullptr);

/// `coxswain-sim course check`: the file loaded and validated (load_course_file), then proved
/// solvable for a hull of `beam_m` with `margin_m` each side. Problems go to `errors`. Linear in
/// the obstacles and in the area the course spans (bounded by kMaxCourseObstacles and
/// kMaxSolvableCells).
Course check_course_file(const std::string& path, config::ConfigErrors& errors, double beam_m = 0.8,
                         double margin_m = 0.3);

}  // namespace coxswain::sim::world
