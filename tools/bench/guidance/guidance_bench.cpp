// SPDX-License-Identifier: Apache-2.0
// Cost of one avoidance decision per strategy (~50 segments) and of A* on a 100x100 grid.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "coxswain/core/angles.hpp"
#include "coxswain/guidance/avoidance.hpp"
#include "coxswain/guidance/grid_planner.hpp"
#include "coxswain/guidance/pure_pursuit.hpp"

namespace coxswain::guidance {
namespace {

// 50 segments: buoys scattered ahead plus pieces of a wall on each side.
perception::ObstacleList scene() {
  perception::ObstacleList l;
  for (int i = 0; i < 30; ++i) {
    const double b = core::deg_to_rad(-80.0 + 5.5 * i);
    const double r = 2.0 + std::fmod(1.7 * i, 6.0);
    const double f = r * std::cos(b);
    const double s = r * std::sin(b);
    (void)l.push({{f - 0.2, s - 0.2}, {f + 0.2, s + 0.2}});
  }
  for (int i = 0; i < 10; ++i) {
    (void)l.push({{i * 1.0, -4.0}, {i * 1.0 + 1.0, -4.0}});
    (void)l.push({{i * 1.0, 4.5}, {i * 1.0 + 1.0, 4.5}});
  }
  return l;
}

void BM_Avoidance(benchmark::State& state) {
  AvoidanceParams p;
  p.strategy = static_cast<Strategy>(state.range(0));
  auto a = std::make_unique<Avoidance>(*Avoidance::create(p));
  const auto l = scene();
  core::TimeNs now = 0;
  for (auto _ : state) {
    now += 20 * core::kNsPerMs;
    auto d = a->decide(l, 5.0, now);
    benchmark::DoNotOptimize(d.bearing_body_deg);
  }
  state.SetLabel(to_string(p.strategy));
}
BENCHMARK(BM_Avoidance)->DenseRange(0, 3);

void BM_AngleBinsFill(benchmark::State& state) {
  AngleBins b;
  (void)b.configure({-90.0, 90.0, 1.0});
  const auto l = scene();
  for (auto _ : state) {
    b.fill(l, 0.8, 8.0);
    benchmark::DoNotOptimize(b.range_m(90));
  }
}
BENCHMARK(BM_AngleBinsFill);

// 100x100 cells at 0.5 m with three staggered walls: start and goal at opposite corners.
void BM_AStar100(benchmark::State& state) {
  GridParams gp;
  gp.rows = 100;
  gp.cols = 100;
  gp.resolution_m = 0.5;
  auto g = *OccupancyGrid::create(gp);
  for (int k = 0; k < 2; ++k) {
    g.mark_segment({12.5, 0.0}, {12.5, 38.0});
    g.mark_segment({25.0, 12.0}, {25.0, 49.9});
    g.mark_segment({37.5, 0.0}, {37.5, 38.0});
  }
  g.rebuild_inflation();
  AStarPlanner a(gp.rows, gp.cols);
  for (auto _ : state) {
    const auto st = a.plan(g, {1.0, 1.0}, {49.0, 1.0});
    benchmark::DoNotOptimize(st);
  }
  state.counters["expanded"] = static_cast<double>(a.expanded());
  state.counters["path_points"] = static_cast<double>(a.path().size());
}
BENCHMARK(BM_AStar100);

void BM_GridUpdate100(benchmark::State& state) {
  GridParams gp;
  auto g = *OccupancyGrid::create(gp);
  const auto l = scene();
  for (auto _ : state) g.update(l, {{25.0, 25.0}, 30.0});
}
BENCHMARK(BM_GridUpdate100);

}  // namespace
}  // namespace coxswain::guidance
