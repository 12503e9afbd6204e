// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/turn_side.hpp"

#include <gtest/gtest.h>

#include "coxswain/core/angles.hpp"

namespace coxswain::guidance {
namespace {

// The shipped boat's hull: the pivot (0.4 m) lies ahead of the bow tip (0.1 m), as for a hull
// driven by a stern thruster.
TurnHull boat(double radius_m = 3.5) {
  TurnHull h;
  h.turn_radius_m = radius_m;
  h.pivot_ahead_m = 0.4;
  h.bow_ahead_m = 0.1;
  h.hull_length_m = 1.2;
  h.half_beam_m = 0.4;
  return h;
}

perception::ObstacleList scene(
    std::initializer_list<std::pair<core::BodyPoint, core::BodyPoint>> segments) {
  perception::ObstacleList list;
  for (const auto& [a, b] : segments) {
    perception::ObstacleSegment s;
    s.begin = a;
    s.end = b;
    s.kind = perception::ObstacleKind::kWall;
    EXPECT_TRUE(list.push(s));
  }
  return list;
}

// A wall 4 m off the starboard side, along the heading: a starboard turn runs into it.
perception::ObstacleList starboard_wall() { return scene({{{-10.0, 4.0}, {10.0, 4.0}}}); }

TEST(TurnRoom, OpenWaterLeavesAFullTurnEitherWay) {
  const TurnRoom room = turn_room(perception::ObstacleList{}, boat(), 0.5);
  EXPECT_EQ(room.starboard_deg, TurnRoom::kFullTurnDeg);
  EXPECT_EQ(room.port_deg, TurnRoom::kFullTurnDeg);
}

TEST(TurnRoom, AWallAlongsideBlocksTheTurnTowardItOnly) {
  const TurnRoom room = turn_room(starboard_wall(), boat(), 0.5);
  // Not enough for a turn round to a reciprocal course.
  EXPECT_LT(room.starboard_deg, 150.0);
  EXPECT_EQ(room.port_deg, TurnRoom::kFullTurnDeg);
  // Mirrored, the other way round.
  const TurnRoom mirrored = turn_room(scene({{{-10.0, -4.0}, {10.0, -4.0}}}), boat(), 0.5);
  EXPECT_EQ(mirrored.starboard_deg, TurnRoom::kFullTurnDeg);
  EXPECT_NEAR(mirrored.port_deg, room.starboard_deg, 1e-9);
}

// A post on the starboard turning circle a quarter turn round from the pivot: the hull, all of
// it behind the pivot, reaches it after a little more than 90 degrees of turn (not at once).
TEST(TurnRoom, APostAQuarterTurnRoundIsReachedAfterAboutAQuarterTurn) {
  const TurnHull h = boat();
  const core::BodyPoint post{h.pivot_ahead_m + h.turn_radius_m, h.turn_radius_m};
  const TurnRoom room = turn_room(scene({{post, post}}), h, 0.5);
  EXPECT_GT(room.starboard_deg, 85.0);
  EXPECT_LT(room.starboard_deg, 100.0);
  EXPECT_EQ(room.port_deg, TurnRoom::kFullTurnDeg);
}

TEST(TurnRoom, WhatLiesAsternOrInsideTheCircleIsNotInTheWay) {
  const TurnHull h = boat();
  // Astern, and the turning centre itself (inside the ring the hull sweeps).
  const TurnRoom room =
      turn_room(scene({{{-3.0, 0.5}, {-3.0, 0.5}},
                       {{h.pivot_ahead_m, h.turn_radius_m}, {h.pivot_ahead_m, h.turn_radius_m}}}),
                h, 0.5);
  EXPECT_EQ(room.starboard_deg, TurnRoom::kFullTurnDeg);
}

TEST(TurnSideChooser, ATurnBlockedTheShortWayGoesTheLongWayAndHoldsItToTheEnd) {
  TurnSideChooser chooser({}, boat());
  chooser.observe(starboard_wall());
  // The goal 150 degrees to starboard: the short way is into the wall.
  double heading = 0.0;
  const double desired = 150.0;
  EXPECT_DOUBLE_EQ(chooser.steer(heading, desired), -90.0);
  EXPECT_EQ(chooser.side(), TurnSideChooser::Side::kPort);
  // Half way round, the goal now lies less than 180 to starboard: still to port.
  heading = -90.0;
  chooser.forget();
  EXPECT_NEAR(core::angle_diff_deg(chooser.steer(heading, desired), 180.0), 0.0, 1e-9);
  heading = 180.0;
  EXPECT_DOUBLE_EQ(chooser.steer(heading, desired), desired);  // 30 deg to go: released
  EXPECT_EQ(chooser.side(), TurnSideChooser::Side::kShortest);
}

TEST(TurnSideChooser, AClearShortTurnIsHeldTooSoTheControllerCannotTurnTheOtherWay) {
  TurnSideChooser chooser({}, boat());
  chooser.observe(perception::ObstacleList{});
  // 170 degrees to starboard, open water: starboard, commanded as such.
  EXPECT_DOUBLE_EQ(chooser.steer(10.0, 180.0), 100.0);
  EXPECT_EQ(chooser.side(), TurnSideChooser::Side::kStarboard);
}

TEST(TurnSideChooser, SmallTurnsAndTurnsWithoutAScanAreLeftAlone) {
  TurnSideChooser chooser({}, boat());
  EXPECT_DOUBLE_EQ(chooser.steer(0.0, 150.0), 150.0);  // nothing measured yet
  chooser.observe(starboard_wall());
  EXPECT_DOUBLE_EQ(chooser.steer(0.0, 40.0), 40.0);  // below min_turn_deg
  TurnSideParams off;
  off.enabled = false;
  TurnSideChooser disabled(off, boat());
  disabled.observe(starboard_wall());
  EXPECT_DOUBLE_EQ(disabled.steer(0.0, 150.0), 150.0);
}

TEST(TurnSideChooser, NeitherWayClearKeepsTheShortWayUnlessTheLongHasClearlyMoreRoom) {
  // Walls 4 m off either side: both turns meet one as soon as the other, so the short way.
  const auto channel = scene({{{-10.0, 4.0}, {10.0, 4.0}}, {{-10.0, -4.0}, {10.0, -4.0}}});
  TurnSideChooser even({}, boat());
  even.observe(channel);
  (void)even.steer(0.0, 160.0);
  EXPECT_EQ(even.side(), TurnSideChooser::Side::kStarboard);
  // The starboard wall nearer (2 m): the port turn meets its wall clearly later.
  const auto narrow = scene({{{-10.0, 2.0}, {10.0, 2.0}}, {{-10.0, -4.0}, {10.0, -4.0}}});
  const TurnRoom room = turn_room(narrow, boat(), 0.5);
  ASSERT_LT(room.port_deg, 200.0);
  ASSERT_GT(room.port_deg, room.starboard_deg + 30.0);
  TurnSideChooser uneven({}, boat());
  uneven.observe(narrow);
  (void)uneven.steer(0.0, 160.0);
  EXPECT_EQ(uneven.side(), TurnSideChooser::Side::kPort);
}

TEST(TurnSide, APointInsideTheTurningCircleCannotBeReachedByTurning) {
  const TurnHull h = boat(2.6);
  EXPECT_TRUE(inside_turning_circle({0.5, 2.0}, h, 0.5));    // close abeam to starboard
  EXPECT_TRUE(inside_turning_circle({0.5, -2.0}, h, 0.5));   // and to port
  EXPECT_FALSE(inside_turning_circle({10.0, 1.0}, h, 0.5));  // well ahead
  EXPECT_FALSE(inside_turning_circle({0.4, 5.0}, h, 0.5));   // on the circle's far side
  EXPECT_FALSE(inside_turning_circle({0.4, 0.3}, h, 0.5));   // within reach of the circle
}

TEST(TurnSideParams, OutOfRangeValuesAreRefused) {
  TurnSideParams p;
  EXPECT_FALSE(p.validate().has_value());
  p.turn_radius_m = 0.0;
  EXPECT_TRUE(p.validate().has_value());
  p = {};
  p.release_deg = 120.0;
  EXPECT_TRUE(p.validate().has_value());
}

}  // namespace
}  // namespace coxswain::guidance
