// SPDX-License-Identifier: Apache-2.0
// Simulator throughput: dynamics steps per second (items/s), a scoring update against the wide
// obstacle field, a whole lockstep step (firmware, dynamics, ideal sensors, scoring, pilot), and
// generating a solvable course.
#include <benchmark/benchmark.h>

#include "sim/runner/ideal_sensors.hpp"
#include "sim/runner/lockstep_runner.hpp"
#include "sim/world/generator.hpp"

namespace {

using namespace coxswain;

sim::world::Course final_field() {
  config::ConfigErrors errors;
  return sim::world::load_course_file(
      std::string(COXSWAIN_SOURCE_DIR) + "/config/courses/kaboat2022_obstacle_final.yaml", errors);
}

void BM_DynamicsStep(benchmark::State& state) {
  const config::BoatConfig boat;
  sim::dynamics::Environment env;
  env.wind_speed_mps = 3.0;
  env.gust_std_mps = 1.0;
  env.wave_force_n = 3.0;
  env.current_speed_mps = 0.2;
  sim::dynamics::BoatModel model(boat, sim::dynamics::otter_scaled(1.2), env, 1);
  model.set_pulses({1560, 1750});
  for (auto _ : state) {
    model.step();
    benchmark::DoNotOptimize(model.state());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_DynamicsStep);

void BM_ScorerUpdate(benchmark::State& state) {
  sim::world::Course course = final_field();
  course.world.regions.clear();  // no time limit: the scorer never stops judging
  const config::BoatConfig boat;
  sim::scoring::Scorer scorer(course.world, boat.hull);
  sim::dynamics::TruthState truth;
  truth.pose = {{10.0, 1.0}, 10.0};
  truth.cg = {9.5, 0.9};
  std::int64_t i = 0;
  for (auto _ : state) {
    truth.stamp_ns = ++i * 10 * core::kNsPerMs;
    scorer.update(truth, msg::LedColour::kOff);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ScorerUpdate);

class Circler final : public sim::runner::Pilot {
 public:
  void step(const core::Snapshot& /*snapshot*/, core::TimeNs /*now_ns*/,
            msg::ActuatorCommand& out) override {
    out.pulse_us = {1560, 1750};
    out.active = true;
  }
};

void BM_LockstepStep(benchmark::State& state) {
  sim::world::Course course = final_field();
  course.world.regions.clear();  // no time limit: the run never ends while measuring
  course.world.gates.clear();
  const config::BoatConfig boat;
  Circler pilot;
  sim::runner::IdealSensorSuite sensors(course.world.origin, boat);
  sim::runner::RunnerOptions options;
  options.max_time_s = 1e9;
  sim::runner::LockstepRunner runner(course, boat, options, &sensors, &pilot);
  for (auto _ : state) benchmark::DoNotOptimize(runner.step());
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_LockstepStep);

void BM_GenerateObstacleCourse(benchmark::State& state) {
  std::uint64_t seed = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        sim::world::generate_course(sim::world::CourseKind::kObstacle, ++seed));
  }
}
BENCHMARK(BM_GenerateObstacleCourse)->Unit(benchmark::kMillisecond);

}  // namespace
