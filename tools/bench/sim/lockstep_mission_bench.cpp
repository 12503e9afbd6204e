// SPDX-License-Identifier: Apache-2.0
// Lockstep real-time factor: three minutes of the KABOAT 2026 course (real mission core,
// realistic lidar/GNSS/IMU, and the camera rendered and run through the camera pipeline while
// the mission looks through it) per iteration, with and without the camera.
// sim_s_per_s = simulated seconds per second of CPU: the real-time factor.
#include <benchmark/benchmark.h>

#include <opencv2/core/utility.hpp>

#include "sim/runner/mission_run.hpp"
#include "sim/world/course.hpp"

namespace {

using namespace coxswain;

void BM_LockstepKaboat2026ThreeMinutes(benchmark::State& state) {
  // As coxswain-sim runs it: one world per thread, no OpenCV worker pool beside it.
  cv::setNumThreads(1);
  const std::string dir = std::string(COXSWAIN_SOURCE_DIR) + "/config/";
  config::ConfigErrors errors;
  const sim::world::Course course =
      sim::world::load_course_file(dir + "courses/kaboat2026.yaml", errors);
  config::Configuration config;
  config.boat = config::load_boat_config(dir + "boat.yaml", errors);
  config.devices = config::load_devices_config(dir + "devices.yaml", errors);
  config.mission = config::load_mission_config(dir + "missions/kaboat2026.yaml", errors);
  if (!errors.empty()) {
    state.SkipWithError(errors.format().c_str());
    return;
  }
  config.mission = sim::runner::fit_mission_to_course(config.mission, course.world);
  sim::runner::MissionRunOptions options;
  options.camera = state.range(0) != 0;
  options.max_time_s = 180.0;
  options.record_path = false;
  double sim_s = 0.0;
  std::uint64_t frames = 0;
  for (auto _ : state) {
    const sim::runner::MissionRunResult r = sim::runner::run_mission(course, config, options);
    sim_s += core::ns_to_sec(r.outcome.end_ns);
    frames += r.camera_frames;
    benchmark::DoNotOptimize(r.outcome.trajectory_hash);
  }
  state.counters["sim_s_per_s"] = benchmark::Counter(sim_s, benchmark::Counter::kIsRate);
  state.counters["camera_frames"] =
      benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_LockstepKaboat2026ThreeMinutes)
    ->ArgName("camera")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);

}  // namespace
