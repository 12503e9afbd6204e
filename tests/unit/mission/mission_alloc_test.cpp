// SPDX-License-Identifier: Apache-2.0
// MissionCore::step must not allocate once constructed: a counting global operator new.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "coxswain/mission/mission_core.hpp"
#include "mission_rig.hpp"

// GCC flags free() inside a replaced operator delete as a mismatch once inlined; the pair is
// matched.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
namespace {
std::atomic<long> g_allocations{0};
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
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace coxswain::mission::test {
namespace {

TEST(MissionAllocation, StepDoesNotAllocate) {
  config::Configuration c = base_config(config::TaskType::kObstacleCourse);
  const core::LocalFrame f(c.mission.origin);
  c.mission.tasks[0].waypoints.push_back(f.to_geo({40.0, 0.0}));
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
  EXPECT_GE(rig->out.status.waypoints_arrived, 1U);  // through the gate on the way
}

// A live parameter set applied between two steps may allocate (the clusterer's buffers, an
// operator action); the steps after it must not.
TEST(MissionAllocation, StepsAfterALiveParameterChangeDoNotAllocate) {
  config::Configuration c = base_config(config::TaskType::kObstacleCourse);
  const core::LocalFrame f(c.mission.origin);
  c.mission.tasks[0].waypoints.push_back(f.to_geo({40.0, 0.0}));
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

}  // namespace
}  // namespace coxswain::mission::test
