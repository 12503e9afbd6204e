// SPDX-License-Identifier: Apache-2.0
#pragma once
// Random courses of each kind from a seed, always solvable, and the clearance check that proves
// it: a grid flood fill from the start over water at least (half-beam + margin) away from every
// obstacle must reach every goal (waypoints, gate centres, the water in front of every dock,
// a ring around the 2026 purple buoy). A drawn layout that fails is discarded and redrawn from
// the same random stream, so the result depends on the seed only. Pure functions.
#include <cstdint>
#include <string>

#include "sim/world/course.hpp"
#include "sim/world/world.hpp"

namespace coxswain::sim::world {

struct GeneratorParams {
  double hull_beam_m = 0.8;  // config/boat.yaml hull.beam_m
  double margin_m = 0.3;     // extra clearance on each side of the hull
  bool narrow = false;       // obstacle: the narrow preliminary field instead of the final
  core::GeoPoint origin{35.069500, 128.828000, 0.0};  // navigation frame origin
  int max_attempts = 200;
};

/// A course of `kind` drawn from `seed`. Throws std::runtime_error only if no solvable layout
/// was found in max_attempts (never observed with the default sizes).
Course generate_course(CourseKind kind, std::uint64_t seed, const GeneratorParams& params = {});

/// True when a boat of beam `beam_m` with `margin_m` each side can reach every goal of `world`
/// from its start (grid flood fill, cell 0.1 m). On false, `why` names the first unreachable goal.
bool course_is_solvable(const World& world, double beam_m, double margin_m,
                        std::string* why = nullptr);

}  // namespace coxswain::sim::world
