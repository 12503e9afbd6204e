// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/avoidance.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "coxswain/core/angles.hpp"
#include "support/obstacles.hpp"

namespace coxswain::guidance {
namespace {

using perception::ObstacleList;
using perception::ObstacleSegment;

using test::segment;

// A short segment across the line of sight at `bearing_deg`, `range_m` away (a buoy).
ObstacleSegment buoy(double range_m, double bearing_deg, double half_width_m = 0.2) {
  const double a = core::deg_to_rad(bearing_deg);
  const double f = range_m * std::cos(a);
  const double s = range_m * std::sin(a);
  return segment(f + half_width_m * std::sin(a), s - half_width_m * std::cos(a),
                 f - half_width_m * std::sin(a), s + half_width_m * std::cos(a));
}

ObstacleList list_of(std::initializer_list<ObstacleSegment> segs) {
  ObstacleList l;
  for (const auto& s : segs) EXPECT_TRUE(l.push(s));
  return l;
}

// The plain reactive engine these behaviour tests were written for: no swept hull, an 8 m view,
// the 2022 plan's 8 deg / 1.5 s hysteresis and its slow-down, a 0.45 m half-beam with 0.35 m of
// clearance. (The defaults are the tuned values a mission ships: 5 m, swept hull, 15 deg / 3 s,
// no slow-down, the hull from boat.yaml.)
AvoidanceParams plain_params() {
  AvoidanceParams p;
  p.detection_range_m = 8.0;
  p.sweep_enabled = false;
  p.hysteresis_deg = 8.0;
  p.hold_time_s = 1.5;
  p.min_speed_factor = 0.35;
  p.half_beam_m = 0.45;
  p.clearance_m = 0.35;
  p.sweep_clearance_m = 0.15;
  return p;
}

Avoidance make(Strategy s, AvoidanceParams p = plain_params()) {
  p.strategy = s;
  std::string err;
  auto a = Avoidance::create(p, &err);
  EXPECT_TRUE(a.has_value()) << err;
  return std::move(*a);
}

// Lateral distance at which a straight run along `heading_deg` passes a point.
double pass_distance(double range_m, double bearing_deg, double heading_deg) {
  const double d = std::abs(core::deg_to_rad(core::angle_diff_deg(bearing_deg, heading_deg)));
  return d >= core::kPi / 2 ? range_m : range_m * std::sin(d);
}

constexpr Strategy kOurs[] = {Strategy::kSelection, Strategy::kScore, Strategy::kRiskBin};
constexpr core::TimeNs kTick = 100 * core::kNsPerMs;

TEST(AvoidanceParams, ValidateAndNames) {
  EXPECT_FALSE(AvoidanceParams{}.validate().has_value());
  AvoidanceParams p = plain_params();
  p.shrink_factor = 1.0;
  EXPECT_TRUE(p.validate().has_value());
  p = {};
  p.min_detection_range_m = 20.0;
  EXPECT_TRUE(p.validate().has_value());
  p = {};
  p.risk_threshold = 10.0;  // above e^1.5: never unsafe
  EXPECT_TRUE(p.validate().has_value());
  EXPECT_FALSE(Avoidance::create(p).has_value());
  for (const Strategy s : {Strategy::kSelection, Strategy::kScore, Strategy::kRiskBin,
                           Strategy::kSelectionNaive2022}) {
    EXPECT_EQ(parse_strategy(to_string(s)), s);
  }
  EXPECT_FALSE(parse_strategy("fuzzy").has_value());
  p = {};
  p.path_bins = -1;
  EXPECT_TRUE(p.validate().has_value());
  p = {};
  p.path_clearance_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(p.validate().has_value());
  EXPECT_NEAR(AvoidanceParams{}.risk_range_m(), (1.5 - std::log(0.005)) / 2.7, 1e-12);
}

TEST(Avoidance, ClearPathSteersAtTheGoalForEveryStrategy) {
  for (const Strategy s : {Strategy::kSelection, Strategy::kScore, Strategy::kRiskBin,
                           Strategy::kSelectionNaive2022}) {
    Avoidance a = make(s);
    const auto d = a.decide(list_of({buoy(5.0, -60.0)}), 23.4, 0);
    EXPECT_DOUBLE_EQ(d.bearing_body_deg, 23.4) << to_string(s);
    EXPECT_EQ(d.status, AvoidanceStatus::kClear) << to_string(s);
    EXPECT_EQ(d.side, Side::kNone);
    const auto e = a.decide(ObstacleList{}, -41.0, kTick);
    EXPECT_DOUBLE_EQ(e.bearing_body_deg, -41.0) << to_string(s);
    EXPECT_DOUBLE_EQ(e.speed_factor, 1.0);
  }
}

TEST(Avoidance, GoalOutsideTheFanSteersAtTheNearestEdge) {
  Avoidance a = make(Strategy::kSelection);
  const auto d = a.decide(ObstacleList{}, 150.0, 0);
  EXPECT_NEAR(d.bearing_body_deg, 89.5, 1e-9);
  const auto e = a.decide(ObstacleList{}, -150.0, kTick);
  EXPECT_NEAR(e.bearing_body_deg, -89.5, 1e-9);
}

TEST(Avoidance, EveryStrategyAvoidsABuoyOnTheGoalLineWithHullClearance) {
  const AvoidanceParams p = plain_params();
  const double hull = p.half_beam_m + p.clearance_m;
  for (const Strategy s : kOurs) {
    Avoidance a = make(s);
    const auto d = a.decide(list_of({buoy(2.0, 3.0, 0.1)}), 0.0, 0);
    EXPECT_EQ(d.status, AvoidanceStatus::kAvoiding) << to_string(s);
    EXPECT_NE(d.side, Side::kNone);
    EXPECT_GE(pass_distance(2.0, 3.0, d.bearing_body_deg), hull - 0.1) << to_string(s);
    EXPECT_LT(d.speed_factor, 1.0);  // 2 m is inside the slow-down range
    EXPECT_GT(d.speed_factor, 0.0);
  }
}

TEST(Avoidance, RiskBinsIgnoreLowRiskFarObstaclesSelectionDoesNot) {
  Avoidance risk = make(Strategy::kRiskBin);
  Avoidance sel = make(Strategy::kSelection);
  const auto l = list_of({buoy(5.0, 0.0)});
  const auto r = risk.decide(l, 0.0, 0);
  const auto s = sel.decide(l, 0.0, 0);
  EXPECT_EQ(r.status, AvoidanceStatus::kClear);  // e^(-2.7*5+1.5) is far below the threshold
  EXPECT_EQ(s.status, AvoidanceStatus::kAvoiding);
  const std::size_t ahead = risk.bins().index_of(0.0);
  EXPECT_GT(r.danger[ahead], 0.0F);
  EXPECT_LT(r.danger[ahead], 1.0F);
  EXPECT_FLOAT_EQ(s.danger[ahead], 1.0F);
}

TEST(Avoidance, ScoreGradesDangerAndBlocksNearObstacles) {
  Avoidance a = make(Strategy::kScore);
  const auto far = a.decide(list_of({buoy(6.0, 40.0)}), 0.0, 0);
  const std::size_t i = a.bins().index_of(40.0);
  EXPECT_GT(far.danger[i], 0.0F);
  EXPECT_LT(far.danger[i], 1.0F);
  const auto near = a.decide(list_of({buoy(2.0, 40.0)}), 40.0, kTick);
  EXPECT_FLOAT_EQ(near.danger[i], 1.0F);
  EXPECT_GT(std::abs(near.bearing_body_deg - 40.0), 10.0);
}

// ---- Each defect of the 2022 code: a case the naive version fails and ours passes. ----

TEST(Defects, WallSpanningTheWholeFanWithEndsOutsideIt) {
  AvoidanceParams p = plain_params();
  p.fan = {-60.0, 60.0, 1.0};
  // 2 m ahead, first point 5.4 m away (in range), both ends at +-68 deg: outside the fan.
  const auto wall = list_of({segment(2.0, -5.0, 2.0, 5.0)});
  Avoidance naive = make(Strategy::kSelectionNaive2022, p);
  const auto n = naive.decide(wall, 0.0, 0);
  EXPECT_EQ(n.status, AvoidanceStatus::kClear);  // defect: never saw the wall
  EXPECT_DOUBLE_EQ(n.bearing_body_deg, 0.0);
  EXPECT_DOUBLE_EQ(n.speed_factor, 1.0);
  for (const Strategy s : kOurs) {
    Avoidance a = make(s, p);
    const auto d = a.decide(wall, 0.0, 0);
    EXPECT_NE(d.status, AvoidanceStatus::kClear) << to_string(s);
    EXPECT_LT(d.speed_factor, 1.0) << to_string(s);
    EXPECT_GT(d.danger[a.bins().index_of(0.0)], 0.0F) << to_string(s);
  }
}

TEST(Defects, FirstPointFarButMiddleNear) {
  // First point ~10 m (beyond the 8 m range), but the wall passes 3 m ahead of the bow.
  const auto wall = list_of({segment(3.0, -9.5, 3.0, 2.0)});
  Avoidance naive = make(Strategy::kSelectionNaive2022);
  EXPECT_DOUBLE_EQ(naive.decide(wall, 0.0, 0).bearing_body_deg, 0.0);  // defect: straight on
  Avoidance a = make(Strategy::kSelection);
  const auto d = a.decide(wall, 0.0, 0);
  EXPECT_EQ(d.status, AvoidanceStatus::kAvoiding);
  EXPECT_GT(d.bearing_body_deg, 20.0);  // round the free (starboard) end
}

TEST(Defects, AllBlockedSlowsShrinksThenStopsOrBacksOff) {
  // A pocket: wall 0.9 m ahead and walls 0.9 m to each side.
  const auto pocket = list_of(
      {segment(0.9, -3.0, 0.9, 3.0), segment(-1.0, -0.9, 0.9, -0.9), segment(-1.0, 0.9, 0.9, 0.9)});
  Avoidance naive = make(Strategy::kSelectionNaive2022);
  const auto n = naive.decide(pocket, 10.0, 0);
  EXPECT_DOUBLE_EQ(n.bearing_body_deg, 10.0);  // defect: straight at the goal, full speed
  EXPECT_DOUBLE_EQ(n.speed_factor, 1.0);
  for (const Strategy s : kOurs) {
    Avoidance a = make(s);
    const auto d = a.decide(pocket, 10.0, 0);
    EXPECT_EQ(d.status, AvoidanceStatus::kBlockedStop) << to_string(s);
    EXPECT_DOUBLE_EQ(d.speed_factor, 0.0);
    EXPECT_GT(d.shrink_steps, 0);
    AvoidanceParams p = plain_params();
    p.all_blocked_policy = AllBlockedPolicy::kBackOff;
    Avoidance b = make(s, p);
    const auto e = b.decide(pocket, 10.0, 0);
    EXPECT_EQ(e.status, AvoidanceStatus::kBackOff) << to_string(s);
    EXPECT_LT(e.speed_factor, 0.0);
  }
}

TEST(Defects, AllBlockedAtFullRangeShrinksAndSlows) {
  AvoidanceParams p = plain_params();
  p.fan = {-60.0, 60.0, 1.0};
  const auto wall = list_of({segment(3.0, -20.0, 3.0, 20.0)});
  Avoidance a = make(Strategy::kSelection, p);
  const auto d = a.decide(wall, 0.0, 0);
  EXPECT_EQ(d.status, AvoidanceStatus::kBlockedSlow);
  EXPECT_GE(d.shrink_steps, 1);
  EXPECT_LT(d.effective_range_m, p.detection_range_m);
  EXPECT_LE(d.speed_factor, p.blocked_speed_factor);
}

TEST(Defects, ShrinkingFindsTheGapBetweenNearBuoysUnderAFarWall) {
  // A wall 4 m ahead closes every bin at 8 m; near buoys at +-30 deg leave a gap ahead once the
  // range is shrunk. The goal is at 20 deg: steer into the gap, at the side nearest the goal.
  AvoidanceParams p = plain_params();
  p.fan = {-60.0, 60.0, 1.0};
  const auto l =
      list_of({segment(4.0, -20.0, 4.0, 20.0), buoy(2.5, -30.0, 0.1), buoy(2.5, 30.0, 0.1)});
  Avoidance a = make(Strategy::kSelection, p);
  const auto d = a.decide(l, 20.0, 0);
  EXPECT_EQ(d.status, AvoidanceStatus::kBlockedSlow);
  EXPECT_GT(d.bearing_body_deg, 0.0);
  EXPECT_GE(pass_distance(2.5, 30.0, d.bearing_body_deg), p.half_beam_m + p.clearance_m - 0.1);
}

TEST(Defects, MarginGrowsNearAndShrinksFar) {
  const AvoidanceParams p = plain_params();
  const double hull = p.half_beam_m + p.clearance_m;
  // Near: the naive fixed 10 deg passes a buoy 1.5 m ahead closer than the half beam.
  const auto near = list_of({buoy(1.5, 0.0, 0.0)});
  Avoidance naive = make(Strategy::kSelectionNaive2022);
  const auto n = naive.decide(near, 0.0, 0);
  EXPECT_LT(pass_distance(1.5, 0.0, n.bearing_body_deg), p.half_beam_m);  // defect: a hit
  Avoidance a = make(Strategy::kSelection);
  const auto d = a.decide(near, 0.0, 0);
  EXPECT_GE(pass_distance(1.5, 0.0, d.bearing_body_deg), hull);
  // Far: ours turns less than the naive fixed margin, and still clears the hull.
  const auto far = list_of({buoy(7.5, 0.0, 0.0)});
  Avoidance naive2 = make(Strategy::kSelectionNaive2022);
  Avoidance b = make(Strategy::kSelection);
  const auto nf = naive2.decide(far, 0.0, 0);
  const auto df = b.decide(far, 0.0, 0);
  EXPECT_LT(std::abs(df.bearing_body_deg), std::abs(nf.bearing_body_deg));
  EXPECT_GE(pass_distance(7.5, 0.0, df.bearing_body_deg), hull);
}

TEST(Defects, ExactTieHasNoLeftBias) {
  // A buoy dead ahead on the goal line: both sides cost exactly the same.
  const auto sym = list_of({buoy(4.0, 0.0)});
  Avoidance naive = make(Strategy::kSelectionNaive2022);
  EXPECT_EQ(naive.decide(sym, 0.0, 0).side, Side::kPort);  // defect: always port
  // Ours: the more open side wins the tie. A far obstacle on the port side makes starboard
  // more open; its mirror image makes port more open.
  const auto port_cluttered = list_of({buoy(4.0, 0.0), buoy(6.0, -60.0, 1.0)});
  const auto stbd_cluttered = list_of({buoy(4.0, 0.0), buoy(6.0, 60.0, 1.0)});
  Avoidance naive2 = make(Strategy::kSelectionNaive2022);
  EXPECT_EQ(naive2.decide(port_cluttered, 0.0, 0).side, Side::kPort);  // defect
  for (const Strategy s : kOurs) {
    AvoidanceParams p = plain_params();
    p.risk_threshold = 1e-5;  // risk bins see 6 m too
    Avoidance a = make(s, p);
    EXPECT_EQ(a.decide(port_cluttered, 0.0, 0).side, Side::kStarboard) << to_string(s);
    Avoidance b = make(s, p);
    EXPECT_EQ(b.decide(stbd_cluttered, 0.0, 0).side, Side::kPort) << to_string(s);
    Avoidance c = make(s, p);
    // Perfect symmetry: starboard (COLREG rule 14), not a port default.
    EXPECT_EQ(c.decide(sym, 0.0, 0).side, Side::kStarboard) << to_string(s);
  }
}

TEST(Defects, JitterDeadAheadDoesNotFlipSides) {
  Avoidance naive = make(Strategy::kSelectionNaive2022);
  int naive_flips = 0;
  Side naive_prev = Side::kNone;
  for (const Strategy s : kOurs) {
    Avoidance a = make(s);
    Side prev = Side::kNone;
    int flips = 0;
    for (int k = 0; k < 60; ++k) {
      const double jitter = (k % 2 == 0) ? 0.5 : -0.5;
      const auto l = list_of({buoy(2.2, jitter, 0.3)});
      const core::TimeNs now = k * kTick;
      const auto d = a.decide(l, 0.0, now);
      ASSERT_NE(d.side, Side::kNone) << to_string(s);
      if (prev != Side::kNone && d.side != prev) ++flips;
      prev = d.side;
      if (s == Strategy::kSelection) {
        const auto n = naive.decide(l, 0.0, now);
        if (naive_prev != Side::kNone && n.side != naive_prev) ++naive_flips;
        naive_prev = n.side;
      }
    }
    EXPECT_EQ(flips, 0) << to_string(s);
  }
  EXPECT_GT(naive_flips, 20);  // defect: side to side every tick
}

TEST(Avoidance, SwitchesSideOnlyWhenClearlyBetterAfterTheHoldTime) {
  Avoidance a = make(Strategy::kSelection);
  // Buoy slightly to starboard: go port.
  auto d = a.decide(list_of({buoy(3.0, 2.0)}), 0.0, 0);
  ASSERT_EQ(d.side, Side::kPort);
  // A long obstacle now extends far to port: starboard is much better, but the hold is on.
  const auto shifted = list_of({segment(3.0, -6.0, 3.0, 0.3)});
  d = a.decide(shifted, 0.0, 5 * kTick);
  EXPECT_EQ(d.side, Side::kPort);
  d = a.decide(shifted, 0.0, 20 * kTick);  // hold over, better by far more than hysteresis
  EXPECT_EQ(d.side, Side::kStarboard);
  // The kept side losing every safe bin forces a switch at once, hold or not.
  const auto port_closed = list_of({segment(2.0, -8.0, 2.0, 0.2), segment(0.0, -1.0, 2.0, -1.0)});
  Avoidance b = make(Strategy::kSelection);
  ASSERT_EQ(b.decide(list_of({buoy(3.0, 2.0)}), 0.0, 0).side, Side::kPort);
  EXPECT_EQ(b.decide(port_closed, 0.0, kTick).side, Side::kStarboard);
}

TEST(Avoidance, ForgetsTheSideAfterBeingClear) {
  Avoidance a = make(Strategy::kSelection);
  ASSERT_EQ(a.decide(list_of({buoy(3.0, 2.0)}), 0.0, 0).side, Side::kPort);
  EXPECT_EQ(a.decide(ObstacleList{}, 0.0, kTick).status, AvoidanceStatus::kClear);
  // Long after: a buoy slightly to port now sends us to starboard (no stale memory).
  EXPECT_EQ(a.decide(list_of({buoy(3.0, -2.0)}), 0.0, 100 * kTick).side, Side::kStarboard);
}

// ---- Swept hull: the stern swings out of a turn (sensors at the bow, thruster at the stern). ----

AvoidanceParams swept() {
  AvoidanceParams p = plain_params();
  p.sweep_enabled = true;
  return p;
}

TEST(SweptHull, BuoyAlongsideTheStarboardSideRefusesAHardTurnToPort) {
  // A buoy's face 0.4 m off the starboard side, aft of the bow; the goal 60 deg to port.
  const auto alongside = list_of({segment(-0.35, 0.8, -0.65, 0.8)});
  for (const Strategy s : kOurs) {
    Avoidance plain = make(s);
    const auto d0 = plain.decide(alongside, -60.0, 0);
    EXPECT_NEAR(d0.bearing_body_deg, -60.0, 1e-9) << to_string(s);  // the bow ray sees nothing
    Avoidance a = make(s, swept());
    const auto d = a.decide(alongside, -60.0, 0);
    EXPECT_LT(d.sweep_port_deg, 60.0) << to_string(s);
    EXPECT_GE(d.sweep_starboard_deg, 89.5) << to_string(s);  // the stern swings away from it
    EXPECT_GE(d.bearing_body_deg, -d.sweep_port_deg - 0.5) << to_string(s);
    EXPECT_LT(d.bearing_body_deg, -1.0) << to_string(s);  // still turns toward the goal
    EXPECT_FLOAT_EQ(d.danger[a.bins().index_of(-60.0)], 1.0F) << to_string(s);
  }
  // The same buoy on the port quarter mirrors it.
  Avoidance m = make(Strategy::kSelection, swept());
  const auto e = m.decide(list_of({segment(-0.35, -0.8, -0.65, -0.8)}), 60.0, 0);
  EXPECT_LT(e.sweep_starboard_deg, 60.0);
  EXPECT_GE(e.sweep_port_deg, 89.5);
  EXPECT_LE(e.bearing_body_deg, e.sweep_starboard_deg + 0.5);
}

TEST(SweptHull, ABuoyAlreadyInsideTheClearanceDoesNotFreezeTheBoat) {
  // 0.1 m off the starboard side amidships: turning away (port) is refused at once, but the
  // boat may still go straight on or turn starboard, where the hull moves away from it.
  const auto close = list_of({segment(-0.3, 0.5, -0.6, 0.5)});
  Avoidance a = make(Strategy::kSelection, swept());
  const auto d = a.decide(close, 30.0, 0);
  EXPECT_LE(d.sweep_port_deg, 0.5 + 1e-9);
  EXPECT_GT(d.sweep_starboard_deg, 30.0);
  EXPECT_NEAR(d.bearing_body_deg, 30.0, 1e-9);
  EXPECT_EQ(d.status, AvoidanceStatus::kClear);
  const auto ahead = a.decide(close, 0.0, kTick);
  EXPECT_NEAR(ahead.bearing_body_deg, 0.0, 1e-9);
}

TEST(SweptHull, APlannedSubGoalThroughAGapMetAtASlantTakesThePathsNarrowerCorridor) {
  // Two buoys 2.8 m apart, their line at 45 deg to the bow, the gap's middle 4 m dead ahead
  // where the goal lies. Across the corridor ahead the buoys' faces come 0.75 m from the centre
  // line: inside the full corridor (0.45 + 0.35 m), outside the path's (0.45 + 0.15 m).
  const double half_gap = 1.4 / std::sqrt(2.0);
  const auto gap = list_of({buoy(std::hypot(4.0 + half_gap, half_gap),
                                 core::rad_to_deg(std::atan2(half_gap, 4.0 + half_gap)), 0.25),
                            buoy(std::hypot(4.0 - half_gap, half_gap),
                                 core::rad_to_deg(std::atan2(-half_gap, 4.0 - half_gap)), 0.25)});
  AvoidanceParams p = swept();
  p.strategy = Strategy::kScore;
  p.path_clearance_m = 0.15;
  for (const bool planned : {false, true}) {
    Avoidance a = make(Strategy::kScore, p);
    const auto d = a.decide(gap, 0.0, 0, planned);
    if (planned) {
      EXPECT_EQ(d.bearing_body_deg, 0.0);  // through the gap
    } else {
      EXPECT_GT(std::abs(d.bearing_body_deg), 5.0);  // the full margin refuses it
    }
  }
  // Off (negative), the planned sub-goal keeps the full corridor too.
  p.path_clearance_m = -1.0;
  Avoidance off = make(Strategy::kScore, p);
  EXPECT_GT(std::abs(off.decide(gap, 0.0, 0, true).bearing_body_deg), 5.0);
  // The narrower corridor still meets a buoy in it: the same turn away, planned or not.
  p.path_clearance_m = 0.15;
  Avoidance a = make(Strategy::kScore, p);
  Avoidance b = make(Strategy::kScore, p);
  const auto ahead = list_of({buoy(2.8, 4.0, 0.25)});
  const auto planned = a.decide(ahead, 0.0, 0, true);
  EXPECT_GT(std::abs(planned.bearing_body_deg), 5.0) << to_string(planned.status);
  EXPECT_EQ(planned.bearing_body_deg, b.decide(ahead, 0.0, 0, false).bearing_body_deg);
  // The corridor's ranges are kept between scans: a new scan replaces them.
  Avoidance c = make(Strategy::kScore, p);
  EXPECT_EQ(c.decide(gap, 0.0, 0, true).bearing_body_deg, 0.0);
  EXPECT_EQ(c.decide(ahead, 0.0, kTick, true).bearing_body_deg, planned.bearing_body_deg);
}

TEST(SweptHull, TheArcToAHeadingIsCheckedNotJustTheRayFromTheBow) {
  // A buoy 2.5 m out at 35 deg; the goal at 70 deg. A ray from the bow at 70 deg passes it
  // 1.4 m clear, but the boat cannot turn on the spot: on its 2.6 m arc it sails into the buoy.
  const auto l = list_of({buoy(2.5, 35.0, 0.2)});
  Avoidance plain = make(Strategy::kSelection);
  EXPECT_NEAR(plain.decide(l, 70.0, 0).bearing_body_deg, 70.0, 1e-9);
  Avoidance a = make(Strategy::kSelection, swept());
  const auto d = a.decide(l, 70.0, 0);
  EXPECT_EQ(d.status, AvoidanceStatus::kAvoiding);
  EXPECT_LT(d.bearing_body_deg, 35.0);  // passes inside, to port of the buoy
}

TEST(SweptHull, NoArcLeftFallsBackToTheRaysInsteadOfStoppingForGood) {
  // A wall 1.6 m ahead ending 1 m to starboard, a buoy abeam to starboard: no arc of the turn
  // radius gets out, but a boat at rest can turn onto a gap the bow rays see (about 60 deg).
  const auto l = list_of({segment(1.6, -6.0, 1.6, 1.0), segment(-0.15, 1.8, -0.45, 1.8)});
  for (const Strategy s : {Strategy::kSelection, Strategy::kScore}) {
    Avoidance plain = make(s);
    const auto p = plain.decide(l, 80.0, 0);
    ASSERT_NE(p.status, AvoidanceStatus::kBlockedStop) << to_string(s);
    Avoidance a = make(s, swept());
    const auto d = a.decide(l, 80.0, 0);
    EXPECT_EQ(d.status, AvoidanceStatus::kBlockedSlow) << to_string(s);
    EXPECT_DOUBLE_EQ(d.bearing_body_deg, p.bearing_body_deg) << to_string(s);
    EXPECT_LE(d.speed_factor, AvoidanceParams{}.blocked_speed_factor) << to_string(s);
    EXPECT_GT(d.speed_factor, 0.0) << to_string(s);
  }
}

TEST(SweptHull, TurnRoomLooksPastTheFanToAHalfTurn) {
  // A buoy where the hull lies at the end of a hard starboard half turn, 5.2 m to starboard.
  // The fan's 90 deg never reaches it; a turn back along a path does.
  const auto l = list_of({segment(1.2, 5.0, 1.2, 5.4)});
  Avoidance a = make(Strategy::kScore, swept());
  const auto d = a.decide(l, 0.0, 0);
  EXPECT_GE(d.sweep_starboard_deg, 89.5);
  EXPECT_DOUBLE_EQ(a.turn_room_deg(l, Side::kStarboard, 120.0), 120.0);
  const double half_turn = a.turn_room_deg(l, Side::kStarboard, 180.0);
  EXPECT_GT(half_turn, 120.0);
  EXPECT_LT(half_turn, 180.0);
  // To port the hull swings away from it; asking more than a half turn asks a half turn.
  EXPECT_DOUBLE_EQ(a.turn_room_deg(l, Side::kPort, 250.0), 180.0);
  // In a pocket narrower than the turning circle no half turn has room either way.
  const auto pocket = list_of(
      {segment(-3.0, -2.5, 3.0, -2.5), segment(3.0, -2.5, 3.0, 2.5), segment(3.0, 2.5, -3.0, 2.5)});
  (void)a.decide(pocket, 0.0, kTick);
  EXPECT_LT(a.turn_room_deg(pocket, Side::kPort, 150.0), 150.0);
  EXPECT_LT(a.turn_room_deg(pocket, Side::kStarboard, 150.0), 150.0);
  // Without the sweep there is nothing to tell.
  Avoidance plain = make(Strategy::kScore);
  (void)plain.decide(pocket, 0.0, 0);
  EXPECT_DOUBLE_EQ(plain.turn_room_deg(pocket, Side::kPort, 150.0), 150.0);
}

TEST(SweptHull, AsternRoomIsTheWaterBehindTheStern) {
  const AvoidanceParams p = swept();
  const double stern_m = p.bow_ahead_m - p.hull_length_m;
  Avoidance a = make(Strategy::kScore, p);
  EXPECT_EQ(a.astern_room_m(ObstacleList{}, 0.6), AngleBins::kNoObstacle);
  // A wall across the stern 0.3 m behind it: inside a 0.6 m look, 0.1 m from a 0.2 m one.
  const auto behind = list_of({segment(stern_m - 0.3, -1.0, stern_m - 0.3, 1.0)});
  EXPECT_DOUBLE_EQ(a.astern_room_m(behind, 0.6), 0.0);
  EXPECT_NEAR(a.astern_room_m(behind, 0.2), 0.1, 1e-9);
  // A wall alongside, 0.4 m off the side, is not astern.
  const auto alongside = list_of({segment(stern_m, p.half_beam_m + 0.4, 0.0, p.half_beam_m + 0.4)});
  EXPECT_NEAR(a.astern_room_m(alongside, 0.6), 0.4, 1e-9);
}

// Bin j's path range worked out the long way: every segment against the corridor (half-width
// w) that starts where the turn onto the bin's heading ends, nothing skipped.
double path_range_the_long_way(const AvoidanceParams& p, double center_deg,
                               const ObstacleList& list, double start_m, double reach_m) {
  const double a = core::deg_to_rad(std::min(std::abs(center_deg), 180.0));
  const double sign = center_deg < 0.0 ? -1.0 : 1.0;
  const double c = std::cos(a);
  const double sn = sign * std::sin(a);
  const double r = p.sweep_turn_radius_m;
  const double end_f = p.pivot_ahead_m + r * std::sin(a) - p.pivot_ahead_m * c;
  const double end_s = sign * r * (1.0 - c) - p.pivot_ahead_m * sn;
  const double w = p.half_beam_m + p.clearance_m;
  double range = start_m;
  for (std::uint32_t k = 0; k < list.count; ++k) {
    const ObstacleSegment& seg = list.segments[k];
    const double af = seg.begin.forward_m;
    const double as = seg.begin.starboard_m;
    const double bf = seg.end.forward_m;
    const double bs = seg.end.starboard_m;
    // The segment's nearest point to the boat, for the reach.
    const double df = bf - af;
    const double ds = bs - as;
    const double dd = df * df + ds * ds;
    const double t0 = dd > 0.0 ? std::clamp(-(af * df + as * ds) / dd, 0.0, 1.0) : 0.0;
    if (std::hypot(af + t0 * df, as + t0 * ds) > reach_m) continue;
    const auto to_f = [&](double f, double s) { return (f - end_f) * c + (s - end_s) * sn; };
    const auto to_s = [&](double f, double s) { return -(f - end_f) * sn + (s - end_s) * c; };
    const double f0 = to_f(af, as);
    const double s0 = to_s(af, as);
    const double f1 = to_f(bf, bs);
    const double s1 = to_s(bf, bs);
    double lo = 0.0;
    double hi = 1.0;
    for (const auto& [v0, v1] : {std::pair{w + s0, w + s1}, std::pair{w - s0, w - s1},
                                 std::pair{f0, f1}}) {  // keep v0 + (v1 - v0) t >= 0
      if (v0 < 0.0 && v1 < 0.0) lo = 2.0;
      if (v0 < 0.0 && v1 >= 0.0) lo = std::max(lo, v0 / (v0 - v1));
      if (v0 >= 0.0 && v1 < 0.0) hi = std::min(hi, v0 / (v0 - v1));
    }
    if (lo > hi) continue;
    const double f_near = std::min(f0 + (f1 - f0) * lo, f0 + (f1 - f0) * hi);
    range = std::min(range, r * a + std::max(0.0, f_near));
  }
  return range;
}

// The path ranges skip most (segment, bin) pairs by cheap tests in floats before the exact one:
// whatever they skip, every range is the one the exact test gives on every pair. Buoys, walls,
// segments reaching past 100 m (tested exactly) and points, on a half fan and a full circle.
TEST(SweptHull, PathRangesAreTheExactOnesWhateverTheCullingSkips) {
  std::mt19937_64 rng(20261129);
  std::uniform_real_distribution<double> near_m(-14.0, 14.0);
  std::uniform_real_distribution<double> far_m(-160.0, 160.0);
  std::uniform_real_distribution<double> length_m(0.05, 1.0);
  std::uniform_real_distribution<double> angle(-3.2, 3.2);
  for (const bool full_circle : {false, true}) {
    for (const Strategy strategy : {Strategy::kScore, Strategy::kRiskBin}) {
      AvoidanceParams p = swept();
      p.strategy = strategy;
      if (full_circle) {
        p.fan.min_deg = -180.0;
        p.fan.max_deg = 180.0;
        p.fan.bin_width_deg = 0.5;
        p.pivot_ahead_m = 0.9;
      }
      Avoidance a = make(strategy, p);
      const bool capped = strategy != Strategy::kRiskBin;
      const double start_m = capped ? p.detection_range_m : AngleBins::kNoObstacle;
      const double reach_m = capped ? 1e9
                                    : p.detection_range_m + p.sweep_turn_radius_m * core::kPi +
                                          std::abs(p.pivot_ahead_m);
      for (int scene = 0; scene < 60; ++scene) {
        ObstacleList list;
        for (int k = 0; k < 40; ++k) {
          const double f = near_m(rng);
          const double s = near_m(rng);
          const double heading = angle(rng);
          const double len = k % 5 == 0 ? 12.0 : length_m(rng);  // a wall, or a buoy
          ObstacleSegment seg =
              segment(f, s, f + len * std::cos(heading), s + len * std::sin(heading));
          if (k % 5 == 1) seg = segment(f, s, far_m(rng), far_m(rng));  // reaching far off
          if (k % 5 == 2) seg = segment(f, s, f, s);                    // a point
          ASSERT_TRUE(list.push(seg));
        }
        (void)a.decide(list, 0.0, scene * 100'000'000LL);
        for (std::size_t j = 0; j < a.bins().size(); ++j) {
          const double want =
              path_range_the_long_way(p, a.bins().center_deg(j), list, start_m, reach_m);
          ASSERT_NEAR(a.path_range_m(j), want, 1e-9 * std::max(1.0, want))
              << "bin " << j << " (" << a.bins().center_deg(j) << " deg), scene " << scene
              << (full_circle ? ", full circle" : ", half fan") << ", " << to_string(strategy);
        }
      }
    }
  }
}

TEST(SweptHull, OnByDefaultAndRejectsBadGeometry) {
  EXPECT_TRUE(AvoidanceParams{}.sweep_enabled);
  AvoidanceParams p = swept();
  EXPECT_FALSE(p.validate().has_value());
  p.bow_ahead_m = 2.0;  // longer than the hull
  EXPECT_TRUE(p.validate().has_value());
  p = swept();
  p.sweep_step_deg = 0.0;
  EXPECT_TRUE(p.validate().has_value());
  p = swept();
  p.sweep_turn_radius_m = -1.0;
  EXPECT_TRUE(p.validate().has_value());
  // No obstacles: nothing is refused.
  Avoidance a = make(Strategy::kScore, swept());
  const auto d = a.decide(ObstacleList{}, -80.0, 0);
  EXPECT_NEAR(d.bearing_body_deg, -80.0, 1e-9);
  EXPECT_GE(d.sweep_port_deg, 89.5);
  EXPECT_GE(d.sweep_starboard_deg, 89.5);
}

TEST(Avoidance, Deterministic) {
  for (const Strategy s : {Strategy::kSelection, Strategy::kScore, Strategy::kRiskBin,
                           Strategy::kSelectionNaive2022}) {
    AvoidanceParams p = plain_params();
    p.sweep_enabled = s != Strategy::kRiskBin;  // with and without the swept hull
    Avoidance a = make(s, p);
    Avoidance b = make(s, p);
    for (int k = 0; k < 40; ++k) {
      const double t = 0.37 * k;
      const auto l = list_of({buoy(2.0 + std::fmod(t, 5.0), 30.0 * std::sin(t)),
                              segment(5.0, -4.0 + std::cos(t), 6.0, 3.0), buoy(1.5, -70.0)});
      const double goal = 40.0 * std::sin(0.1 * k);
      const auto x = a.decide(l, goal, k * kTick);
      const auto y = b.decide(l, goal, k * kTick);
      ASSERT_EQ(x.bearing_body_deg, y.bearing_body_deg);
      ASSERT_EQ(x.speed_factor, y.speed_factor);
      ASSERT_EQ(x.status, y.status);
      ASSERT_EQ(x.side, y.side);
      ASSERT_EQ(0, std::memcmp(x.danger.data(), y.danger.data(), sizeof(x.danger)));
    }
  }
}

// Between scans the mission decides every tick on the same list with a new goal; what depends
// on the obstacles alone is then reused. The same list in another order (equal geometry, but
// worked out again) gives bit for bit the same decisions.
TEST(Avoidance, ReusedGeometryDecidesAsFreshGeometry) {
  bool fresh_order = true;
  const ObstacleList list = list_of({buoy(3.0, 5.0), buoy(4.5, -20.0), segment(2.0, 2.0, 2.5, 3.5),
                                     segment(1.2, -1.5, 1.4, -0.6), buoy(6.0, 40.0)});
  ObstacleList reversed = list;
  std::reverse(reversed.segments.begin(), reversed.segments.begin() + reversed.count);
  for (const Strategy s : {Strategy::kSelection, Strategy::kScore, Strategy::kRiskBin}) {
    for (const bool sweep : {false, true}) {
      AvoidanceParams p = plain_params();
      p.sweep_enabled = sweep;
      Avoidance kept = make(s, p);
      Avoidance fresh = make(s, p);
      core::TimeNs now = core::kNsPerSec;
      for (const double goal : {0.0, 12.0, -35.0, 70.0, -5.0}) {
        const AvoidanceDecision a = kept.decide(list, goal, now);
        // Alternating the order makes `fresh` work the geometry out on every call.
        const AvoidanceDecision b = fresh.decide(fresh_order ? reversed : list, goal, now);
        fresh_order = !fresh_order;
        EXPECT_EQ(a.bearing_body_deg, b.bearing_body_deg) << to_string(s) << " " << goal;
        EXPECT_EQ(a.speed_factor, b.speed_factor);
        EXPECT_EQ(a.status, b.status);
        EXPECT_EQ(a.side, b.side);
        EXPECT_EQ(a.sweep_port_deg, b.sweep_port_deg);
        EXPECT_EQ(a.sweep_starboard_deg, b.sweep_starboard_deg);
        EXPECT_EQ(a.nearest_m, b.nearest_m);
        EXPECT_EQ(a.danger, b.danger);
        now += 20 * core::kNsPerMs;
      }
    }
  }
}

}  // namespace
}  // namespace coxswain::guidance
