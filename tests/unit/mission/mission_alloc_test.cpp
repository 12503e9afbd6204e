// SPDX-License-Identifier: Apache-2.0
// MissionCore::step must not allocate once constructed: a counting global operator new (and
// delete, so a temporary allocated and freed within a tick is caught too).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <new>

#include "coxswain/config/config.hpp"
#include "coxswain/mission/mission_core.hpp"
#include "mission_rig.hpp"
#include "support/testdata.hpp"

// GCC flags free() inside a replaced operator delete as a mismatch once inlined; the pair is
// matched.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
namespace {
std::atomic<long> g_allocations{0};
std::atomic<long> g_frees{0};
void counted_free(void* p) noexcept {
  if (p != nullptr) g_frees.fetch_add(1, std::memory_order_relaxed);
  std::free(p);
}
}  // namespace

void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
// The nothrow forms too (std::stable_sort's temporary buffer uses them), so every new is paired
// with the delete below.
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  return std::malloc(size == 0 ? 1 : size);
}
void operator delete(void* p) noexcept { counted_free(p); }
void operator delete(void* p, std::size_t) noexcept { counted_free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { counted_free(p); }

namespace coxswain::mission::test {
namespace {

TEST(MissionAllocation, StepDoesNotAllocate) {
  config::Configuration c = obstacle_config();
  auto rig = std::make_unique<Rig>(c);
  rig->move = true;
  add_circle(rig->scan, 10.0, 0.5, 0.5);
  add_wall_ahead(rig->scan, 15.0, 6.0);
  rig->log.reserve(64);
  rig->run_for(1.0);  // warm up (start, task entry)
  ASSERT_EQ(rig->path(), "obstacle_course/navigate") << rig->log_text();
  const long before = g_allocations.load();
  // Step directly: the rig's own log would allocate on a transition.
  for (int i = 0; i < 500; ++i) {
    if (i % 5 == 0) rig->lidar();
    if (i % 10 == 0) rig->gnss(rig->position);
    rig->imu(rig->heading_deg);
    rig->publish_arduino();
    rig->core.step(*rig->snap, rig->now, rig->out);
    rig->integrate();
    rig->now += kTickNs;
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_GT(rig->out.viz.segment_count, 0U);
}

// The map takes every scan, the planner replans a few times a second and the gate is tracked
// and judged, all in fixed storage.
TEST(MissionAllocation, MappingPlanningAndGateJudgingDoNotAllocate) {
  config::Configuration c = base_config(config::TaskType::kObstacleCourse);
  const core::LocalFrame f(c.mission.origin);
  c.mission.tasks[0].waypoints.push_back(f.to_geo({15.0, 0.0}));
  c.mission.tasks[0].waypoints.push_back(f.to_geo({40.0, 0.0}));
  for (const core::NavPoint p : {core::NavPoint{-10.0, -10.0}, core::NavPoint{-10.0, 10.0},
                                 core::NavPoint{50.0, 10.0}, core::NavPoint{50.0, -10.0}}) {
    c.mission.planning.boundary.push_back(f.to_geo(p));
  }
  auto rig = std::make_unique<Rig>(c);
  rig->move = true;
  rig->world_buoys.push_back({{15.0, -1.5}, 0.2});
  rig->world_buoys.push_back({{15.0, 1.5}, 0.2});
  rig->world_buoys.push_back({{8.0, 0.3}, 0.4});
  rig->log.reserve(64);
  rig->run_for(1.0);
  ASSERT_EQ(rig->path(), "obstacle_course/navigate") << rig->log_text();
  const long before = g_allocations.load();
  for (int i = 0; i < 1000; ++i) {
    if (i % 5 == 0) {
      rig->scan_world();
      rig->lidar();
    }
    if (i % 10 == 0) rig->gnss(rig->position);
    rig->imu(rig->heading_deg);
    rig->publish_arduino();
    rig->core.step(*rig->snap, rig->now, rig->out);
    rig->integrate();
    rig->now += kTickNs;
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_GE(rig->out.status.waypoints_arrived, 1U)
      << rig->position.north_m << "," << rig->position.east_m << " "
      << rig->path();  // through the gate on the way
}

// A live parameter set applied between two steps may allocate (the clusterer's buffers, an
// operator action); the steps after it must not.
TEST(MissionAllocation, StepsAfterALiveParameterChangeDoNotAllocate) {
  config::Configuration c = obstacle_config();
  auto rig = std::make_unique<Rig>(c);
  rig->move = true;
  add_circle(rig->scan, 10.0, 0.5, 0.5);
  rig->log.reserve(64);
  rig->run_for(1.0);
  ASSERT_EQ(rig->path(), "obstacle_course/navigate") << rig->log_text();
  TunableParameters p = rig->core.parameters();
  p.heading_pid.kp_per_deg *= 1.5;
  p.clustering.group_gap_m = 0.15;
  p.avoidance.clearance_m = 0.5;
  p.speed.max_thrust_frac = 0.8;
  p.vision.colours[0].hsv.s_min = 100;
  ASSERT_EQ(rig->core.apply_parameters(p), "");
  rig->lidar();  // the first scan through the rebuilt clusterer sizes its buffers
  rig->core.step(*rig->snap, rig->now, rig->out);
  rig->now += kTickNs;
  const long before = g_allocations.load();
  for (int i = 0; i < 500; ++i) {
    if (i % 5 == 0) rig->lidar();
    if (i % 10 == 0) rig->gnss(rig->position);
    rig->imu(rig->heading_deg);
    rig->publish_arduino();
    rig->core.step(*rig->snap, rig->now, rig->out);
    rig->integrate();
    rig->now += kTickNs;
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_TRUE(rig->out.viz.has_avoidance);
}

// The shipped obstacle-course mission on the shipped boat, started as on the water (start
// switch, GNSS calibration), with lidar scans of buoys along the leg arriving at 10 Hz: after
// start-up and a warm-up, the running tick neither allocates nor frees. `planner` turns on the
// map and global planner the shipped file leaves off.
void expect_shipped_obstacle_course_tick_does_not_allocate(bool planner) {
  const std::filesystem::path dir = coxswain::testing::source_dir() / "config";
  config::ConfigErrors errors;
  config::Configuration c{
      config::load_boat_config((dir / "boat.yaml").string(), errors),
      config::load_devices_config((dir / "devices.yaml").string(), errors),
      config::load_mission_config((dir / "missions" / "obstacle_course.yaml").string(), errors)};
  ASSERT_TRUE(errors.empty()) << errors.format();
  c.mission.planning.planner.enabled = planner;
  auto rig = std::make_unique<Rig>(c);
  rig->move = true;
  for (const core::NavPoint p : {core::NavPoint{8.0, 0.8}, core::NavPoint{14.0, -1.2},
                                 core::NavPoint{20.0, 1.0}, core::NavPoint{26.0, -0.6}}) {
    rig->world_buoys.push_back({p, 0.3});
  }
  rig->log.reserve(64);
  rig->arduino_autonomous(true);  // the start switch
  ASSERT_TRUE(rig->run_until([&] { return rig->path() == "obstacle_course/navigate"; }, 60.0))
      << rig->path() << "\n"
      << rig->log_text();
  rig->run_for(2.0);  // warm-up: the first scans, the first plan
  const long allocations = g_allocations.load();
  const long frees = g_frees.load();
  std::uint32_t most_segments = 0;
  // Step directly: the rig's own log would allocate on a transition.
  for (int i = 0; i < 1000; ++i) {
    if (i % 5 == 0) {
      rig->scan_world();
      rig->lidar();
    }
    if (i % 10 == 0) rig->gnss(rig->position);
    rig->imu(rig->heading_deg);
    rig->publish_arduino();
    rig->core.step(*rig->snap, rig->now, rig->out);
    rig->core.finish_tick();  // the map update and replans, as the daemon runs them
    most_segments = std::max(most_segments, rig->out.viz.segment_count);
    rig->integrate();
    rig->now += kTickNs;
  }
  // Both read before any assertion: a failure message allocates.
  const long new_allocations = g_allocations.load() - allocations;
  const long new_frees = g_frees.load() - frees;
  EXPECT_EQ(new_allocations, 0);
  EXPECT_EQ(new_frees, 0);
  EXPECT_GT(most_segments, 0U);                        // the scans reached the avoidance
  EXPECT_GT(rig->position.north_m, 10.0);              // and the boat sailed the leg meanwhile
  EXPECT_EQ(rig->path(), "obstacle_course/navigate");  // still running, nothing aborted
}

TEST(MissionAllocation, ShippedObstacleCourseTickDoesNotAllocate) {
  expect_shipped_obstacle_course_tick_does_not_allocate(false);
}

TEST(MissionAllocation, ShippedObstacleCourseTickWithThePlannerOnDoesNotAllocate) {
  expect_shipped_obstacle_course_tick_does_not_allocate(true);
}

}  // namespace
}  // namespace coxswain::mission::test
