// SPDX-License-Identifier: Apache-2.0
// What a host records of the mission: the map geometry in both frames, and the route of a step.
#include "coxswain/host/step_record.hpp"

#include <gtest/gtest.h>

#include "coxswain/core/geodesy.hpp"

namespace coxswain::host {
namespace {

TEST(MapGeometry, HoldsEveryPointOfTheMissionInBothFrames) {
  config::MissionConfig m;
  m.origin = {35.1, 129.0, 0.0};
  const core::LocalFrame frame(m.origin);
  config::TaskConfig hop;
  hop.name = "hopping";
  hop.waypoints = {frame.to_geo({10.0, 0.0}), frame.to_geo({10.0, 20.0})};
  config::TaskConfig dock;
  dock.name = "docking";
  dock.slips = {frame.to_geo({30.0, -4.0})};
  m.tasks = {hop, dock};
  m.planning.boundary = {frame.to_geo({-5.0, -10.0}), frame.to_geo({-5.0, 30.0}),
                         frame.to_geo({40.0, 30.0})};
  m.planning.no_go = {
      {frame.to_geo({5.0, 5.0}), frame.to_geo({5.0, 8.0}), frame.to_geo({8.0, 8.0})}};

  const record::MapGeometry g = map_geometry(m);
  ASSERT_EQ(g.marks.size(), 3U);
  EXPECT_EQ(g.marks[0].label, "hopping 1");
  EXPECT_EQ(g.marks[1].label, "hopping 2");
  EXPECT_EQ(g.marks[1].kind, record::MapMark::Kind::kWaypoint);
  EXPECT_NEAR(g.marks[1].at.nav.north_m, 10.0, 1e-6);
  EXPECT_NEAR(g.marks[1].at.nav.east_m, 20.0, 1e-6);
  EXPECT_DOUBLE_EQ(g.marks[1].at.lat_deg, hop.waypoints[1].lat_deg);
  EXPECT_DOUBLE_EQ(g.marks[1].at.lon_deg, hop.waypoints[1].lon_deg);
  EXPECT_EQ(g.marks[2].label, "docking slip 1");
  EXPECT_EQ(g.marks[2].kind, record::MapMark::Kind::kSlip);
  EXPECT_NEAR(g.marks[2].at.nav.east_m, -4.0, 1e-6);
  ASSERT_EQ(g.areas.size(), 2U);
  EXPECT_EQ(g.areas[0].kind, record::MapArea::Kind::kBoundary);
  ASSERT_EQ(g.areas[0].corners.size(), 3U);
  EXPECT_NEAR(g.areas[0].corners[2].nav.north_m, 40.0, 1e-6);
  EXPECT_EQ(g.areas[1].kind, record::MapArea::Kind::kNoGo);
  EXPECT_EQ(g.areas[1].label, "no-go 1");

  EXPECT_TRUE(map_geometry(config::MissionConfig{}).empty());
}

TEST(FillTickViz, CarriesTheRouteInTheNavigationFrame) {
  mission::CoreOutput out;
  out.viz.pose_valid = true;
  out.viz.has_goal = true;
  out.viz.goal = {20.0, 1.0};
  out.viz.arrival_radius_m = 2.0;
  out.viz.has_leg = true;
  out.viz.leg_start = {0.0, 0.5};
  out.viz.has_gate = true;
  out.viz.gate_by_lidar = true;
  out.viz.gate_port = {20.0, -0.5};
  out.viz.gate_starboard = {20.0, 2.5};
  out.viz.path_count = 2;
  out.viz.path[0] = {0.0, 0.5};
  out.viz.path[1] = {20.0, 1.0};
  record::TickViz viz;
  fill_tick_viz(out, config::BoatConfig{}, viz);
  EXPECT_TRUE(viz.goal_valid);
  EXPECT_DOUBLE_EQ(viz.goal.east_m, 1.0);
  EXPECT_DOUBLE_EQ(viz.arrival_radius_m, 2.0);
  EXPECT_TRUE(viz.leg_valid);
  EXPECT_DOUBLE_EQ(viz.leg_start.east_m, 0.5);
  EXPECT_TRUE(viz.gate_valid);
  EXPECT_TRUE(viz.gate_by_lidar);
  EXPECT_DOUBLE_EQ(viz.gate_starboard.east_m, 2.5);
  ASSERT_EQ(viz.path_count, 2U);
  EXPECT_DOUBLE_EQ(viz.path[1].north_m, 20.0);

  out.viz = mission::VizFrame{};
  fill_tick_viz(out, config::BoatConfig{}, viz);
  EXPECT_FALSE(viz.goal_valid);
  EXPECT_FALSE(viz.gate_valid);
  EXPECT_EQ(viz.path_count, 0U);
}

}  // namespace
}  // namespace coxswain::host
