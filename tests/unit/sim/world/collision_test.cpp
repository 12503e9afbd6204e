// SPDX-License-Identifier: Apache-2.0
// The simulator's collision response: a hull driven into a wall stops at it, a glancing hull
// slides along, a buoy stops the hull too; the overlap geometry on hand-placed cases.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/dynamics/params.hpp"
#include "sim/world/collision.hpp"
#include "sim/world/course.hpp"
#include "sim/world/geometry.hpp"

namespace coxswain::sim::world {
namespace {

using core::NavPoint;

constexpr std::array<std::uint16_t, 2> kFullAhead{1500, 1900};  // servo centred, thrust max

std::array<NavPoint, 5> outline_at(const core::NavPose& pose) {
  const auto body = hull_outline_body(config::HullConfig{});
  std::array<NavPoint, 5> out{};
  for (std::size_t i = 0; i < 5; ++i) out[i] = core::body_to_nav(pose, body[i]);
  return out;
}

// The deepest any outline vertex reaches past the line north = wall_n (> 0 = through it).
double past_wall(const dynamics::BoatModel& m, double wall_n) {
  double worst = -1e9;
  for (const NavPoint& p : outline_at(m.truth().pose)) worst = std::max(worst, p.north_m - wall_n);
  return worst;
}

World walled(std::vector<NavPoint> wall) {
  World w;
  w.walls.push_back({std::move(wall), 0.5});
  return w;
}

dynamics::BoatModel boat_at(const core::NavPose& pose) {
  const config::BoatConfig boat;
  dynamics::BoatModel m(boat, dynamics::otter_scaled(boat.hull.length_m), {}, 1);
  m.reset(pose);
  return m;
}

TEST(Penetration, ASegmentAcrossTheBowPushesTheHullBackAlongTheWallNormal) {
  // Heading north, bow tip at north 0.1: a wall at north 0.05 overlaps the bow by 5 cm.
  Penetration p;
  ASSERT_TRUE(
      outline_segment_penetration(outline_at({{0.0, 0.0}, 0.0}), {0.05, -5.0}, {0.05, 5.0}, p));
  EXPECT_NEAR(p.normal.north_m, -1.0, 1e-12);
  EXPECT_NEAR(p.normal.east_m, 0.0, 1e-12);
  EXPECT_NEAR(p.depth_m, 0.05, 1e-12);
  EXPECT_NEAR(p.point.north_m, 0.1, 1e-12);  // the bow tip
  EXPECT_FALSE(
      outline_segment_penetration(outline_at({{0.0, 0.0}, 0.0}), {0.15, -5.0}, {0.15, 5.0}, p));
}

TEST(Penetration, ABuoyAgainstTheSideIsPushedOutThroughTheNearestSide) {
  // Starboard side at east 0.4; a 0.3 m buoy centred at east 0.6 overlaps it by 0.1 m.
  Penetration p;
  ASSERT_TRUE(outline_circle_penetration(outline_at({{0.0, 0.0}, 0.0}), {-0.6, 0.6}, 0.3, p));
  EXPECT_NEAR(p.normal.east_m, -1.0, 1e-12);  // the hull is pushed west, away from it
  EXPECT_NEAR(p.depth_m, 0.1, 1e-12);
  EXPECT_FALSE(outline_circle_penetration(outline_at({{0.0, 0.0}, 0.0}), {-0.6, 0.8}, 0.3, p));
}

TEST(CollisionResponse, AHullDrivenIntoAWallStopsAtItAndNeverPassesThrough) {
  const World w = walled({{5.0, -10.0}, {5.0, 10.0}});
  const CollisionResponse response(w, config::HullConfig{});
  dynamics::BoatModel m = boat_at({{0.0, 0.0}, 0.0});
  m.set_pulses(kFullAhead);
  int touching_steps = 0;
  for (int i = 0; i < 3000; ++i) {  // 30 s at full thrust
    m.step();
    if (response.resolve(m) > 0) ++touching_steps;
    ASSERT_LE(past_wall(m, 5.0), 1e-9) << "step " << i;
  }
  EXPECT_GT(touching_steps, 1000);            // pinned there by its thrust
  EXPECT_NEAR(past_wall(m, 5.0), 0.0, 1e-6);  // resting on it
  EXPECT_LT(std::abs(m.truth().vel_north_mps), 0.05);
}

TEST(CollisionResponse, AnAccelerometerOnAHullPinnedAgainstAWallSensesNoForwardAcceleration) {
  // The navigation filter integrates the sensed acceleration: a pinned boat whose thrust still
  // showed as acceleration would be dead-reckoned through the wall.
  const World w = walled({{5.0, -10.0}, {5.0, 10.0}});
  const CollisionResponse response(w, config::HullConfig{});
  dynamics::BoatModel m = boat_at({{0.0, 0.0}, 0.0});
  m.set_pulses(kFullAhead);
  double sensed_sum = 0.0;
  double velocity_change = 0.0;
  int steps = 0;
  for (int i = 0; i < 3000; ++i) {
    const double before = m.truth().u_mps;
    m.step();
    (void)response.resolve(m);
    if (i >= 2000) {  // long after the impact: resting on the wall under full thrust
      sensed_sum += m.truth().accel_forward_mps2;
      velocity_change += m.truth().u_mps - before;
      ++steps;
    }
  }
  EXPECT_NEAR(sensed_sum / steps, 0.0, 0.05);
  // What the accelerometer senses integrates to what the hull did.
  EXPECT_NEAR(sensed_sum * m.dt_s(), velocity_change, 0.05);
}

TEST(CollisionResponse, ABoatHittingAWallBouncesBackOnlyWithTheRestitution) {
  const World w = walled({{2.0, -10.0}, {2.0, 10.0}});
  const CollisionResponse response(w, config::HullConfig{}, {.restitution = 0.15, .passes = 4});
  dynamics::BoatModel m = boat_at({{0.0, 0.0}, 0.0});
  m.set_pulses(kFullAhead);
  double before = 0.0;
  for (int i = 0; i < 1000; ++i) {
    before = m.truth().vel_north_mps;
    m.step();
    if (response.resolve(m) > 0) break;
  }
  ASSERT_GT(before, 0.5);  // it arrived at speed
  EXPECT_LT(m.truth().vel_north_mps, 0.0);
  EXPECT_NEAR(m.truth().vel_north_mps, -0.15 * before, 0.05 * before);
}

TEST(CollisionResponse, AGlancingHullSlidesAlongTheWall) {
  // A wall along east = 3 from south to north; the boat heads 30 deg off it (heading 30).
  const World w = walled({{-50.0, 3.0}, {100.0, 3.0}});
  const CollisionResponse response(w, config::HullConfig{});
  dynamics::BoatModel m = boat_at({{0.0, 0.0}, 30.0});
  m.set_pulses(kFullAhead);
  double first_touch_n = -1.0;
  for (int i = 0; i < 2000; ++i) {
    m.step();
    const int hits = response.resolve(m);
    if (hits > 0 && first_touch_n < 0.0) first_touch_n = m.truth().cg.north_m;
    for (const NavPoint& p : outline_at(m.truth().pose)) ASSERT_LE(p.east_m, 3.0 + 1e-9);
  }
  ASSERT_GT(first_touch_n, 0.0);
  // After touching it keeps going north along the wall, not stopped by it.
  EXPECT_GT(m.truth().cg.north_m - first_touch_n, 10.0);
  EXPECT_GT(m.truth().vel_north_mps, 0.5);
}

TEST(CollisionResponse, AHullAlongsideAWallCanTurnAwayFromIt) {
  // The port side resting on a wall along east = -0.4, heading north; rudder hard to starboard,
  // compared with the same manoeuvre in open water.
  auto sail = [](double wall_east_m, double seconds) {
    const World w = walled({{-50.0, wall_east_m}, {100.0, wall_east_m}});
    const CollisionResponse response(w, config::HullConfig{});
    dynamics::BoatModel m = boat_at({{0.0, 0.0}, 0.0});
    m.set_pulses({1900, 1800});
    for (int i = 0; i < static_cast<int>(seconds * 100.0); ++i) {
      m.step();
      (void)response.resolve(m);
      for (const NavPoint& p : outline_at(m.truth().pose)) {
        EXPECT_GE(p.east_m, wall_east_m - 1e-9);
      }
    }
    return m.truth();
  };
  // The wall takes the stern's side force (a stern-steered boat cannot simply steer off a wall
  // it lies against: it pivots about the stern, slowly), but the bow does turn out and leave.
  const dynamics::TruthState open = sail(-50.0, 6.0);
  const dynamics::TruthState walled_in = sail(-0.4, 6.0);
  EXPECT_GT(walled_in.pose.heading_deg, 45.0);
  EXPECT_GT(walled_in.cg.east_m, 1.0);
  EXPECT_LT(walled_in.pose.heading_deg, open.pose.heading_deg);
}

TEST(CollisionResponse, ABuoyStopsAHullDrivenStraightAtIt) {
  World w;
  w.buoys.push_back({{4.0, 0.0}, 0.3, 0.6, msg::Colour::kOrange});
  const CollisionResponse response(w, config::HullConfig{});
  dynamics::BoatModel m = boat_at({{0.0, 0.0}, 0.0});
  m.set_pulses(kFullAhead);
  bool touched = false;
  for (int i = 0; i < 1500; ++i) {
    m.step();
    touched = response.resolve(m) > 0 || touched;
    Penetration p;
    ASSERT_FALSE(outline_circle_penetration(outline_at(m.truth().pose), {4.0, 0.0}, 0.3, p) &&
                 p.depth_m > 1e-6)
        << "step " << i;
  }
  EXPECT_TRUE(touched);
  EXPECT_LT(m.truth().pose.position.north_m, 4.0 - 0.3 + 1e-6);  // the bow never got past it
}

TEST(CollisionResponse, ADockFingerStopsTheHullLikeAWall) {
  World w;
  Dock d;
  d.name = "A";
  d.entrance = {6.0, 0.0};
  d.entry_heading_deg = 0.0;
  build_dock_geometry(d);
  w.docks.push_back(d);
  const CollisionResponse response(w, config::HullConfig{});
  // Aimed at the left finger's end (east -0.8 - 0.15), not into the slip.
  dynamics::BoatModel m = boat_at({{0.0, -0.95}, 0.0});
  m.set_pulses(kFullAhead);
  for (int i = 0; i < 1500; ++i) {
    m.step();
    (void)response.resolve(m);
  }
  EXPECT_LT(m.truth().pose.position.north_m, 6.0 + 1e-6);  // the bow did not enter the finger
}

}  // namespace
}  // namespace coxswain::sim::world
