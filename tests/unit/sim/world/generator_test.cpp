// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "sim/world/generator.hpp"

namespace coxswain::sim::world {
namespace {

constexpr CourseKind kKinds[] = {CourseKind::kHopping, CourseKind::kObstacle, CourseKind::kDocking,
                                 CourseKind::kKaboat2026};

TEST(Generator, SameSeedSameCourseDifferentSeedDifferentCourse) {
  for (CourseKind kind : kKinds) {
    const std::string a = to_course_yaml(generate_course(kind, 42));
    const std::string b = to_course_yaml(generate_course(kind, 42));
    const std::string c = to_course_yaml(generate_course(kind, 43));
    EXPECT_EQ(a, b) << course_kind_name(kind);
    EXPECT_NE(a, c) << course_kind_name(kind);
  }
}

TEST(Generator, EveryGeneratedCourseIsValidAndSolvable) {
  for (CourseKind kind : kKinds) {
    for (std::uint64_t seed = 1; seed <= 12; ++seed) {
      GeneratorParams params;
      params.narrow = seed % 2 == 0;
      const Course c = generate_course(kind, seed, params);
      config::ConfigErrors errors;
      validate_world(c.world, errors);
      EXPECT_TRUE(errors.empty()) << errors.format();
      std::string why;
      EXPECT_TRUE(course_is_solvable(c.world, 0.8, 0.3, &why))
          << course_kind_name(kind) << " seed " << seed << ": " << why;
    }
  }
}

TEST(Generator, KindsHaveTheirParts) {
  EXPECT_GE(generate_course(CourseKind::kHopping, 3).world.waypoints.size(), 3U);
  const World obstacle = generate_course(CourseKind::kObstacle, 3).world;
  EXPECT_EQ(obstacle.gates.size(), 2U);
  EXPECT_GE(obstacle.buoys.size(), 12U);
  const World docking = generate_course(CourseKind::kDocking, 3).world;
  ASSERT_EQ(docking.docks.size(), 3U);
  int matches = 0;
  for (const Dock& d : docking.docks) {
    matches += (d.marker.colour == docking.target_colour && d.marker.shape == docking.target_shape);
  }
  EXPECT_EQ(matches, 1);
  const World k2026 = generate_course(CourseKind::kKaboat2026, 3).world;
  EXPECT_EQ(k2026.regions.size(), 3U);
}

// The obstacle families: the same course for a seed, valid, solvable with the hull's
// clearance, and the straight line from the start through the gates blocked.
constexpr Family kFamilies[] = {Family::kDeadEnd, Family::kGapWall};

TEST(GeneratorFamilies, AreDeterministicPerSeedValidSolvableAndBlockTheStraightLine) {
  for (Family family : kFamilies) {
    GeneratorParams params;
    params.family = family;
    for (std::uint64_t seed = 1; seed <= 16; ++seed) {
      const Course c = generate_course(CourseKind::kObstacle, seed, params);
      EXPECT_EQ(to_course_yaml(c),
                to_course_yaml(generate_course(CourseKind::kObstacle, seed, params)));
      config::ConfigErrors errors;
      validate_world(c.world, errors);
      EXPECT_TRUE(errors.empty()) << errors.format();
      std::string why;
      EXPECT_TRUE(course_is_solvable(c.world, 0.8, 0.3, &why)) << "seed " << seed << ": " << why;
      EXPECT_TRUE(straight_line_blocked(c.world, 0.7)) << c.world.name;
      EXPECT_EQ(c.world.gates.size(), 2U);
      EXPECT_EQ(c.world.kind, CourseKind::kObstacle);
    }
    EXPECT_NE(to_course_yaml(generate_course(CourseKind::kObstacle, 1, params)),
              to_course_yaml(generate_course(CourseKind::kObstacle, 2, params)));
  }
}

TEST(GeneratorFamilies, TheDeadEndLetsTheBoatSailStraightIntoIt) {
  GeneratorParams params;
  params.family = Family::kDeadEnd;
  for (std::uint64_t seed = 1; seed <= 8; ++seed) {
    const World w = generate_course(CourseKind::kObstacle, seed, params).world;
    // Up the straight line from the start gate to the first thing in the way (the back of the
    // enclosure): the water just short of it is reachable from the start, so the enclosure is
    // open toward the boat and a boat steering straight at the finish ends up inside it.
    World probe = w;
    probe.gates.clear();
    double n = 4.0;
    for (; n < 40.0; n += 0.1) {
      World line = probe;
      line.waypoints = {{"probe", {n, 0.0}, 0.5}};
      if (straight_line_blocked(line, 0.7)) break;
    }
    ASSERT_LT(n, 30.0) << w.name;
    probe.waypoints.push_back({"inside", {n - 0.8, 0.0}, 0.5});
    std::string why;
    EXPECT_TRUE(course_is_solvable(probe, 0.8, 0.3, &why)) << w.name << ": " << why;
  }
}

TEST(GeneratorFamilies, NamesAreFoundAndTheStandardKindsKeepTheirNames) {
  ASSERT_TRUE(find_generator_kind("deadend"));
  EXPECT_EQ(find_generator_kind("deadend")->family, Family::kDeadEnd);
  EXPECT_EQ(find_generator_kind("gapwall")->kind, CourseKind::kObstacle);
  EXPECT_FALSE(find_generator_kind("maze"));
  EXPECT_EQ(generate_course(CourseKind::kObstacle, 5).world.name, "obstacle-seed-5");
  GeneratorParams params;
  params.family = Family::kGapWall;
  EXPECT_EQ(generate_course(CourseKind::kObstacle, 5, params).world.name, "gapwall-seed-5");
}

TEST(Generator, RoundTripThroughTheYamlFile) {
  for (CourseKind kind : kKinds) {
    const Course original = generate_course(kind, 11);
    const auto path = std::filesystem::temp_directory_path() /
                      ("coxswain_gen_" + std::string(course_kind_name(kind)) + ".yaml");
    {
      std::ofstream out(path);
      out << to_course_yaml(original);
    }
    config::ConfigErrors errors;
    Course loaded = load_course_file(path.string(), errors);
    std::filesystem::remove(path);
    ASSERT_TRUE(errors.empty()) << errors.format();
    // Writing the loaded course gives the same text, except its source file name.
    loaded.world.file.clear();
    EXPECT_EQ(to_course_yaml(loaded), to_course_yaml(original));
    ASSERT_EQ(loaded.world.buoys.size(), original.world.buoys.size());
    for (std::size_t i = 0; i < loaded.world.buoys.size(); ++i) {
      EXPECT_EQ(loaded.world.buoys[i].center.north_m, original.world.buoys[i].center.north_m);
      EXPECT_EQ(loaded.world.buoys[i].center.east_m, original.world.buoys[i].center.east_m);
    }
    EXPECT_EQ(loaded.world.docks.size(), original.world.docks.size());
  }
}

TEST(Clearance, AWallAcrossTheChannelMakesTheCourseUnsolvable) {
  World w;
  w.kind = CourseKind::kObstacle;
  w.walls.push_back({{{-2, -4}, {-2, 4}, {30, 4}, {30, -4}, {-2, -4}}, 0.5});
  w.gates.push_back({"finish", {25, -1}, {25, 1}});
  std::string why;
  EXPECT_TRUE(course_is_solvable(w, 0.8, 0.3, &why)) << why;
  // A barrier with a 1.2 m gap: less than beam + 2 margins (1.4 m).
  w.walls.push_back({{{12, -4}, {12, -0.6}}, 0.5});
  w.walls.push_back({{{12, 0.6}, {12, 4}}, 0.5});
  EXPECT_FALSE(course_is_solvable(w, 0.8, 0.3, &why));
  EXPECT_NE(why.find("finish"), std::string::npos);
  // A 1.8 m gap is wide enough.
  w.walls[1].points[1] = {12, -0.9};
  w.walls[2].points[0] = {12, 0.9};
  EXPECT_TRUE(course_is_solvable(w, 0.8, 0.3, &why)) << why;
}

TEST(Clearance, NarrowDockIsRejected) {
  World w;
  w.kind = CourseKind::kDocking;
  w.walls.push_back({{{-2, -5}, {-2, 5}, {20, 5}, {20, -5}, {-2, -5}}, 0.5});
  Dock d;
  d.name = "tight";
  d.entrance = {15, 0};
  d.width_m = 1.2;
  build_dock_geometry(d);
  w.docks.push_back(d);
  std::string why;
  EXPECT_FALSE(course_is_solvable(w, 0.8, 0.3, &why));
  EXPECT_NE(why.find("narrower"), std::string::npos);
}

// A lattice of `rows` x `cols` buoys `spacing_m` apart (at 4 m, 2 m of water between buoys
// inflated for a 0.8 m hull with 0.3 m margins), the start outside its first corner and a
// waypoint in its middle, reached only through the gaps.
Course buoy_lattice(int rows, int cols, double spacing_m = 4.0) {
  Course c;
  World& w = c.world;
  w.name = "lattice";
  w.kind = CourseKind::kObstacle;
  w.origin = {35.0, 128.0, 0.0};
  w.start.position = {-5.0, -5.0};
  for (int r = 0; r < rows; ++r) {
    for (int k = 0; k < cols; ++k) {
      Buoy b;
      b.center = {r * spacing_m, k * spacing_m};
      b.radius_m = 0.3;
      w.buoys.push_back(b);
    }
  }
  w.waypoints.push_back(
      {"middle", {(rows / 2 + 0.5) * spacing_m, (cols / 2 + 0.5) * spacing_m}, 1.0});
  return c;
}

// `coxswain-sim course check` on 20,000 buoys: loaded, validated and proved solvable (the check
// is linear in the obstacles and the area; it took minutes when every point merged the file's
// node pool into a new one). Its time is printed by the course check benchmark.
TEST(CourseCheck, ACourseOfTwentyThousandBuoysIsChecked) {
  const Course lattice = buoy_lattice(100, 200);
  ASSERT_EQ(lattice.world.buoys.size(), 20'000U);
  const auto path = std::filesystem::temp_directory_path() /
                    ("coxswain_lattice_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(path) << to_course_yaml(lattice);
  config::ConfigErrors errors;
  const Course checked = check_course_file(path.string(), errors);
  std::filesystem::remove(path);
  EXPECT_TRUE(errors.empty()) << errors.format();
  EXPECT_EQ(checked.world.buoys.size(), 20'000U);
  EXPECT_NEAR(checked.world.buoys.back().center.north_m, 99 * 4.0, 1e-9);
}

TEST(CourseCheck, ALatticeTooTightForTheHullIsNotSolvable) {
  // 1.5 m apart: the inflated buoys (1.0 m reach each) close every gap.
  std::string why;
  EXPECT_FALSE(course_is_solvable(buoy_lattice(30, 30, 1.5).world, 0.8, 0.3, &why));
  EXPECT_NE(why.find("waypoint middle cannot be reached"), std::string::npos) << why;
}

TEST(CourseCheck, MoreObstaclesThanTheLimitAreRefusedWithTheCount) {
  const Course c = buoy_lattice(1, static_cast<int>(kMaxCourseObstacles) + 1, 1.0);
  config::ConfigErrors errors;
  validate_world(c.world, errors);
  ASSERT_FALSE(errors.empty());
  EXPECT_NE(errors.format().find("has 50001 obstacles"), std::string::npos) << errors.format();
}

TEST(CourseCheck, ACourseSpanningMoreThanTheGridIsRefusedWithItsSize) {
  Course c = buoy_lattice(2, 2);
  c.world.waypoints.back().position = {3000.0, 3000.0};
  std::string why;
  EXPECT_FALSE(course_is_solvable(c.world, 0.8, 0.3, &why));
  EXPECT_NE(why.find("spans 3005 m x 3005 m"), std::string::npos) << why;
}

}  // namespace
}  // namespace coxswain::sim::world
