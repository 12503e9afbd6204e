// SPDX-License-Identifier: Apache-2.0
// Scoring against constructed contacts and passages: the truth states are placed by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/scoring/scorer.hpp"
#include "sim/world/course.hpp"

namespace coxswain::sim::scoring {
namespace {

using core::NavPose;

config::HullConfig hull() { return {}; }  // 1.2 m x 0.8 m, bow overhang 0.1 m

// A truth state with the body origin at `pose` (the CG half a hull length minus the overhang
// behind it), stamped at t_s.
dynamics::TruthState at(double t_s, NavPose pose) {
  dynamics::TruthState t;
  t.stamp_ns = core::sec_to_ns(t_s);
  t.pose = pose;
  const double back = 0.5;  // 0.6 - 0.1
  const double h = pose.heading_deg * M_PI / 180.0;
  t.cg = {pose.position.north_m - back * std::cos(h), pose.position.east_m - back * std::sin(h)};
  return t;
}

world::World obstacle_world() {
  world::World w;
  w.name = "test";
  w.kind = world::CourseKind::kObstacle;
  world::Buoy b;
  b.center = {10.0, 1.0};
  b.radius_m = 0.3;
  w.buoys.push_back(b);
  w.gates.push_back({"start", {3.0, -1.5}, {3.0, 1.5}});
  w.gates.push_back({"finish", {20.0, -1.5}, {20.0, 1.5}});
  return w;
}

TEST(HullOutline, IsThePentagonOfTheConfiguredHull) {
  const auto body = hull_outline_body(hull());
  EXPECT_DOUBLE_EQ(body[0].forward_m, 0.1);
  EXPECT_DOUBLE_EQ(body[2].forward_m, -1.1);
  EXPECT_DOUBLE_EQ(body[2].starboard_m, 0.4);
  EXPECT_DOUBLE_EQ(body[3].starboard_m, -0.4);
  const auto nav = hull_outline(hull(), {{0.0, 0.0}, 90.0});
  EXPECT_NEAR(nav[0].east_m, 0.1, 1e-12);    // bow tip points east
  EXPECT_NEAR(nav[2].north_m, -0.4, 1e-12);  // starboard side is south when heading east
}

TEST(Scorer, TheHullSideTouchingABuoyIsACollisionThoughTheBowPathMissesIt) {
  const world::World w = obstacle_world();
  Scorer s(w, hull());
  // Heading north along east = 0.35: the bow passes 0.65 m from the buoy centre (clear of its
  // 0.3 m radius by 0.35 m), but the 0.4 m half-beam reaches 0.05 m into it.
  const std::size_t buoy = 0;
  EXPECT_LT(s.clearance_m(buoy, {{11.0, 0.35}, 0.0}), 0.0);  // beside the straight side
  EXPECT_GT(s.clearance_m(buoy, {{11.0, -0.2}, 0.0}), 0.0);
  for (int i = 0; i <= 100; ++i) {
    s.update(at(0.1 * i, {{5.0 + 0.1 * i, 0.35}, 0.0}), msg::LedColour::kOff);
  }
  ASSERT_EQ(s.result().contacts.size(), 1U);  // one contact although touching for many steps
  EXPECT_EQ(s.result().contacts[0].kind, ObstacleKind::kBuoy);
  EXPECT_EQ(s.result().collisions, 1);
  EXPECT_DOUBLE_EQ(s.result().penalty_s, 60.0);  // 2022 obstacle course: 60 s each
}

TEST(Scorer, AContactEndsOnlyWhenClearByTheReleaseDistance) {
  const world::World w = obstacle_world();
  Scorer s(w, hull());
  // Side-on to the buoy, jittering by 2 cm around touching: one contact.
  double t = 0.0;
  auto put = [&](double east) {
    s.update(at(t, {{10.5, east}, 0.0}), msg::LedColour::kOff);
    t += 0.01;
  };
  put(-0.5);                                                   // clear by 0.4 m
  for (int i = 0; i < 20; ++i) put(i % 2 == 0 ? 0.31 : 0.29);  // touching, then 1 cm clear
  EXPECT_EQ(s.result().contacts.size(), 1U);
  put(0.2);   // 10 cm clear: released
  put(0.31);  // touching again: a second contact
  EXPECT_EQ(s.result().contacts.size(), 2U);
  EXPECT_EQ(s.result().collisions, 2);
}

TEST(Scorer, WallContactCountsOncePerWall) {
  world::World w;
  w.kind = world::CourseKind::kHopping;
  w.walls.push_back({{{0.0, 2.0}, {30.0, 2.0}}, 0.5});
  w.waypoints.push_back({"wp", {50.0, 0.0}, 2.0});
  Scorer s(w, hull());
  // Scraping along the wall with the starboard side for 10 m.
  for (int i = 0; i <= 100; ++i) s.update(at(0.1 * i, {{5.0 + 0.1 * i, 1.65}, 0.0}), {});
  EXPECT_EQ(s.result().collisions, 1);
  EXPECT_DOUBLE_EQ(s.result().penalty_s, 30.0);  // 2022 hopping: 30 s each
}

TEST(Scorer, WaypointNeedsHalfTheHullInsideTheCircle) {
  world::World w;
  w.kind = world::CourseKind::kHopping;
  w.waypoints.push_back({"wp1", {10.0, 0.0}, 2.0});
  w.waypoints.push_back({"wp2", {20.0, 0.0}, 2.0});
  Scorer s(w, hull());
  // Bow 2.1 m short of the centre: the bow tip is inside the circle but not half the hull.
  s.update(at(1.0, {{7.9 + 0.1, 0.0}, 0.0}), {});
  s.update(at(1.1, {{7.95 + 0.1, 0.0}, 0.0}), {});
  EXPECT_TRUE(s.result().waypoints.empty());
  // Hull centre 0.4 m inside the circle edge... more than half the area inside.
  s.update(at(2.0, {{8.9, 0.0}, 0.0}), {});
  ASSERT_EQ(s.result().waypoints.size(), 1U);
  EXPECT_EQ(s.result().waypoints[0].name, "wp1");
  EXPECT_DOUBLE_EQ(s.result().waypoints[0].t_s, 2.0);
  // In order: wp2 is next, and reaching it completes the hopping tour.
  s.update(at(5.0, {{20.5, 0.0}, 0.0}), {});
  EXPECT_TRUE(s.result().completed);
  EXPECT_TRUE(s.done());
  EXPECT_DOUBLE_EQ(s.result().elapsed_s, 5.0);
  EXPECT_DOUBLE_EQ(s.result().score_s, 5.0);
}

TEST(Scorer, WaypointsOutOfOrderDoNotCount) {
  world::World w;
  w.kind = world::CourseKind::kHopping;
  w.waypoints.push_back({"wp1", {10.0, 0.0}, 2.0});
  w.waypoints.push_back({"wp2", {20.0, 0.0}, 2.0});
  Scorer s(w, hull());
  s.update(at(1.0, {{20.5, 0.0}, 0.0}), {});
  EXPECT_TRUE(s.result().waypoints.empty());
}

TEST(Scorer, GatesCountOnlyInTheRightDirectionAndInOrder) {
  const world::World w = obstacle_world();
  Scorer s(w, hull());
  // Southward through the start gate: wrong way, recorded but not counted.
  s.update(at(0.0, {{5.0, -0.5}, 180.0}), {});
  s.update(at(0.1, {{2.0, -0.5}, 180.0}), {});
  ASSERT_EQ(s.result().gates.size(), 1U);
  EXPECT_FALSE(s.result().gates[0].ok);
  // Northward: counted; then the finish completes the course.
  s.update(at(1.0, {{3.0, -0.5}, 0.0}), {});
  s.update(at(1.1, {{4.0, -0.5}, 0.0}), {});
  ASSERT_EQ(s.result().gates.size(), 2U);
  EXPECT_TRUE(s.result().gates[1].ok);
  EXPECT_FALSE(s.result().completed);
  s.update(at(9.0, {{19.9, -0.5}, 0.0}), {});
  s.update(at(9.1, {{21.0, -0.5}, 0.0}), {});
  EXPECT_TRUE(s.result().completed);
  EXPECT_DOUBLE_EQ(s.result().elapsed_s, 9.1);
}

world::World docking_world() {
  world::World w;
  w.kind = world::CourseKind::kDocking;
  const char* names[] = {"A", "B"};
  for (int i = 0; i < 2; ++i) {
    world::Dock d;
    d.name = names[i];
    d.entrance = {20.0, i * 3.1};
    d.entry_heading_deg = 0.0;
    d.marker.colour = i == 0 ? msg::Colour::kGreen : msg::Colour::kRed;
    d.marker.shape = msg::Shape::kTriangle;
    world::build_dock_geometry(d);
    w.docks.push_back(d);
  }
  w.target_colour = msg::Colour::kRed;
  w.target_shape = msg::Shape::kTriangle;
  w.regions.push_back({"pool", {{0, -5}, {0, 8}, {23, 8}, {23, -5}}, 300.0});
  return w;
}

TEST(Scorer, EnteringTheTargetDockCompletesAndDockContactsAreFree) {
  const world::World w = docking_world();
  Scorer s(w, hull());
  // Into dock A (not the target) far enough for half the hull, brushing its side wall.
  s.update(at(1.0, {{21.5, 0.45}, 0.0}), {});
  ASSERT_EQ(s.result().docks.size(), 1U);
  EXPECT_FALSE(s.result().docks[0].ok);
  EXPECT_FALSE(s.result().completed);
  ASSERT_EQ(s.result().contacts.size(), 1U);
  EXPECT_EQ(s.result().contacts[0].kind, ObstacleKind::kDock);
  EXPECT_FALSE(s.result().contacts[0].penalised);
  EXPECT_EQ(s.result().collisions, 0);
  // Only a quarter in: not yet entered.
  s.update(at(5.0, {{20.2, 3.1}, 0.0}), {});
  EXPECT_EQ(s.result().docks.size(), 1U);
  s.update(at(6.0, {{21.7, 3.1}, 0.0}), {});
  EXPECT_TRUE(s.result().completed);
  EXPECT_TRUE(s.result().docked);
  EXPECT_DOUBLE_EQ(s.result().score_s, 6.0);
}

TEST(Scorer, TimeLimitEndsTheRun) {
  const world::World w = docking_world();
  Scorer s(w, hull());
  s.update(at(299.9, {{5.0, 0.0}, 0.0}), {});
  EXPECT_FALSE(s.done());
  s.update(at(300.0, {{5.0, 0.0}, 0.0}), {});
  EXPECT_TRUE(s.done());
  EXPECT_TRUE(s.result().timed_out);
  EXPECT_FALSE(s.result().completed);
}

world::World kaboat2026_world() {
  world::World w;
  w.kind = world::CourseKind::kKaboat2026;
  w.regions.push_back({"course1", {{-5, -10}, {-5, 10}, {20, 10}, {20, -10}}, 180.0});
  w.regions.push_back({"course2", {{20, -10}, {20, 10}, {40, 10}, {40, -10}}, 120.0});
  w.regions.push_back({"course3", {{40, -10}, {40, 10}, {60, 10}, {60, -10}}, 300.0});
  world::Buoy b;
  b.center = {10.0, 0.0};
  b.radius_m = 0.3;
  w.buoys.push_back(b);
  world::Buoy object = b;
  object.center = {30.0, -8.0};
  object.colour = msg::Colour::kGreen;
  w.buoys.push_back(object);
  w.target_colour = msg::Colour::kGreen;
  world::Dock d;
  d.name = "dock";
  d.entrance = {55.0, 0.0};
  world::build_dock_geometry(d);
  w.docks.push_back(d);
  return w;
}

TEST(Scorer, Kaboat2026PenalisesPerCourseAndAwardsBonuses) {
  const world::World w = kaboat2026_world();
  Scorer s(w, hull());
  // Course 1: hit the buoy once (10 s).
  s.update(at(10.0, {{10.0, 0.3}, 0.0}), {});
  s.update(at(11.0, {{15.0, 0.0}, 0.0}), {});
  // Course 2 from 30 s; the LED shows green (the target colour): recognised.
  s.update(at(30.0, {{22.0, 0.0}, 0.0}), {});
  s.update(at(40.0, {{25.0, 0.0}, 0.0}), msg::LedColour::kGreen);
  // Course 3 from 60 s, then docked at 100 s.
  s.update(at(60.0, {{42.0, 0.0}, 0.0}), msg::LedColour::kGreen);
  s.update(at(100.0, {{56.7, 0.0}, 0.0}), msg::LedColour::kGreen);
  const ScoreResult& r = s.result();
  EXPECT_TRUE(r.completed);
  EXPECT_TRUE(r.recognised);
  EXPECT_TRUE(r.docked);
  EXPECT_DOUBLE_EQ(r.bonus_points, 80.0);
  EXPECT_DOUBLE_EQ(r.penalty_s, 10.0);
  ASSERT_EQ(r.courses.size(), 3U);
  EXPECT_EQ(r.courses[0].collisions, 1);
  EXPECT_EQ(r.courses[1].collisions, 0);
  EXPECT_DOUBLE_EQ(r.courses[0].end_s, 30.0);
  EXPECT_DOUBLE_EQ(r.courses[1].start_s, 30.0);
  EXPECT_DOUBLE_EQ(r.courses[2].start_s, 60.0);
  EXPECT_DOUBLE_EQ(r.courses[2].end_s, 100.0);
  EXPECT_DOUBLE_EQ(r.score_s, 110.0);
  const nlohmann::json j = to_json(r);
  EXPECT_EQ(j["rules"], "kaboat2026");
  EXPECT_EQ(j["courses"].size(), 3U);
  EXPECT_EQ(j["contacts"][0]["kind"], "buoy");
  EXPECT_EQ(j["bonus_points"], 80.0);
}

TEST(Scorer, FinishSettlesARunTheMissionEndedBeforeTheRules) {
  const world::World w = kaboat2026_world();
  Scorer s(w, hull());
  s.update(at(10.0, {{10.0, 0.3}, 0.0}), {});  // one collision in course 1
  s.update(at(30.0, {{22.0, 0.0}, 0.0}), {});
  s.update(at(40.0, {{25.0, 0.0}, 0.0}), msg::LedColour::kGreen);  // recognised
  s.update(at(60.0, {{42.0, 0.0}, 0.0}), msg::LedColour::kGreen);  // in course 3, not docked
  ASSERT_FALSE(s.done());
  EXPECT_DOUBLE_EQ(s.result().elapsed_s, 0.0);
  s.finish(75.0);
  const ScoreResult& r = s.result();
  EXPECT_TRUE(s.done());
  EXPECT_FALSE(r.completed);
  EXPECT_DOUBLE_EQ(r.elapsed_s, 75.0);
  EXPECT_DOUBLE_EQ(r.score_s, 85.0);
  EXPECT_DOUBLE_EQ(r.bonus_points, 30.0);
  EXPECT_DOUBLE_EQ(r.courses[2].end_s, 75.0);
  s.finish(90.0);  // no-op once done
  EXPECT_DOUBLE_EQ(s.result().elapsed_s, 75.0);
}

TEST(Scorer, Kaboat2026WrongColourFirstIsNotRecognisedAndCourseTimeLimitHolds) {
  const world::World w = kaboat2026_world();
  Scorer s(w, hull());
  s.update(at(1.0, {{1.0, 0.0}, 0.0}), msg::LedColour::kRed);
  s.update(at(2.0, {{1.0, 0.0}, 0.0}), msg::LedColour::kGreen);
  EXPECT_FALSE(s.result().recognised);
  s.update(at(180.0, {{1.0, 0.0}, 0.0}), {});  // still in course 1 at its 3 min limit
  EXPECT_TRUE(s.done());
  EXPECT_TRUE(s.result().courses[0].timed_out);
}

TEST(Scorer, Kaboat2026CountsAFullTurnAroundThePurpleBuoy) {
  world::World w = kaboat2026_world();
  world::Buoy purple;
  purple.center = {30.0, 0.0};
  purple.radius_m = 0.3;
  purple.colour = msg::Colour::kPurple;
  w.buoys.push_back(purple);
  Scorer s(w, hull());
  // Counter-clockwise (buoy kept to port) on a 3 m circle, in 10 deg steps: 350 deg is not yet
  // a turn, 370 deg is.
  auto put = [&](int k) {
    const double a = -10.0 * k * M_PI / 180.0;
    const NavPose p{{30.0 + 3.0 * std::cos(a), 3.0 * std::sin(a)}, 0.0};
    s.update(at(40.0 + 0.1 * k, p), {});
  };
  for (int k = 0; k <= 35; ++k) put(k);
  EXPECT_FALSE(s.result().circled);
  put(36);
  put(37);
  EXPECT_TRUE(s.result().circled);
  EXPECT_LT(s.result().buoy_circled_deg, -360.0);
}

TEST(Scorer, AHullExactlyTouchingAWallAfterTheCollisionResponseIsOneContact) {
  world::World w;
  w.kind = world::CourseKind::kHopping;
  w.walls.push_back({{{0.0, 2.0}, {30.0, 2.0}}, 0.5});
  w.waypoints.push_back({"wp", {50.0, 0.0}, 2.0});
  Scorer s(w, hull());
  // The starboard side at east 1.6 + 0.4 = 2.0: touching to the last bit, as the collision
  // response leaves a hull it pushed out; then clear, then touching again: two contacts.
  for (int i = 0; i <= 50; ++i) s.update(at(0.1 * i, {{5.0, 1.6}, 0.0}), {});
  EXPECT_EQ(s.result().collisions, 1);
  for (int i = 51; i <= 60; ++i) s.update(at(0.1 * i, {{5.0, 1.0}, 0.0}), {});
  for (int i = 61; i <= 70; ++i) s.update(at(0.1 * i, {{5.0, 1.6}, 0.0}), {});
  EXPECT_EQ(s.result().collisions, 2);
}

TEST(Scorer, AHullPinnedAgainstAWallEndsTheRunAsAFailure) {
  world::World w = obstacle_world();
  w.walls.push_back({{{12.0, -5.0}, {12.0, 5.0}}, 0.5});
  Scorer s(w, hull());
  // The bow against the wall (bow tip at 12.0), nudging a few centimetres for 40 s.
  double t = 0.0;
  for (; t < 40.0 && !s.done(); t += 0.01) {
    s.update(at(t, {{11.9 - 0.02 * std::sin(t), -0.5}, 0.0}), {});
  }
  ASSERT_TRUE(s.done());
  const ScoreResult& r = s.result();
  EXPECT_TRUE(r.pinned);
  EXPECT_FALSE(r.completed);
  EXPECT_EQ(r.pinned_to, "wall 0");
  EXPECT_NEAR(r.elapsed_s, 30.0, 0.02);  // ScoringOptions::pinned_s after the touch
  EXPECT_EQ(r.collisions, 1);
  EXPECT_EQ(r.pending, "gate start");
  EXPECT_NE(failure_reason(r, false).find("pinned against wall 0"), std::string::npos);
}

TEST(Scorer, SlidingAlongAWallIsNotPinned) {
  world::World w;
  w.kind = world::CourseKind::kHopping;
  w.walls.push_back({{{0.0, 2.0}, {100.0, 2.0}}, 0.5});
  w.waypoints.push_back({"wp", {150.0, 0.0}, 2.0});
  Scorer s(w, hull());
  // 60 s in contact, moving along at 0.5 m/s: one long scrape, never stuck.
  for (double t = 0.0; t < 60.0; t += 0.01) s.update(at(t, {{5.0 + 0.5 * t, 1.6}, 0.0}), {});
  EXPECT_FALSE(s.done());
  EXPECT_FALSE(s.result().pinned);
  EXPECT_EQ(s.result().collisions, 1);
}

TEST(FailureReason, AMissionThatFinishedWithTheFinishGateUncrossedFails) {
  const world::World w = obstacle_world();
  Scorer s(w, hull());
  // Through the start gate, then past the finish gate outside its buoys (east 3).
  s.update(at(0.0, {{1.0, 0.0}, 0.0}), {});
  s.update(at(1.0, {{5.0, 0.0}, 0.0}), {});
  s.update(at(2.0, {{18.0, 3.0}, 0.0}), {});
  s.update(at(3.0, {{23.0, 3.0}, 0.0}), {});
  s.finish(3.0);
  const ScoreResult& r = s.result();
  EXPECT_FALSE(r.completed);
  EXPECT_EQ(r.pending, "gate finish");
  const std::string why = failure_reason(r, true);
  EXPECT_NE(why.find("mission finished"), std::string::npos) << why;
  EXPECT_NE(why.find("gate finish"), std::string::npos) << why;
}

TEST(FailureReason, NamesTheWrongDockTheBoatEntered) {
  ScoreResult r;
  r.rules = Rules::k2022Docking;
  r.docks.push_back({"C", 50.0, false});
  r.pending = "the target dock";
  EXPECT_EQ(failure_reason(r, true), "entered dock C, not the target");
}

TEST(FailureReason, IsEmptyForACompletedRun) {
  const world::World w = obstacle_world();
  Scorer s(w, hull());
  s.update(at(0.0, {{1.0, 0.0}, 0.0}), {});
  s.update(at(1.0, {{5.0, 0.0}, 0.0}), {});
  s.update(at(2.0, {{18.0, 0.0}, 0.0}), {});
  s.update(at(3.0, {{23.0, 0.0}, 0.0}), {});
  ASSERT_TRUE(s.result().completed);
  EXPECT_EQ(failure_reason(s.result(), true), "");
}

TEST(Svg, DrawsCoursePathCollisionsAndWaypoints) {
  world::World w = obstacle_world();
  w.waypoints.push_back({"wp", {15.0, 0.0}, 2.0});
  w.walls.push_back({{{0, -3}, {25, -3}}, 0.5});
  Scorer s(w, hull());
  std::vector<NavPose> path;
  for (int i = 0; i <= 100; ++i) {
    const NavPose p{{5.0 + 0.1 * i, 0.35}, 0.0};
    path.push_back(p);
    s.update(at(0.1 * i, p), {});
  }
  const std::string svg = trajectory_svg(w, hull(), path, &s.result());
  EXPECT_EQ(svg.rfind("<svg", 0), 0U);
  EXPECT_NE(svg.find("class=\"path\""), std::string::npos);
  EXPECT_NE(svg.find("class=\"collision\""), std::string::npos);
  EXPECT_NE(svg.find("class=\"waypoint\""), std::string::npos);
  EXPECT_NE(svg.find("class=\"gate\""), std::string::npos);
  EXPECT_NE(svg.find("class=\"wall\""), std::string::npos);
  EXPECT_NE(svg.find("class=\"hull\""), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
}

}  // namespace
}  // namespace coxswain::sim::scoring
