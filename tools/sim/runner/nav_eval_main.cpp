// SPDX-License-Identifier: Apache-2.0
// coxswain-nav-eval: the navigation filter checked against the simulator's truth over a batch of
// generated hopping courses with a large, wandering GNSS bias (default 8 m in a direction drawn
// per seed, the simulator's 1 m / 300 s wander around it) and the batch's 0.2 m/s current:
// mission success, runs where the mission counted a waypoint the judge did not, and per tick
// (after the start) the antenna position error against the filter's covariance (inside the 95 %
// ellipse, NEES) and the heading error. One JSON line per run, then a summary line.
//   coxswain-nav-eval --runs 100 --seed0 10001 --bias-m 8 --jobs 2
// `--trace FILE` writes every tick of the first run as CSV (time, error, covariance, NEES, the
// receiver's true bias, heading error, speed): where a run leaves its ellipse, and why.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "coxswain/core/angles.hpp"
#include "coxswain/core/frames.hpp"
#include "sim/runner/lockstep_runner.hpp"
#include "sim/runner/mission_pilot.hpp"
#include "sim/runner/mission_run.hpp"
#include "sim/runner/realistic_sensors.hpp"
#include "sim/scoring/scorer.hpp"
#include "sim/world/generator.hpp"

namespace {

using namespace coxswain;

struct RunStats {
  bool passed = false;
  std::string failure;  // the judge's reason ("" when passed)
  bool false_count = false;
  std::uint32_t mission_arrived = 0;
  std::size_t judge_arrived = 0;
  std::size_t ticks = 0;
  std::size_t inside95 = 0;
  double nees_sum = 0.0;
  std::vector<double> err_m;
  std::vector<double> heading_err_deg;
};

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1))];
}

RunStats run_one(std::uint64_t seed, double bias_m, const config::Configuration& base,
                 std::FILE* trace) {
  sim::world::Course course = sim::world::generate_course(sim::world::CourseKind::kHopping, seed);
  const double u = std::fmod(static_cast<double>(seed) * 0.6180339887498949, 1.0);
  const double v = std::fmod(static_cast<double>(seed) * 0.7548776662466927, 1.0);
  if (course.environment.current_speed_mps == 0.0) {
    course.environment.current_speed_mps = 0.2;
    course.environment.current_toward_deg = 360.0 * u;
  }
  if (course.world.declination_deg == 0.0) course.world.declination_deg = -8.5;
  sim::sensors::SensorConfig sensors;
  sensors.gnss.bias_direction_deg = 360.0 * v;
  sensors.gnss.bias_mean_m = bias_m;
  sensors.gnss.bias_max_m = bias_m + 3.0;
  config::Configuration config = base;
  config.mission = sim::runner::fit_mission_to_course(base.mission, course.world);

  sim::runner::MissionPilot pilot(config);
  sim::runner::RealisticSensorOptions so;
  so.camera = false;
  sim::runner::RealisticSensorSuite suite(
      course.world, config, sim::runner::fitted_sensor_config(sensors, course.world, config, seed),
      so);
  sim::runner::RunnerOptions ro;
  ro.seed = seed;
  ro.tick_rate_hz = config.mission.tick_rate_hz;
  ro.max_time_s = 900.0;
  ro.failsafe_ms = static_cast<std::uint16_t>(config.devices.arduino.failsafe_ms);
  sim::runner::LockstepRunner runner(course, config.boat, ro, &suite, &pilot);
  const core::MountTransform mount = config.boat.mounts.gnss;

  RunStats st;
  std::uint64_t last_tick = 0;
  while (runner.step()) {
    const mission::CoreOutput& out = pilot.output();
    if (out.status.tick_count == last_tick) continue;  // one sample per mission tick
    last_tick = out.status.tick_count;
    if (!out.status.started || !out.status.position_cov_valid || !out.viz.pose_valid) continue;
    const sim::dynamics::TruthState truth = runner.truth();
    const core::NavPoint true_antenna = core::body_to_nav(truth.pose, {mount.x_m, mount.y_m});
    const core::NavPoint est_antenna = core::body_to_nav(out.viz.pose, {mount.x_m, mount.y_m});
    const double dn = est_antenna.north_m - true_antenna.north_m;
    const double de = est_antenna.east_m - true_antenna.east_m;
    const double a = out.status.position_cov_nn_m2;
    const double b = out.status.position_cov_ne_m2;
    const double c = out.status.position_cov_ee_m2;
    const double det = a * c - b * b;
    if (!(det > 0.0)) continue;
    const double nees = (c * dn * dn - 2.0 * b * dn * de + a * de * de) / det;
    ++st.ticks;
    st.nees_sum += nees;
    if (nees <= 5.991) ++st.inside95;
    st.err_m.push_back(std::hypot(dn, de));
    const double heading_err_deg =
        core::wrap_deg(out.viz.pose.heading_deg - truth.pose.heading_deg);
    st.heading_err_deg.push_back(std::abs(heading_err_deg));
    if (trace != nullptr) {
      const core::NavPoint bias = suite.gnss().bias();
      std::fprintf(trace, "%.2f,%.3f,%.3f,%.4f,%.4f,%.4f,%.3f,%.3f,%.3f,%.2f,%.2f,%.2f\n",
                   core::ns_to_sec(runner.now_ns()), dn, de, a, b, c, nees, bias.north_m,
                   bias.east_m, heading_err_deg,
                   std::hypot(truth.vel_north_mps, truth.vel_east_mps),
                   out.status.heading_sigma_deg);
    }
  }
  const sim::runner::RunOutcome outcome = runner.run();
  st.passed = sim::runner::mission_passed(outcome.score);
  if (!st.passed) st.failure = sim::scoring::failure_reason(outcome.score, pilot.status().finished);
  st.mission_arrived = pilot.status().waypoints_arrived;
  st.judge_arrived = outcome.score.waypoints.size();
  st.false_count = st.mission_arrived > st.judge_arrived;
  return st;
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 20;
  std::uint64_t seed0 = 1;
  double bias_m = 8.0;
  unsigned jobs = 2;
  std::string mission = "config/missions/hopping.yaml";
  std::string trace_path;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    const std::string val = argv[i + 1];
    if (k == "--runs") runs = std::atoi(val.c_str());
    if (k == "--seed0") seed0 = std::strtoull(val.c_str(), nullptr, 10);
    if (k == "--bias-m") bias_m = std::atof(val.c_str());
    if (k == "--jobs") jobs = static_cast<unsigned>(std::max(1, std::atoi(val.c_str())));
    if (k == "--mission") mission = val;
    if (k == "--trace") trace_path = val;
  }
  config::ConfigErrors errors;
  config::Configuration base;
  base.boat = config::load_boat_config("config/boat.yaml", errors);
  base.devices = config::load_devices_config("config/devices.yaml", errors);
  base.mission = config::load_mission_config(mission, errors);
  if (!errors.empty()) {
    std::fprintf(stderr, "%s", errors.format().c_str());
    return 2;
  }
  std::FILE* trace = nullptr;
  if (!trace_path.empty()) {
    trace = std::fopen(trace_path.c_str(), "w");
    if (trace == nullptr) {
      std::fprintf(stderr, "cannot write %s\n", trace_path.c_str());
      return 2;
    }
    std::fprintf(trace,
                 "t_s,err_n_m,err_e_m,cov_nn_m2,cov_ne_m2,cov_ee_m2,nees,true_bias_n_m,"
                 "true_bias_e_m,heading_err_deg,speed_mps,heading_sigma_deg\n");
  }
  std::vector<RunStats> results(static_cast<std::size_t>(std::max(runs, 0)));
  std::atomic<int> next{0};
  std::mutex io;
  auto worker = [&] {
    for (;;) {
      const int i = next.fetch_add(1);
      if (i >= runs) return;
      const std::uint64_t seed = seed0 + static_cast<std::uint64_t>(i);
      RunStats st = run_one(seed, bias_m, base, i == 0 ? trace : nullptr);
      const std::lock_guard<std::mutex> lock(io);
      std::printf(
          "{\"seed\": %llu, \"passed\": %s, \"false_count\": %s, \"mission_arrived\": %u, "
          "\"judge_arrived\": %zu, \"inside95\": %.4f, \"nees\": %.3f, \"err_med_m\": %.3f, "
          "\"err_p95_m\": %.3f, \"heading_err_med_deg\": %.2f, \"failure\": \"%s\"}\n",
          static_cast<unsigned long long>(seed), st.passed ? "true" : "false",
          st.false_count ? "true" : "false", st.mission_arrived, st.judge_arrived,
          st.ticks ? static_cast<double>(st.inside95) / static_cast<double>(st.ticks) : 0.0,
          st.ticks ? st.nees_sum / static_cast<double>(st.ticks) : 0.0, quantile(st.err_m, 0.5),
          quantile(st.err_m, 0.95), quantile(st.heading_err_deg, 0.5), st.failure.c_str());
      std::fflush(stdout);
      results[static_cast<std::size_t>(i)] = std::move(st);
    }
  };
  std::vector<std::thread> threads;
  for (unsigned j = 0; j < jobs; ++j) threads.emplace_back(worker);
  for (auto& t : threads) t.join();
  std::size_t passed = 0;
  std::size_t false_counts = 0;
  std::size_t ticks = 0;
  std::size_t inside = 0;
  double nees = 0.0;
  std::vector<double> err;
  std::vector<double> herr;
  for (const RunStats& st : results) {
    passed += st.passed;
    false_counts += st.false_count;
    ticks += st.ticks;
    inside += st.inside95;
    nees += st.nees_sum;
    err.insert(err.end(), st.err_m.begin(), st.err_m.end());
    herr.insert(herr.end(), st.heading_err_deg.begin(), st.heading_err_deg.end());
  }
  if (trace != nullptr) std::fclose(trace);
  std::printf(
      "summary: seeds %llu-%llu, bias %.1f m: success %zu/%d, runs counting a waypoint the judge "
      "did not %zu, ticks inside the 95%% ellipse %.2f%% of %zu, mean NEES %.2f (2 dof), position "
      "error median %.2f m p95 %.2f m, heading error median %.2f deg p95 %.2f deg\n",
      static_cast<unsigned long long>(seed0),
      static_cast<unsigned long long>(seed0 + static_cast<std::uint64_t>(runs) - 1), bias_m, passed,
      runs, false_counts,
      ticks ? 100.0 * static_cast<double>(inside) / static_cast<double>(ticks) : 0.0, ticks,
      ticks ? nees / static_cast<double>(ticks) : 0.0, quantile(err, 0.5), quantile(err, 0.95),
      quantile(herr, 0.5), quantile(herr, 0.95));
  return 0;
}
