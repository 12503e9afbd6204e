// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/grid_planner.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace coxswain::guidance {
namespace {

using core::NavPoint;

GridParams params(double inflate_m = 0.8) {
  GridParams p;
  p.rows = 40;
  p.cols = 40;
  p.resolution_m = 0.5;
  p.inflate_radius_m = inflate_m;
  return p;
}

OccupancyGrid make(const GridParams& p) {
  std::string err;
  auto g = OccupancyGrid::create(p, &err);
  EXPECT_TRUE(g.has_value()) << err;
  return std::move(*g);
}

double path_length(const std::vector<NavPoint>& path) {
  double l = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) l += core::distance_m(path[i - 1], path[i]);
  return l;
}

// Every point along the path (sampled finely) lies in a free cell.
bool path_is_free(const OccupancyGrid& g, const std::vector<NavPoint>& path) {
  for (std::size_t i = 1; i < path.size(); ++i) {
    const NavPoint a = path[i - 1];
    const NavPoint b = path[i];
    const int n = 1 + static_cast<int>(core::distance_m(a, b) / 0.05);
    for (int k = 0; k <= n; ++k) {
      const double t = static_cast<double>(k) / n;
      const auto c = g.cell_of(
          {a.north_m + t * (b.north_m - a.north_m), a.east_m + t * (b.east_m - a.east_m)});
      if (!c || g.state(*c) != OccupancyGrid::State::kFree) return false;
    }
  }
  return true;
}

TEST(OccupancyGrid, ValidatesParams) {
  GridParams p = params();
  p.resolution_m = 0.0;
  EXPECT_FALSE(OccupancyGrid::create(p).has_value());
  p = params();
  p.decay_per_update = 1.0F;
  EXPECT_TRUE(p.validate().has_value());
  EXPECT_FALSE(params().validate().has_value());
}

TEST(OccupancyGrid, MarksBodyFrameSegmentsInTheNavigationFrameAndInflates) {
  OccupancyGrid g = make(params());
  perception::ObstacleList l;
  // Boat at (10, 10) heading east: 4 m ahead in the body frame is 4 m east.
  ASSERT_TRUE(l.push({{4.0, -0.1}, {4.0, 0.1}}));
  g.update(l, {{10.0, 10.0}, 90.0});
  const auto hit = g.cell_of({10.0, 14.0});
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(g.state(*hit), OccupancyGrid::State::kOccupied);
  EXPECT_EQ(g.state(*g.cell_of({10.0, 14.6})), OccupancyGrid::State::kInflated);
  EXPECT_EQ(g.state(*g.cell_of({10.0, 16.0})), OccupancyGrid::State::kFree);
  EXPECT_EQ(g.state(*g.cell_of({14.0, 10.0})), OccupancyGrid::State::kFree);
}

TEST(OccupancyGrid, EvidenceDecaysWhenNotSeenAgain) {
  OccupancyGrid g = make(params());
  perception::ObstacleList l;
  ASSERT_TRUE(l.push({{4.0, 0.0}, {4.0, 0.0}}));
  const core::NavPose pose{{10.0, 10.0}, 0.0};
  g.update(l, pose);
  g.update(l, pose);
  const GridCell c = *g.cell_of({14.0, 10.0});
  EXPECT_EQ(g.state(c), OccupancyGrid::State::kOccupied);
  const perception::ObstacleList empty;
  int updates = 0;
  while (g.state(c) == OccupancyGrid::State::kOccupied && updates < 100) {
    g.update(empty, pose);
    ++updates;
  }
  EXPECT_GT(updates, 1);
  EXPECT_LT(updates, 10);
  EXPECT_EQ(g.state(c), OccupancyGrid::State::kFree);
}

TEST(AStar, StraightLineOnAFreeGrid) {
  OccupancyGrid g = make(params());
  AStarPlanner a(g.rows(), g.cols());
  ASSERT_EQ(a.plan(g, {1.2, 5.2}, {18.2, 5.2}), PlanStatus::kOk);
  ASSERT_EQ(a.path().size(), 2U);  // collinear cells removed
  EXPECT_NEAR(path_length(a.path()), 17.0, 1e-9);
}

TEST(AStar, FindsAPathAroundAWallRespectingInflation) {
  OccupancyGrid g = make(params());
  for (int k = 0; k < 2; ++k) g.mark_segment({10.0, 2.0}, {10.0, 16.0});  // wall across north
  g.rebuild_inflation();
  AStarPlanner a(g.rows(), g.cols());
  const NavPoint start{5.0, 8.0};
  const NavPoint goal{15.0, 8.0};
  ASSERT_EQ(a.plan(g, start, goal), PlanStatus::kOk);
  EXPECT_TRUE(path_is_free(g, a.path()));
  EXPECT_GT(path_length(a.path()), 10.0 + 2.0);
  // It goes round the nearer (west) end of the wall, beyond its inflation.
  double min_east = 1e9;
  for (const NavPoint& p : a.path()) min_east = std::min(min_east, p.east_m);
  EXPECT_LT(min_east, 2.0 - 0.8);
}

TEST(AStar, NarrowGapIsClosedByTheHullButOpenWithoutIt) {
  for (const double inflate : {0.8, 0.0}) {
    OccupancyGrid g = make(params(inflate));
    g.mark_segment({10.0, 0.0}, {10.0, 9.0});  // wall with a 1 m gap at east 9..10
    g.mark_segment({10.0, 10.0}, {10.0, 19.9});
    g.mark_segment({10.0, 0.0}, {10.0, 9.0});
    g.mark_segment({10.0, 10.0}, {10.0, 19.9});
    g.rebuild_inflation();
    AStarPlanner a(g.rows(), g.cols());
    const auto st = a.plan(g, {5.0, 9.5}, {15.0, 9.5});
    if (inflate > 0.0) {
      EXPECT_EQ(st, PlanStatus::kNoPath);  // the wall spans the grid except the narrow gap
    } else {
      ASSERT_EQ(st, PlanStatus::kOk);
      EXPECT_TRUE(path_is_free(g, a.path()));
      EXPECT_NEAR(path_length(a.path()), 10.0, 0.5);
    }
  }
}

TEST(AStar, FailsCleanly) {
  OccupancyGrid g = make(params());
  // A box round the goal.
  for (int k = 0; k < 2; ++k) {
    g.mark_segment({12.0, 12.0}, {12.0, 16.0});
    g.mark_segment({12.0, 16.0}, {16.0, 16.0});
    g.mark_segment({16.0, 16.0}, {16.0, 12.0});
    g.mark_segment({16.0, 12.0}, {12.0, 12.0});
  }
  g.rebuild_inflation();
  AStarPlanner a(g.rows(), g.cols());
  EXPECT_EQ(a.plan(g, {2.0, 2.0}, {14.0, 14.0}), PlanStatus::kNoPath);
  EXPECT_TRUE(a.path().empty());
  EXPECT_EQ(a.plan(g, {2.0, 2.0}, {12.0, 14.0}), PlanStatus::kGoalBlocked);
  EXPECT_EQ(a.plan(g, {2.0, 2.0}, {30.0, 2.0}), PlanStatus::kGoalOutside);
  EXPECT_EQ(a.plan(g, {-1.0, 2.0}, {2.0, 2.0}), PlanStatus::kStartOutside);
  AStarPlanner wrong(10, 10);
  EXPECT_EQ(wrong.plan(g, {2.0, 2.0}, {3.0, 3.0}), PlanStatus::kNoPath);
}

TEST(AStar, StartInsideTheInflationCanLeaveIt) {
  OccupancyGrid g = make(params());
  for (int k = 0; k < 2; ++k) g.mark_segment({10.0, 0.0}, {10.0, 8.0});
  g.rebuild_inflation();
  const NavPoint start{9.4, 4.0};  // 0.6 m from the wall, inside the 0.8 m inflation
  ASSERT_EQ(g.state(*g.cell_of(start)), OccupancyGrid::State::kInflated);
  AStarPlanner a(g.rows(), g.cols());
  ASSERT_EQ(a.plan(g, start, {15.0, 4.0}), PlanStatus::kOk);
  for (const NavPoint& p : a.path()) {
    EXPECT_NE(g.state(*g.cell_of(p)), OccupancyGrid::State::kOccupied);
  }
}

// A row of obstacles across a 9 x 9 grid with a one-cell gap narrower than the hull, the boat
// in the inflation just below the gap: it may back away, never squeeze through.
TEST(AStar, WithDepthsAnEscapeFromTheInflationNeverGoesDeeper) {
  constexpr std::uint32_t kN = 9;
  std::vector<CellState> state(kN * kN, CellState::kFree);
  std::vector<std::uint8_t> depth(kN * kN, 0);
  for (std::uint32_t c = 0; c < kN; ++c) {
    state[4 * kN + c] = CellState::kOccupied;
    depth[4 * kN + c] = 255;
    for (const std::uint32_t r : {3U, 5U}) {
      state[r * kN + c] = CellState::kInflated;
      depth[r * kN + c] = 100;
    }
  }
  state[4 * kN + 4] = CellState::kInflated;  // the gap, deeper than its sides
  depth[4 * kN + 4] = 200;
  GridView view{kN, kN, 1.0, {0.0, 0.0}, state.data(), nullptr};
  const NavPoint start{3.5, 4.5};  // cell (3, 4)
  const NavPoint beyond{8.5, 4.5};
  const NavPoint back{0.5, 4.5};
  AStarPlanner a(kN, kN);
  // Without depths the escape threads the gap; with them there is no way through, but the way
  // back is open.
  EXPECT_EQ(a.plan(view, start, beyond), PlanStatus::kOk);
  view.depth = depth.data();
  EXPECT_EQ(a.plan(view, start, beyond), PlanStatus::kNoPath);
  EXPECT_EQ(a.plan(view, start, back), PlanStatus::kOk);
}

TEST(AStar, DeterministicAndRepeatable) {
  OccupancyGrid g = make(params());
  for (int k = 0; k < 2; ++k) g.mark_segment({6.0, 3.0}, {6.0, 17.0});
  g.rebuild_inflation();
  AStarPlanner a(g.rows(), g.cols());
  ASSERT_EQ(a.plan(g, {2.0, 10.0}, {18.0, 10.0}), PlanStatus::kOk);
  const auto first = a.path();
  ASSERT_EQ(a.plan(g, {2.0, 10.0}, {18.0, 10.0}), PlanStatus::kOk);
  ASSERT_EQ(first.size(), a.path().size());
  for (std::size_t i = 0; i < first.size(); ++i) {
    EXPECT_EQ(first[i].north_m, a.path()[i].north_m);
    EXPECT_EQ(first[i].east_m, a.path()[i].east_m);
  }
}

TEST(AStar, AWeightedHeuristicExpandsFewerCellsForAPathWithinItsBound) {
  OccupancyGrid g = make(params());
  for (int k = 0; k < 2; ++k) {  // a cup open toward the start, the goal behind it
    g.mark_segment({12.0, 4.0}, {12.0, 16.0});
    g.mark_segment({12.0, 4.0}, {8.0, 4.0});
    g.mark_segment({12.0, 16.0}, {8.0, 16.0});
  }
  g.rebuild_inflation();
  const NavPoint start{5.0, 10.0};
  const NavPoint goal{17.0, 10.0};
  AStarPlanner exact(g.rows(), g.cols());
  ASSERT_EQ(exact.plan(g.view(), start, goal), PlanStatus::kOk);
  const double shortest = path_length(exact.path());
  for (const float w : {1.2F, 1.5F, 3.0F}) {
    AStarPlanner weighted(g.rows(), g.cols());
    ASSERT_EQ(weighted.plan(g.view(), start, goal, SIZE_MAX, w), PlanStatus::kOk) << w;
    EXPECT_TRUE(path_is_free(g, weighted.path())) << w;
    EXPECT_LT(weighted.expanded(), exact.expanded()) << w;
    EXPECT_LE(path_length(weighted.path()), static_cast<double>(w) * shortest + 1e-9) << w;
  }
  // A weight below 1 or not finite is taken as 1: the exact search, cell for cell.
  for (const float w : {0.5F, std::nanf(""), INFINITY}) {
    AStarPlanner same(g.rows(), g.cols());
    ASSERT_EQ(same.plan(g.view(), start, goal, SIZE_MAX, w), PlanStatus::kOk);
    EXPECT_EQ(same.expanded(), exact.expanded());
    ASSERT_EQ(same.path().size(), exact.path().size());
    for (std::size_t i = 0; i < same.path().size(); ++i) {
      EXPECT_EQ(same.path()[i].north_m, exact.path()[i].north_m);
      EXPECT_EQ(same.path()[i].east_m, exact.path()[i].east_m);
    }
  }
}

}  // namespace
}  // namespace coxswain::guidance
