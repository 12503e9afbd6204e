// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/nav_map.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "coxswain/core/angles.hpp"

namespace coxswain::guidance {
namespace {

using core::NavPoint;

const perception::HullBox kHull{-2.2, 0.1, -0.65, 0.65};

NavMapParams small_map() {
  NavMapParams p;
  p.size_north_m = 60.0;
  p.size_east_m = 40.0;
  return p;
}

// A scan (body frame at `pose`) of straight navigation-frame walls, one beam per half degree:
// each beam ends on the nearest wall it meets, or returns nothing.
msg::LidarScan scan_of(const core::NavPose& pose,
                       const std::vector<std::pair<NavPoint, NavPoint>>& walls) {
  msg::LidarScan scan;
  scan.max_range_m = 25.0F;
  for (int i = 0; i < 720; ++i) {
    const double b = -180.0 + 0.5 * i;
    const double a = core::deg_to_rad(pose.heading_deg + b);
    const double dn = std::cos(a);
    const double de = std::sin(a);
    double best = 1e9;
    for (const auto& [p, q] : walls) {
      // Ray (pose + t d) against segment p + s (q - p).
      const double wn = q.north_m - p.north_m;
      const double we = q.east_m - p.east_m;
      const double den = dn * we - de * wn;
      if (std::abs(den) < 1e-12) continue;
      const double rn = p.north_m - pose.position.north_m;
      const double re = p.east_m - pose.position.east_m;
      const double t = (rn * we - re * wn) / den;
      const double s = (rn * de - re * dn) / den;
      if (t > 0.0 && s >= 0.0 && s <= 1.0) best = std::min(best, t);
    }
    if (best < 25.0) (void)scan.push({static_cast<float>(b), static_cast<float>(best), 200, 0});
  }
  return scan;
}

bool occupied_at(const NavMap& m, NavPoint p) {
  const auto c = m.cell_of(p);
  return c && m.occupied(m.index(*c));
}

TEST(NavMap, ABeamMarksWhereItEndsAndClearsTheCellsBeforeIt) {
  NavMap m(small_map(), {}, {});
  const core::NavPose pose{{0.0, 0.0}, 0.0};
  const auto wall = scan_of(pose, {{{5.0, -1.0}, {5.0, 1.0}}});
  m.add_scan(wall, pose, kHull);
  EXPECT_TRUE(occupied_at(m, {5.05, 0.0}));
  const auto c = m.cell_of({2.5, 0.0});
  ASSERT_TRUE(c);
  EXPECT_LT(m.log_odds(m.index(*c)), 0.0F);  // seen through: evidence of free water
  const auto behind = m.cell_of({7.0, 0.0});
  ASSERT_TRUE(behind);
  EXPECT_EQ(m.log_odds(m.index(*behind)), 0.0F);  // never seen: unknown
}

TEST(NavMap, AnObstacleThatMovedAwayIsClearedByTheBeamsThatNowPassThroughIt) {
  NavMap m(small_map(), {}, {});
  const core::NavPose pose{{0.0, 0.0}, 0.0};
  for (int i = 0; i < 3; ++i) m.add_scan(scan_of(pose, {{{5.0, -1.0}, {5.0, 1.0}}}), pose, kHull);
  ASSERT_TRUE(occupied_at(m, {5.05, 0.0}));
  // The same wall now 3 m farther: the beams pass through the old cells.
  int scans = 0;
  while (occupied_at(m, {5.05, 0.0}) && scans < 20) {
    m.add_scan(scan_of(pose, {{{8.0, -1.0}, {8.0, 1.0}}}), pose, kHull);
    ++scans;
  }
  EXPECT_FALSE(occupied_at(m, {5.05, 0.0}));
  EXPECT_LE(scans, 6);  // cleared by beams within a few scans, not by slow decay
  EXPECT_TRUE(occupied_at(m, {8.05, 0.0}));
}

TEST(NavMap, ReturnsInsideTheHullBoxAreIgnored) {
  NavMap m(small_map(), {}, {});
  msg::LidarScan scan;
  (void)scan.push({180.0F, 1.0F, 200, 0});  // astern, inside the hull box
  m.add_scan(scan, {{0.0, 0.0}, 0.0}, kHull);
  EXPECT_TRUE(m.lidar_occupied().empty());
}

TEST(NavMap, TheKnownLayerHoldsEverythingOutsideTheBoundaryAndInsideANoGoPolygon) {
  NavMapParams p;
  p.resolution_m = 0.5;
  p.margin_m = 3.0;
  const std::vector<NavPoint> boundary{{-5.0, -10.0}, {-5.0, 10.0}, {35.0, 10.0}, {35.0, -10.0}};
  const std::vector<std::vector<NavPoint>> no_go{{{10.0, -2.0}, {10.0, 2.0}, {14.0, 0.0}}};
  NavMap m(p, boundary, no_go);
  // Sized from the boundary's box plus the margin: 46 m x 26 m at 0.5 m.
  EXPECT_EQ(m.rows(), 92U);
  EXPECT_EQ(m.cols(), 52U);
  EXPECT_DOUBLE_EQ(m.origin().north_m, -8.0);
  EXPECT_DOUBLE_EQ(m.origin().east_m, -13.0);
  EXPECT_TRUE(occupied_at(m, {0.0, 11.0}));   // outside the boundary
  EXPECT_TRUE(occupied_at(m, {36.0, 0.0}));   // outside the boundary
  EXPECT_FALSE(occupied_at(m, {0.0, 9.0}));   // inside
  EXPECT_TRUE(occupied_at(m, {11.0, 0.0}));   // inside the no-go triangle
  EXPECT_FALSE(occupied_at(m, {11.0, 3.0}));  // beside it
  EXPECT_TRUE(m.lidar_occupied().empty());    // the known layer is not lidar evidence
  m.clear_evidence();
  EXPECT_TRUE(occupied_at(m, {11.0, 0.0}));  // and survives forgetting it
}

TEST(NavMap, RejectsInvalidParametersAndAreasTooLargeForTheCells) {
  NavMapParams p = small_map();
  p.resolution_m = 0.01;
  EXPECT_THROW(NavMap(p, {}, {}), std::invalid_argument);
  p = small_map();
  p.size_north_m = 1000.0;
  p.size_east_m = 1000.0;
  EXPECT_THROW(NavMap(p, {}, {}), std::invalid_argument);
  p = small_map();
  p.occupied_log_odds = 10.0F;
  EXPECT_THROW(NavMap(p, {}, {}), std::invalid_argument);
}

// A square post `side_m` wide centred on `c`, as four walls.
std::vector<std::pair<NavPoint, NavPoint>> post(NavPoint c, double side_m) {
  const double h = 0.5 * side_m;
  const NavPoint a{c.north_m - h, c.east_m - h};
  const NavPoint b{c.north_m - h, c.east_m + h};
  const NavPoint d{c.north_m + h, c.east_m + h};
  const NavPoint e{c.north_m + h, c.east_m - h};
  return {{a, b}, {b, d}, {d, e}, {e, a}};
}

TEST(NavMap, ABuoySeenBetweenBeamsThatPassBesideItStaysAnObstacle) {
  // The beams either side of a small buoy cross the corners of its cells; were they cleared
  // beam by beam, a boat sailing past would erase the buoy while still seeing it.
  NavMap m(small_map(), {}, {});
  const NavPoint buoy{5.0, 1.1};
  for (int i = 0; i <= 40; ++i) {
    const core::NavPose pose{{0.15 * i, 0.0}, 0.0};
    m.add_scan(scan_of(pose, post(buoy, 0.12)), pose, kHull);
  }
  // The cell the near face of the buoy lies in, seen from every pose.
  EXPECT_TRUE(occupied_at(m, {buoy.north_m - 0.05, buoy.east_m}));
  // No cell holding a piece of the buoy's outline was ever taken for open water.
  for (const auto& [a, b] : post(buoy, 0.12)) {
    for (int k = 0; k <= 15; ++k) {
      const double t = k / 15.0;
      const NavPoint q{a.north_m + t * (b.north_m - a.north_m),
                       a.east_m + t * (b.east_m - a.east_m)};
      const auto c = m.cell_of(q);
      ASSERT_TRUE(c);
      EXPECT_GE(m.log_odds(m.index(*c)), 0.0F) << q.north_m << ", " << q.east_m;
    }
  }
  // The water before it, crossed by every beam, is seen free.
  const auto c = m.cell_of({4.0, 1.0});
  ASSERT_TRUE(c);
  EXPECT_LT(m.log_odds(m.index(*c)), 0.0F);
}

TEST(NavMap, ABeamWithNoReturnClearsItsWholeLengthUnlessToldNotTo) {
  msg::LidarScan open_water;
  open_water.max_range_m = 25.0F;
  for (int i = 0; i < 720; ++i)
    (void)open_water.push({-180.0F + 0.5F * static_cast<float>(i), 0.0F, 0, 0});
  const core::NavPose pose{{0.0, 0.0}, 0.0};
  NavMap m(small_map(), {}, {});
  m.add_scan(open_water, pose, kHull);
  for (const NavPoint p : {NavPoint{5.0, 0.0}, NavPoint{-6.0, 4.0}, NavPoint{0.0, 10.0}}) {
    const auto c = m.cell_of(p);
    ASSERT_TRUE(c);
    EXPECT_LT(m.log_odds(m.index(*c)), 0.0F) << p.north_m << ", " << p.east_m;
  }
  const auto far = m.cell_of({0.0, 15.0});  // beyond map.max_range_m (12 m)
  ASSERT_TRUE(far);
  EXPECT_EQ(m.log_odds(m.index(*far)), 0.0F);
  EXPECT_TRUE(m.lidar_occupied().empty());

  NavMapParams p = small_map();
  p.no_return_clears = false;
  NavMap strict(p, {}, {});
  strict.add_scan(open_water, pose, kHull);
  const auto c = strict.cell_of({5.0, 0.0});
  ASSERT_TRUE(c);
  EXPECT_EQ(strict.log_odds(strict.index(*c)), 0.0F);
}

// A wall nearer than the scanner's least range (0.2 m) gives no return on the beams that meet it
// square; the beams that meet it at a slant still return, very near.
msg::LidarScan scan_against_wall(const core::NavPose& pose,
                                 const std::vector<std::pair<NavPoint, NavPoint>>& walls) {
  msg::LidarScan scan = scan_of(pose, walls);
  for (std::uint32_t i = 0; i < scan.point_count; ++i) {
    if (scan.points[i].range_m < 0.2F) scan.points[i].range_m = 0.0F;
  }
  return scan;
}

TEST(NavMap, AHullAgainstAWallDoesNotMarkTheWaterBehindItAsSeen) {
  const std::vector<std::pair<NavPoint, NavPoint>> wall{{{6.0, -8.0}, {6.0, 8.0}}};
  // Log-odds of a cell 1 m behind the wall after the boat has lain against it.
  const auto behind = [&](const NavMapParams& params) {
    NavMap m(params, {}, {});
    const core::NavPose far_pose{{0.0, 0.0}, 0.0};
    for (int i = 0; i < 3; ++i) m.add_scan(scan_of(far_pose, wall), far_pose, kHull);
    // The bow against the wall: 0.12 m short of it.
    const core::NavPose against{{5.88, 0.0}, 0.0};
    for (int i = 0; i < 20; ++i) m.add_scan(scan_against_wall(against, wall), against, kHull);
    for (const double e : {-0.5, 0.0, 0.5}) EXPECT_TRUE(occupied_at(m, {6.0, e})) << e;
    const auto c = m.cell_of({7.0, 0.0});
    return m.log_odds(m.index(*c));
  };
  EXPECT_EQ(behind(small_map()), 0.0F);  // never seen: the wall hides it
  NavMapParams unguarded = small_map();
  unguarded.no_return_near_m = 0.0;
  EXPECT_LT(behind(unguarded), 0.0F);  // the square beams' "no return" would clear it
}

TEST(NavMap, ABuoyAsternInsideTheHullBoxIsNotClearedByTheBeamsBesideIt) {
  // The boat sails on past a buoy until it lies astern inside the hull box (returns there are
  // taken for the boat itself): the beams that hit it are dropped, and the beams either side of
  // it reach the wall far behind. The buoy must stay on the map -- the boat may back onto it.
  NavMap m(small_map(), {}, {});
  const NavPoint buoy{5.0, 0.0};
  auto world = post(buoy, 0.12);
  world.push_back({{-8.0, -8.0}, {-8.0, 8.0}});
  for (int i = 0; i <= 10; ++i) {
    const core::NavPose pose{{0.3 * i, 0.0}, 0.0};
    m.add_scan(scan_of(pose, world), pose, kHull);
  }
  ASSERT_TRUE(occupied_at(m, {buoy.north_m - 0.05, buoy.east_m}));
  // Past it, heading on: the buoy 1.5 m behind the lidar, inside the box (stern at -1.1 m).
  const core::NavPose past{{buoy.north_m + 1.5, 0.0}, 0.0};
  for (int i = 0; i < 20; ++i) m.add_scan(scan_of(past, world), past, kHull);
  EXPECT_TRUE(occupied_at(m, {buoy.north_m - 0.05, buoy.east_m}));
}

// A dead end open toward the boat: the goal lies straight on behind its back wall.
std::vector<std::pair<NavPoint, NavPoint>> u_walls() {
  return {{{10.0, -3.0}, {10.0, 3.0}}, {{5.0, -3.0}, {10.0, -3.0}}, {{5.0, 3.0}, {10.0, 3.0}}};
}

bool inside_u(NavPoint p) {
  return p.north_m > 4.5 && p.north_m < 10.5 && std::abs(p.east_m) < 3.5;
}

TEST(MapPlanner, PlansRoundADeadEndOpenTowardTheBoatAndItsSubGoalIsNotInside) {
  NavMap m(small_map(), {}, {});
  const core::NavPose pose{{0.0, 0.0}, 0.0};
  m.add_scan(scan_of(pose, u_walls()), pose, kHull);
  MapPlanner planner(m, MapPlannerParams{}, 0.45);
  const NavPoint goal{20.0, 0.0};
  ASSERT_EQ(planner.plan(m, pose.position, goal), PlanStatus::kOk);
  const auto& path = planner.path();
  ASSERT_GE(path.size(), 3U);
  bool round = false;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const NavPoint a = path[i - 1];
    const NavPoint b = path[i];
    for (int k = 0; k <= 50; ++k) {
      const double t = k / 50.0;
      const NavPoint q{a.north_m + t * (b.north_m - a.north_m),
                       a.east_m + t * (b.east_m - a.east_m)};
      EXPECT_FALSE(inside_u(q)) << q.north_m << ", " << q.east_m;
      const auto c = planner.view().cell_of(q);
      ASSERT_TRUE(c);
      EXPECT_NE(planner.view().at(*c), CellState::kOccupied);
    }
    round = round || std::abs(b.east_m) > 3.5;
  }
  EXPECT_TRUE(round);
  const auto sg = planner.subgoal(pose.position);
  ASSERT_TRUE(sg);
  EXPECT_FALSE(inside_u(*sg));
  EXPECT_NEAR(core::distance_m(pose.position, *sg), MapPlannerParams{}.lookahead_m, 0.3);
  // The straight line to the goal would have been into the U.
  EXPECT_TRUE(inside_u({7.0, 0.0}));
}

TEST(MapPlanner, ABlockedGoalMovesToTheNearestFreeCellAndAnEnclosedOneHasNoPath) {
  NavMap m(small_map(), {}, {});
  const core::NavPose pose{{0.0, 0.0}, 0.0};
  m.add_scan(scan_of(pose, {{{6.0, -2.0}, {6.0, 2.0}}}), pose, kHull);
  MapPlanner planner(m, MapPlannerParams{}, 0.45);
  EXPECT_EQ(planner.plan(m, pose.position, {6.1, 0.0}), PlanStatus::kOk);  // on the wall
  // A closed box round the boat.
  NavMap boxed(small_map(), {}, {});
  boxed.add_scan(scan_of(pose, {{{4.0, -4.0}, {4.0, 4.0}},
                                {{-4.0, -4.0}, {-4.0, 4.0}},
                                {{-4.0, -4.0}, {4.0, -4.0}},
                                {{-4.0, 4.0}, {4.0, 4.0}}}),
                 pose, kHull);
  MapPlanner p2(boxed, MapPlannerParams{}, 0.45);
  EXPECT_EQ(p2.plan(boxed, pose.position, {20.0, 0.0}), PlanStatus::kNoPath);
  EXPECT_FALSE(p2.subgoal(pose.position).has_value());
}

TEST(MapPlanner, TheExpansionBudgetBoundsOnePlan) {
  NavMap m(small_map(), {}, {});
  MapPlannerParams p;
  p.max_expansions = 10;
  MapPlanner planner(m, p, 0.45);
  EXPECT_EQ(planner.plan(m, {0.0, 0.0}, {20.0, 10.0}), PlanStatus::kBudget);
  EXPECT_LE(planner.expanded(), 10U);
}

TEST(MapPlanner, AWeightedHeuristicIsPassedOnAndOutOfRangeWeightsAreRejected) {
  NavMap m(small_map(), {}, {});
  MapPlannerParams p;
  MapPlanner exact(m, p, 0.45);
  ASSERT_EQ(exact.plan(m, {0.0, 0.0}, {20.0, 10.0}), PlanStatus::kOk);
  p.heuristic_weight = 1.5;
  MapPlanner weighted(m, p, 0.45);
  ASSERT_EQ(weighted.plan(m, {0.0, 0.0}, {20.0, 10.0}), PlanStatus::kOk);
  EXPECT_LT(weighted.expanded(), exact.expanded());
  for (const double w : {0.99, 5.01, std::nan("")}) {
    p.heuristic_weight = w;
    EXPECT_THROW(MapPlanner(m, p, 0.45), std::invalid_argument) << w;
  }
}

TEST(MapPlanner, KnownNoGoAreasAreInflatedAndPlannedAround) {
  NavMapParams mp = small_map();
  const std::vector<std::vector<NavPoint>> no_go{
      {{8.0, -6.0}, {8.0, 6.0}, {12.0, 6.0}, {12.0, -6.0}}};
  NavMap m(mp, {}, no_go);
  MapPlanner planner(m, MapPlannerParams{}, 0.45);
  ASSERT_EQ(planner.plan(m, {0.0, 0.0}, {20.0, 0.0}), PlanStatus::kOk);
  double widest = 0.0;
  for (const NavPoint& q : planner.path()) widest = std::max(widest, std::abs(q.east_m));
  EXPECT_GT(widest, 6.5);  // round the polygon's end with the hull's clearance
}

// The path's least distance from a wall along the line to the goal, 1 m to its side.
double least_distance_from_side_wall(const MapPlannerParams& params) {
  NavMap m(small_map(), {}, {});
  const std::vector<std::pair<NavPoint, NavPoint>> wall{{{2.0, 1.0}, {18.0, 1.0}}};
  for (const double n : {0.0, 6.0, 12.0}) {
    const core::NavPose pose{{n, -2.0}, 0.0};
    m.add_scan(scan_of(pose, wall), pose, kHull);
  }
  MapPlanner planner(m, params, 0.45);
  EXPECT_EQ(planner.plan(m, {0.0, 0.0}, {20.0, 0.0}), PlanStatus::kOk);
  double least = 1e9;
  const auto& path = planner.path();
  for (std::size_t i = 1; i < path.size(); ++i) {
    for (int k = 0; k <= 100; ++k) {
      const double t = k / 100.0;
      const NavPoint q{path[i - 1].north_m + t * (path[i].north_m - path[i - 1].north_m),
                       path[i - 1].east_m + t * (path[i].east_m - path[i - 1].east_m)};
      if (q.north_m > 5.0 && q.north_m < 15.0) least = std::min(least, 1.0 - q.east_m);
    }
  }
  return least;
}

TEST(MapPlanner, ThePathKeepsItsDistanceFromAWallWhereThereIsRoom) {
  MapPlannerParams hard_only;
  hard_only.clearance_cost = 0.0;
  const double without = least_distance_from_side_wall(hard_only);
  MapPlannerParams soft;
  soft.clearance_cost = 4.0;
  const double with = least_distance_from_side_wall(soft);
  EXPECT_LT(without, 1.3);  // the straight line, 1 m off (outside the 0.65 m inflation)
  EXPECT_GT(with, without + 0.5);
}

TEST(MapPlanner, TheSubGoalIsReachedInAStraightLineNeverRoundACorner) {
  // A wall across the way with a gap at its west end: the path turns the wall's end, and the
  // sub-goal stays on the near side of the turn until the boat can see past it.
  NavMap m(small_map(), {}, {});
  const std::vector<std::pair<NavPoint, NavPoint>> wall{{{6.0, -3.0}, {6.0, 12.0}}};
  const core::NavPose pose{{0.0, 0.0}, 0.0};
  m.add_scan(scan_of(pose, wall), pose, kHull);
  MapPlannerParams params;
  params.lookahead_m = 12.0;
  params.line_of_sight_min_m = 0.25;
  MapPlanner planner(m, params, 0.45);
  ASSERT_EQ(planner.plan(m, pose.position, {12.0, 0.0}), PlanStatus::kOk);
  const auto sg = planner.subgoal(pose.position);
  ASSERT_TRUE(sg);
  for (int k = 0; k <= 100; ++k) {
    const double t = k / 100.0;
    const NavPoint q{t * sg->north_m, t * sg->east_m};
    const auto c = planner.view().cell_of(q);
    ASSERT_TRUE(c);
    EXPECT_NE(planner.view().at(*c), CellState::kOccupied) << q.north_m << ", " << q.east_m;
  }
  EXPECT_LT(sg->east_m, -3.0);  // toward the gap
  // The same plan with the look-ahead alone (no line of sight) aims past the corner; asked for
  // a sub-goal in plain sight, it comes back to the near side.
  MapPlannerParams plain = params;
  plain.line_of_sight_min_m = plain.lookahead_m;
  MapPlanner ahead(m, plain, 0.45);
  ASSERT_EQ(ahead.plan(m, pose.position, {12.0, 0.0}), PlanStatus::kOk);
  const auto far_sg = ahead.subgoal(pose.position);
  const auto near_sg = ahead.subgoal(pose.position, 0.25);
  ASSERT_TRUE(far_sg && near_sg);
  EXPECT_GT(far_sg->north_m, 6.0);  // beyond the wall's line: round the corner
  EXPECT_LT(near_sg->north_m, 6.0);
  EXPECT_NEAR(near_sg->north_m, sg->north_m, 1e-9);
  EXPECT_NEAR(near_sg->east_m, sg->east_m, 1e-9);
}

TEST(MapPlanner, AlongPathWalksThePathWhetherOrNotThePointIsInSight) {
  NavMap m(small_map(), {}, {});
  const std::vector<std::pair<NavPoint, NavPoint>> wall{{{6.0, -3.0}, {6.0, 12.0}}};
  const core::NavPose pose{{0.0, 0.0}, 0.0};
  m.add_scan(scan_of(pose, wall), pose, kHull);
  MapPlanner planner(m, MapPlannerParams{}, 0.45);
  EXPECT_FALSE(planner.along_path(pose.position, 1.0).has_value());  // no plan yet
  ASSERT_EQ(planner.plan(m, pose.position, {12.0, 0.0}), PlanStatus::kOk);
  const std::vector<NavPoint>& path = planner.path();
  double length_m = 0.0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) length_m += distance_m(path[i], path[i + 1]);
  // Each point lies on the path, at the distance asked along it from the start.
  for (const double ahead_m : {0.0, 1.5, 4.0, 0.5 * length_m}) {
    const auto q = planner.along_path(pose.position, ahead_m);
    ASSERT_TRUE(q);
    double walked_m = 0.0;
    double off_m = 1e9;
    double at_m = 0.0;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
      const double seg_m = distance_m(path[i], path[i + 1]);
      const double d = distance_m(path[i], *q) + distance_m(*q, path[i + 1]) - seg_m;
      if (d < off_m) {
        off_m = d;
        at_m = walked_m + distance_m(path[i], *q);
      }
      walked_m += seg_m;
    }
    EXPECT_LT(off_m, 1e-6) << ahead_m;
    EXPECT_NEAR(at_m, ahead_m, 0.3) << ahead_m;  // from the path point nearest the boat
  }
  // Past its end: the end.
  const auto end = planner.along_path(pose.position, length_m + 10.0);
  ASSERT_TRUE(end);
  EXPECT_NEAR(end->north_m, path.back().north_m, 1e-12);
  EXPECT_NEAR(end->east_m, path.back().east_m, 1e-12);
}

TEST(MapPlanner, AStartOnAWallLeavesItOnTheSideTheBoatCameFrom) {
  // A thin wall across the way, open round its west end. A boat whose position lies on the
  // wall (its bow against it, the estimate a little inside) must back off on its own side and
  // go round, never plan straight through to the goal beyond.
  NavMap m(small_map(), {}, {});
  const std::vector<std::pair<NavPoint, NavPoint>> wall{{{6.0, -3.0}, {6.0, 12.0}}};
  const core::NavPose pose{{0.0, 0.0}, 0.0};
  m.add_scan(scan_of(pose, wall), pose, kHull);
  const NavPoint goal{12.0, 0.0};
  const NavPoint on_wall{6.05, 0.0};
  {
    const auto c = m.cell_of(on_wall);
    ASSERT_TRUE(c && m.occupied(m.index(*c)));
  }
  MapPlanner planner(m, MapPlannerParams{}, 0.45);
  // Approaching from the south: every start off the wall is remembered.
  ASSERT_EQ(planner.plan(m, {4.5, 0.0}, goal), PlanStatus::kOk);
  ASSERT_EQ(planner.plan(m, on_wall, goal), PlanStatus::kOk);
  const auto& path = planner.path();
  ASSERT_GE(path.size(), 3U);
  EXPECT_LT(path.front().north_m, 6.0);
  EXPECT_LT(path[1].north_m, 6.0);
  double westmost = 0.0;
  for (const NavPoint& q : path) westmost = std::min(westmost, q.east_m);
  EXPECT_LT(westmost, -3.0);  // round the wall's end
  // A start far from the last clear one says nothing about the side: the old rule (any way out).
  MapPlanner fresh(m, MapPlannerParams{}, 0.45);
  ASSERT_EQ(fresh.plan(m, {-8.0, 8.0}, goal), PlanStatus::kOk);
  ASSERT_EQ(fresh.plan(m, on_wall, goal), PlanStatus::kOk);
  EXPECT_GT(fresh.path()[1].north_m, 6.0);  // through, since nothing says which side
}

TEST(MapPlanner, SeenAheadMeasuresThePathThroughWaterTheLidarHasSeen) {
  NavMap m(small_map(), {}, {});
  MapPlanner planner(m, MapPlannerParams{}, 0.45);
  ASSERT_EQ(planner.plan(m, {0.0, 0.0}, {20.0, 0.0}), PlanStatus::kOk);
  // Nothing seen yet: only the water the boat is on (nearer than the map's least range).
  EXPECT_LT(planner.seen_ahead_m(m, {0.0, 0.0}, 8.0), 1.5);
  // Open water seen all round out to the map's 12 m: the path is seen up to the cap.
  msg::LidarScan open_water;
  for (int i = 0; i < 720; ++i)
    (void)open_water.push({-180.0F + 0.5F * static_cast<float>(i), 0.0F, 0, 0});
  m.add_scan(open_water, {{0.0, 0.0}, 0.0}, kHull);
  EXPECT_DOUBLE_EQ(planner.seen_ahead_m(m, {0.0, 0.0}, 8.0), 8.0);
  EXPECT_NEAR(planner.seen_ahead_m(m, {0.0, 0.0}, 30.0), 12.0, 0.5);
}

}  // namespace
}  // namespace coxswain::guidance

namespace coxswain::guidance {
namespace {

// Replanning works out again only the cells the lidar's obstacles reached (this plan's and the
// last's) and the last goal's faded costs; the inflated grid must be what a planner building it
// from nothing gives, after obstacles appear, move away and vanish, with and without the soft
// clearance cost and the goal's fade.
// Where a path crosses the line north = `line_north_m`, east of the crossing (none: NaN).
double crossing_east_m(const std::vector<NavPoint>& path, double line_north_m) {
  for (std::size_t i = 1; i < path.size(); ++i) {
    const NavPoint a = path[i - 1];
    const NavPoint b = path[i];
    if ((a.north_m - line_north_m) * (b.north_m - line_north_m) > 0.0 || a.north_m == b.north_m) {
      continue;
    }
    const double t = (line_north_m - a.north_m) / (b.north_m - a.north_m);
    return a.east_m + t * (b.east_m - a.east_m);
  }
  return std::nan("");
}

// A gate at north 10 m between east -1.5 and 1.5 m, its goal just beyond it, the boat off to
// the east: the straight way crosses the line well outside the gate. With the gate's line
// beyond its ends as walls the path crosses between them; the walls stand for that plan only.
TEST(MapPlanner, WallsOnAGatesLineMakeThePathCrossBetweenItsEnds) {
  NavMap m(small_map(), {}, {});
  MapPlanner planner(m, MapPlannerParams{}, 0.45);
  const NavPoint start{6.0, 10.0};
  const NavPoint goal{11.5, 0.0};
  const std::vector<PlanWall> walls{{{10.0, -1.5}, {10.0, -9.5}}, {{10.0, 1.5}, {10.0, 9.5}}};
  ASSERT_EQ(planner.plan(m, start, goal), PlanStatus::kOk);
  EXPECT_GT(crossing_east_m(planner.path(), 10.0), 1.5);
  ASSERT_EQ(planner.plan(m, start, goal, walls), PlanStatus::kOk);
  const double across = crossing_east_m(planner.path(), 10.0);
  EXPECT_GT(across, -1.5);
  EXPECT_LT(across, 1.5);
  ASSERT_EQ(planner.plan(m, start, goal), PlanStatus::kOk);
  EXPECT_GT(crossing_east_m(planner.path(), 10.0), 1.5);
  // Walls reaching far off the map are cut to it (the steps stay bounded); a wall with a
  // non-finite end is ignored.
  const std::vector<PlanWall> long_walls{{{10.0, -1.5}, {10.0, -1e12}},
                                         {{10.0, 1.5}, {10.0, 1e12}}};
  ASSERT_EQ(planner.plan(m, start, goal, long_walls), PlanStatus::kOk);
  EXPECT_NEAR(crossing_east_m(planner.path(), 10.0), across, 1e-9);
  const std::vector<PlanWall> broken{{{10.0, 1.5}, {10.0, std::nan("")}}};
  ASSERT_EQ(planner.plan(m, start, goal, broken), PlanStatus::kOk);
  EXPECT_GT(crossing_east_m(planner.path(), 10.0), 1.5);
  // A boat on a wall (its position in it) leaves on the side it came from.
  ASSERT_EQ(planner.plan(m, {9.0, 4.0}, goal, walls), PlanStatus::kOk);
  ASSERT_EQ(planner.plan(m, {10.0, 4.0}, goal, walls), PlanStatus::kOk);
  const double back = crossing_east_m(planner.path(), 10.0);
  EXPECT_GT(back, -1.5);
  EXPECT_LT(back, 1.5);
}

TEST(MapPlanner, ReplanningGivesTheGridAFreshPlannerBuildsAsObstaclesComeAndGo) {
  for (const double clearance_cost : {0.0, 4.0}) {
    NavMapParams mp = small_map();
    const std::vector<std::vector<NavPoint>> no_go{
        {{14.0, -3.0}, {14.0, 3.0}, {16.0, 3.0}, {16.0, -3.0}}};
    NavMap m(mp, {}, no_go);
    MapPlannerParams pp;
    pp.clearance_cost = clearance_cost;
    MapPlanner replanning(m, pp, 0.45);
    std::uint32_t seed = 7;
    const auto next = [&seed](double lo, double hi) {
      seed = seed * 1664525U + 1013904223U;
      return lo + (hi - lo) * static_cast<double>(seed >> 8) / static_cast<double>(1U << 24);
    };
    for (int step = 0; step < 40; ++step) {
      // A few walls somewhere ahead, different each time: old cells clear, new ones mark.
      std::vector<std::pair<NavPoint, NavPoint>> walls;
      const int count = static_cast<int>(next(0.0, 4.0));
      for (int w = 0; w < count; ++w) {
        const NavPoint a{next(2.0, 12.0), next(-8.0, 8.0)};
        walls.push_back({a, {a.north_m + next(-2.0, 2.0), a.east_m + next(-3.0, 3.0)}});
      }
      const core::NavPose pose{{next(-2.0, 1.0), next(-2.0, 2.0)}, next(-30.0, 30.0)};
      for (int k = 0; k < 3; ++k) m.add_scan(scan_of(pose, walls), pose, kHull);
      const NavPoint goal{next(6.0, 20.0), next(-6.0, 6.0)};
      // A gate's walls on some plans, not on others.
      std::vector<PlanWall> gate_walls;
      if (next(0.0, 1.0) < 0.5) {
        const NavPoint end{next(4.0, 16.0), next(-4.0, 4.0)};
        gate_walls.push_back({end, {end.north_m + next(-1.0, 1.0), end.east_m + next(-9.0, 9.0)}});
      }
      (void)replanning.plan(m, pose.position, goal, gate_walls);
      MapPlanner fresh(m, pp, 0.45);
      (void)fresh.plan(m, pose.position, goal, gate_walls);
      const GridView a = replanning.view();
      const GridView b = fresh.view();
      const std::size_t n = static_cast<std::size_t>(a.rows) * a.cols;
      std::size_t differing = 0;
      for (std::size_t k = 0; k < n; ++k) {
        differing += a.state[k] != b.state[k] || a.depth[k] != b.depth[k] || a.cost[k] != b.cost[k];
      }
      ASSERT_EQ(differing, 0U) << "step " << step << ", clearance cost " << clearance_cost;
      ASSERT_EQ(replanning.status(), fresh.status());
      ASSERT_EQ(replanning.path().size(), fresh.path().size());
    }
  }
}

}  // namespace
}  // namespace coxswain::guidance
