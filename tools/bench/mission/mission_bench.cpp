// SPDX-License-Identifier: Apache-2.0
// Cost of one MissionCore::step in the obstacle course: with a new full lidar scan to cluster
// (3600 returns: a walled channel with buoys) and without (the ticks between scans).
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "coxswain/config/config.hpp"
#include "coxswain/core/angles.hpp"
#include "coxswain/core/geodesy.hpp"
#include "coxswain/mission/mission_core.hpp"

namespace coxswain::mission {
namespace {

// Range along body bearing b to the nearest of: walls at starboard -6 m and +6 m, buoys.
double range_at(double b_deg) {
  const double ux = std::cos(core::deg_to_rad(b_deg));
  const double uy = std::sin(core::deg_to_rad(b_deg));
  double best = 25.0;
  if (uy > 1e-6) best = std::min(best, 6.0 / uy);
  if (uy < -1e-6) best = std::min(best, -6.0 / uy);
  const double buoys[][2] = {{5.0, 1.0}, {9.0, -2.0}, {12.0, 2.5}, {16.0, 0.0}, {7.0, -4.0}};
  for (const auto& c : buoys) {
    const double proj = c[0] * ux + c[1] * uy;
    const double d2 = c[0] * c[0] + c[1] * c[1] - proj * proj;
    if (proj > 0.0 && d2 < 0.25) best = std::min(best, proj - std::sqrt(0.25 - d2));
  }
  return best;
}

struct Setup {
  Setup() {
    config::Configuration c;
    c.mission.origin = {35.0695, 128.828, 0.0};
    c.mission.calibrate_gps_at_start = false;
    config::TaskConfig t;
    t.type = config::TaskType::kObstacleCourse;
    t.name = "obstacle_course";
    t.time_limit_s = 7200.0;
    const core::LocalFrame f(c.mission.origin);
    t.waypoints.push_back(f.to_geo({60.0, 0.0}));
    c.mission.tasks.push_back(t);
    core = std::make_unique<MissionCore>(c.boat, c.mission);
    snap = std::make_unique<core::Snapshot>();
    out = std::make_unique<CoreOutput>();
    auto& scan = snap->lidar.value;
    for (int i = 0; i < 3600; ++i) {
      const double b = -180.0 + 0.1 * i;
      (void)scan.push({static_cast<float>(b), static_cast<float>(range_at(b)), 200, 0});
    }
    const core::GeoPoint g = f.to_geo({0.0, 0.0});
    snap->gnss.value.lat_deg = g.lat_deg;
    snap->gnss.value.lon_deg = g.lon_deg;
    snap->gnss.value.fix_ok = true;
    snap->gnss.value.fix_type = msg::FixType::k3D;
    snap->arduino.value.mode = msg::ControlMode::kAutonomous;
    for (int i = 0; i < 10; ++i) tick(true);
  }
  void tick(bool new_scan) {
    now += 20 * core::kNsPerMs;
    snap->imu.stamp_ns = now;
    ++snap->imu.sequence;
    snap->gnss.stamp_ns = now;
    ++snap->gnss.sequence;
    snap->arduino.stamp_ns = now;
    ++snap->arduino.sequence;
    if (new_scan || snap->lidar.sequence == 0) ++snap->lidar.sequence;
    snap->lidar.stamp_ns = now;
    core->step(*snap, now, *out);
  }
  std::unique_ptr<MissionCore> core;
  std::unique_ptr<core::Snapshot> snap;
  std::unique_ptr<CoreOutput> out;
  core::TimeNs now = core::kNsPerSec;
};

void BM_StepWithNewScan(benchmark::State& state) {
  Setup s;
  if (s.out->status.state_path.view() != "obstacle_course/navigate") {
    state.SkipWithError("mission did not start");
    return;
  }
  for (auto _ : state) {
    s.tick(true);
    benchmark::DoNotOptimize(s.out->command);
  }
  state.counters["segments"] = static_cast<double>(s.out->viz.segment_count);
}
BENCHMARK(BM_StepWithNewScan);

void BM_StepBetweenScans(benchmark::State& state) {
  Setup s;
  for (auto _ : state) {
    s.tick(false);
    benchmark::DoNotOptimize(s.out->command);
  }
}
BENCHMARK(BM_StepBetweenScans);

}  // namespace
}  // namespace coxswain::mission
