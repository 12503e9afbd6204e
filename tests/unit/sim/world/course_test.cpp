// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "sim/world/course.hpp"
#include "sim/world/generator.hpp"
#include "support/testdata.hpp"

namespace coxswain::sim::world {
namespace {

std::vector<std::filesystem::path> shipped_courses() {
  std::vector<std::filesystem::path> files;
  for (const auto& e :
       std::filesystem::directory_iterator(testing::source_dir() / "config" / "courses")) {
    if (e.is_regular_file() && e.path().extension() == ".yaml") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Writes `text` to a temporary course file and loads it.
Course load_text(const std::string& text, config::ConfigErrors& errors) {
  const auto path =
      std::filesystem::temp_directory_path() /
      ("coxswain_course_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
       "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".yaml");
  {
    std::ofstream out(path);
    out << text;
  }
  Course c = load_course_file(path.string(), errors);
  std::filesystem::remove(path);
  return c;
}

const char* const kMinimal = R"(kind: course
name: t
type: obstacle
origin: {lat_deg: 35.0, lon_deg: 128.0}
start: {at: [0, 0], heading_deg: 0}
)";

bool has_issue(const config::ConfigErrors& errors, const std::string& key_part,
               const std::string& message_part) {
  for (const auto& i : errors.issues()) {
    if (i.key.find(key_part) != std::string::npos &&
        i.message.find(message_part) != std::string::npos) {
      return true;
    }
  }
  return false;
}

TEST(ShippedCourses, EveryCourseLoadsCleanAndIsSolvable) {
  const auto files = shipped_courses();
  ASSERT_GE(files.size(), 5U);
  for (const auto& path : files) {
    config::ConfigErrors errors;
    const Course c = load_course_file(path.string(), errors);
    EXPECT_TRUE(errors.empty()) << path << ":\n" << errors.format();
    std::string why;
    EXPECT_TRUE(course_is_solvable(c.world, 0.8, 0.3, &why)) << path << ": " << why;
  }
}

TEST(ShippedCourses, DockingPoolHasTheDocumentedLayout) {
  config::ConfigErrors errors;
  const World w = load_course(
      (testing::source_dir() / "config/courses/kaboat2022_docking.yaml").string(), errors);
  ASSERT_TRUE(errors.empty()) << errors.format();
  ASSERT_EQ(w.docks.size(), 3U);
  EXPECT_NEAR(core::distance_m(w.docks[0].entrance, w.docks[1].entrance), 3.1, 1e-9);
  // Each slip: two side walls and a back wall; the marker sits on the back wall facing out.
  ASSERT_EQ(w.docks[2].walls.size(), 3U);
  EXPECT_NEAR(w.docks[2].marker.center.north_m, 35.0, 1e-9);
  EXPECT_NEAR(w.docks[2].marker.facing_deg, 180.0, 1e-9);
  EXPECT_EQ(w.target_colour, msg::Colour::kRed);
}

TEST(ShippedCourses, Kaboat2026HasThreeTimedCourses) {
  config::ConfigErrors errors;
  const World w =
      load_course((testing::source_dir() / "config/courses/kaboat2026.yaml").string(), errors);
  ASSERT_TRUE(errors.empty()) << errors.format();
  ASSERT_EQ(w.regions.size(), 3U);
  EXPECT_DOUBLE_EQ(w.regions[0].time_limit_s, 180.0);
  EXPECT_DOUBLE_EQ(w.regions[1].time_limit_s, 120.0);
  EXPECT_DOUBLE_EQ(w.regions[2].time_limit_s, 300.0);
}

TEST(CourseLoader, MinimalCourseLoads) {
  config::ConfigErrors errors;
  const Course c = load_text(kMinimal, errors);
  EXPECT_TRUE(errors.empty()) << errors.format();
  EXPECT_EQ(c.world.kind, CourseKind::kObstacle);
}

TEST(CourseLoader, WrongKindIsReported) {
  config::ConfigErrors errors;
  std::string text = kMinimal;
  text.replace(text.find("kind: course"), 12, "kind: boat");
  (void)load_text(text, errors);
  EXPECT_TRUE(has_issue(errors, "kind", "must be 'course'")) << errors.format();
}

TEST(CourseLoader, UnknownKeyIsReportedWithItsLine) {
  config::ConfigErrors errors;
  (void)load_text(std::string(kMinimal) + "buoys:\n  - {at: [5, 5], radius: 0.3}\n", errors);
  ASSERT_TRUE(has_issue(errors, "buoys[0].radius", "not a known key")) << errors.format();
  EXPECT_EQ(errors.issues().front().line, 7);
}

TEST(CourseLoader, ShortPolylineIsRejected) {
  config::ConfigErrors errors;
  (void)load_text(std::string(kMinimal) + "walls:\n  - {points: [[5, 5]]}\n", errors);
  EXPECT_TRUE(has_issue(errors, "walls[0].points", "at least 2 points")) << errors.format();
}

TEST(CourseLoader, DegenerateSegmentIsRejected) {
  config::ConfigErrors errors;
  (void)load_text(std::string(kMinimal) + "walls:\n  - {points: [[5, 5], [5, 5], [6, 6]]}\n",
                  errors);
  EXPECT_TRUE(has_issue(errors, "walls[0]", "coincide")) << errors.format();
}

TEST(CourseLoader, NonPositiveRadiusIsRejected) {
  config::ConfigErrors errors;
  (void)load_text(std::string(kMinimal) + "buoys:\n  - {at: [5, 5], radius_m: 0}\n", errors);
  EXPECT_TRUE(has_issue(errors, "buoys[0].radius_m", ">=")) << errors.format();
}

TEST(CourseLoader, UnknownColourIsRejected) {
  config::ConfigErrors errors;
  (void)load_text(std::string(kMinimal) + "buoys:\n  - {at: [5, 5], colour: pink}\n", errors);
  EXPECT_TRUE(has_issue(errors, "buoys[0].colour", "must be one of")) << errors.format();
}

TEST(CourseLoader, BadPointIsRejected) {
  config::ConfigErrors errors;
  (void)load_text(std::string(kMinimal) + "buoys:\n  - {at: [5, x]}\n", errors);
  EXPECT_TRUE(has_issue(errors, "buoys[0].at", "point")) << errors.format();
}

TEST(CourseLoader, DegenerateGateIsRejected) {
  config::ConfigErrors errors;
  (void)load_text(std::string(kMinimal) + "gates:\n  - {name: g, left: [5, 1], right: [5, 1.1]}\n",
                  errors);
  EXPECT_TRUE(has_issue(errors, "gates[0]", "0.5 m apart")) << errors.format();
}

TEST(CourseLoader, StartInsideABuoyIsRejected) {
  config::ConfigErrors errors;
  (void)load_text(std::string(kMinimal) + "buoys:\n  - {at: [0.1, 0], radius_m: 0.3}\n", errors);
  EXPECT_TRUE(has_issue(errors, "start", "buoys[0]")) << errors.format();
}

TEST(CourseLoader, DockingTargetMustExist) {
  config::ConfigErrors errors;
  (void)load_text(R"(kind: course
name: t
type: docking
origin: {lat_deg: 35.0, lon_deg: 128.0}
start: {at: [0, 0], heading_deg: 0}
target: {colour: red, shape: cross}
docks:
  - {name: A, entrance: [10, 0], entry_heading_deg: 0, marker: {colour: red, shape: triangle}}
)",
                  errors);
  EXPECT_TRUE(has_issue(errors, "target", "no dock")) << errors.format();
}

TEST(CourseLoader, DuplicateNamesAreRejected) {
  config::ConfigErrors errors;
  (void)load_text(
      std::string(kMinimal) + "waypoints:\n  - {name: a, at: [5, 0]}\n  - {name: a, at: [9, 0]}\n",
      errors);
  EXPECT_TRUE(has_issue(errors, "waypoints[1].name", "used twice")) << errors.format();
}

TEST(CourseLoader, EnvironmentAndDynamicsSectionsAreRead) {
  config::ConfigErrors errors;
  const Course c = load_text(std::string(kMinimal) +
                                 "environment:\n  current: {speed_mps: 0.3, toward_deg: 45}\n"
                                 "dynamics:\n  d_u: 7.5\n  scale_from_length_m: 1.5\n",
                             errors);
  ASSERT_TRUE(errors.empty()) << errors.format();
  EXPECT_DOUBLE_EQ(c.environment.current_speed_mps, 0.3);
  EXPECT_DOUBLE_EQ(c.dynamics.length_m, 1.5);
  config::BoatConfig boat;
  const auto p = dynamics::make_params(boat, c.dynamics);
  EXPECT_DOUBLE_EQ(p.d_u, 7.5);
  EXPECT_DOUBLE_EQ(p.scale, 0.75);
}

TEST(CourseLoader, SensorConditionsAreReadAndRoundTrip) {
  config::ConfigErrors errors;
  const Course c = load_text(std::string(kMinimal) +
                                 "conditions:\n"
                                 "  gnss: {bias_mean_m: 7.5, bias_direction_deg: 200, "
                                 "bias_wander_sigma_m: 2, bias_tau_s: 120}\n"
                                 "  camera: {venue: harbour, glare: true, sun_bearing_deg: 90, "
                                 "blur_kernel_px: 5}\n",
                             errors);
  ASSERT_TRUE(errors.empty()) << errors.format();
  const SensorConditions& k = c.world.conditions;
  EXPECT_DOUBLE_EQ(*k.gnss_bias_mean_m, 7.5);
  EXPECT_DOUBLE_EQ(*k.gnss_bias_direction_deg, 200.0);
  EXPECT_DOUBLE_EQ(*k.gnss_bias_wander_sigma_m, 2.0);
  EXPECT_DOUBLE_EQ(*k.gnss_bias_tau_s, 120.0);
  EXPECT_FALSE(k.gnss_bias_max_m);  // not given: left to the sensors' own
  EXPECT_EQ(*k.camera_venue, "harbour");
  EXPECT_TRUE(*k.camera_glare);
  EXPECT_EQ(*k.camera_blur_kernel_px, 5);
  EXPECT_FALSE(k.camera_noise_sigma);
  config::ConfigErrors again;
  const Course back = load_text(to_course_yaml(c), again);
  ASSERT_TRUE(again.empty()) << again.format() << to_course_yaml(c);
  EXPECT_EQ(to_course_yaml(back), to_course_yaml(c));
  EXPECT_DOUBLE_EQ(*back.world.conditions.gnss_bias_mean_m, 7.5);
  EXPECT_EQ(*back.world.conditions.camera_venue, "harbour");
  EXPECT_FALSE(back.world.conditions.gnss_bias_max_m);
}

TEST(CourseLoader, BadSensorConditionsAreRejected) {
  config::ConfigErrors errors;
  (void)load_text(std::string(kMinimal) +
                      "conditions:\n  gnss: {bias_mean_m: 9, bias_max_m: 5, foo: 1}\n"
                      "  camera: {blur_kernel_px: 4, venue: lake}\n",
                  errors);
  EXPECT_TRUE(has_issue(errors, "venue", "")) << errors.format();
  EXPECT_TRUE(has_issue(errors, "bias_mean_m", "bias_max_m"));
  EXPECT_TRUE(has_issue(errors, "foo", ""));
  EXPECT_TRUE(has_issue(errors, "blur_kernel_px", "odd"));
}

TEST(CourseLoader, UnknownDynamicsKeyIsRejected) {
  config::ConfigErrors errors;
  (void)load_text(std::string(kMinimal) + "dynamics:\n  mass: 3\n", errors);
  EXPECT_TRUE(has_issue(errors, "dynamics.mass", "not a known key")) << errors.format();
}

TEST(CourseLoader, MissingFileIsReported) {
  config::ConfigErrors errors;
  (void)load_course("/nonexistent/course.yaml", errors);
  EXPECT_FALSE(errors.empty());
}

}  // namespace
}  // namespace coxswain::sim::world
