// SPDX-License-Identifier: Apache-2.0
// Cost of one MissionCore::step in the obstacle course: with a new full lidar scan to cluster
// (3600 returns: a walled channel with buoys) and without (the ticks between scans). Argument
// `shipped`: 1 = the shipped obstacle-course mission file and boat (swept hull on; the file
// ships the planner on), 0 = the engines' defaults; `planner`: the lidar map and global planner
// on or off, whatever the file says.
// Each step is timed on its own and the median and p99 reported (the mean hides the tail), and
// the p99 of the steps' own costs (input_p99_us: the same sequence of steps pass after pass).
// The work each step leaves for after its command (MissionCore::finish_tick: the map update, a
// replan) is timed apart, as after_*.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/call_samples.hpp"
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
  // Five seconds of scans before any step is timed: the map has settled, as on the water.
  static constexpr int kWarmUpSteps = 250;
  Setup(bool shipped, bool planner) {
    config::Configuration c;
    if (shipped) {
      const std::filesystem::path dir = std::filesystem::path(COXSWAIN_BENCH_SOURCE_DIR) / "config";
      config::ConfigErrors errors;
      c.boat = config::load_boat_config((dir / "boat.yaml").string(), errors);
      c.mission =
          config::load_mission_config((dir / "missions" / "obstacle_course.yaml").string(), errors);
      if (!errors.empty()) {
        error = errors.format();
        return;
      }
      c.mission.start_mode = config::StartMode::kImmediate;
      c.mission.tasks.resize(1);
    }
    c.mission.origin = {35.0695, 128.828, 0.0};
    c.mission.calibrate_gps_at_start = false;
    c.mission.planning.planner.enabled = planner;
    const core::LocalFrame f(c.mission.origin);
    if (c.mission.tasks.empty()) c.mission.tasks.emplace_back();
    config::TaskConfig& t = c.mission.tasks[0];
    t.type = config::TaskType::kObstacleCourse;
    t.name = "obstacle_course";
    t.time_limit_s = 7200.0;
    t.waypoints.assign(1, f.to_geo({60.0, 0.0}));
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
    for (int i = 0; i < kWarmUpSteps; ++i) {
      tick(true);
      finish();
    }
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
  // The work after the step (the map update, a replan), as the daemon runs it once the
  // command is out.
  void finish() { core->finish_tick(); }
  std::string error;
  std::unique_ptr<MissionCore> core;
  std::unique_ptr<core::Snapshot> snap;
  std::unique_ptr<CoreOutput> out;
  core::TimeNs now = core::kNsPerSec;
};

// Steps with (or without) a new scan each time; p50/p99 of the single steps in microseconds.
void run_steps(benchmark::State& state, bool new_scan) {
  const bool shipped = state.range(0) != 0;
  const bool planner = state.range(1) != 0;
  std::optional<Setup> setup;
  setup.emplace(shipped, planner);
  if (!setup->error.empty()) {
    state.SkipWithError(setup->error.c_str());
    return;
  }
  if (setup->out->status.state_path.view() != "obstacle_course/navigate") {
    state.SkipWithError("mission did not start");
    return;
  }
  // The same kSteps steps from a fresh start, pass after pass: step i of every pass sees the
  // same inputs, so its least time is its own cost (the input p99, see call_samples.hpp).
  constexpr std::size_t kSteps = 500;
  bench::CallSamples samples(kSteps);
  bench::CallSamples after(kSteps);
  std::size_t step = 0;
  for (auto _ : state) {
    if (step == kSteps) {
      state.PauseTiming();
      setup.emplace(shipped, planner);
      step = 0;
      state.ResumeTiming();
    }
    const auto t0 = std::chrono::steady_clock::now();
    setup->tick(new_scan);
    const auto t1 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(setup->out->command);
    setup->finish();
    const auto t2 = std::chrono::steady_clock::now();
    samples.add(step, std::chrono::duration<double, std::micro>(t1 - t0).count());
    after.add(step++, std::chrono::duration<double, std::micro>(t2 - t1).count());
  }
  samples.report(state);
  after.report(state, "after_");
  state.counters["segments"] = static_cast<double>(setup->out->viz.segment_count);
  state.SetLabel(std::string(shipped ? "shipped obstacle_course.yaml" : "engine defaults") +
                 (planner ? ", planner on" : ", planner off"));
}

void BM_StepWithNewScan(benchmark::State& state) { run_steps(state, true); }
void BM_StepBetweenScans(benchmark::State& state) { run_steps(state, false); }

BENCHMARK(BM_StepWithNewScan)
    ->ArgNames({"shipped", "planner"})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Args({0, 1})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StepBetweenScans)
    ->ArgNames({"shipped", "planner"})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Args({0, 1})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace coxswain::mission
