// SPDX-License-Identifier: Apache-2.0
#include "sim_recording.hpp"

#include "sim/runner/ideal_sensors.hpp"
#include "sim/runner/lockstep_runner.hpp"
#include "sim/runner/mission_pilot.hpp"
#include "sim/runner/mission_run.hpp"
#include "sim/runner/recording.hpp"
#include "sim/sensors/lidar_sim.hpp"
#include "support/testdata.hpp"

namespace coxswain::test {
namespace {

using namespace coxswain::sim;

// Ideal IMU and GNSS plus the simulated lidar (noise from its own seeded stream).
class Suite final : public runner::SensorSuite {
 public:
  Suite(const world::World& world, const config::BoatConfig& boat)
      : ideal_(world.origin, boat), lidar_(lidar_config(boat), world) {}
  void step(const dynamics::TruthState& truth, core::TimeNs now_ns,
            core::LatestStore& store) override {
    ideal_.step(truth, now_ns, store);
    sensors::BoatTruth t;
    t.pose = truth.pose;
    t.surge_mps = truth.u_mps;
    t.sway_mps = truth.v_mps;
    t.yaw_rate_dps = truth.yaw_rate_dps;
    t.vel_north_mps = truth.vel_north_mps;
    t.vel_east_mps = truth.vel_east_mps;
    if (lidar_.update(now_ns, t).scan_ready) store.lidar.publish(lidar_.scan(), now_ns);
  }

 private:
  static sensors::LidarSimConfig lidar_config(const config::BoatConfig& boat) {
    sensors::LidarSimConfig c = sensors::LidarSimConfig::for_model(sensors::LidarModel::kA2M8);
    c.mount = boat.mounts.lidar;
    c.seed = 7;
    return c;
  }
  runner::IdealSensorSuite ideal_;
  sensors::LidarSim lidar_;
};

}  // namespace

config::Configuration shipped_config(const std::string& mission) {
  const auto dir = testing::source_dir() / "config";
  config::ConfigErrors errors;
  config::Configuration c{
      config::load_boat_config((dir / "boat.yaml").string(), errors),
      config::load_devices_config((dir / "devices.yaml").string(), errors),
      config::load_mission_config((dir / "missions" / (mission + ".yaml")).string(), errors)};
  if (!errors.empty()) throw std::runtime_error(errors.format());
  return c;
}

SimRecordingResult record_sim_run(const std::filesystem::path& mcap,
                                  const config::Configuration& config, const std::string& course,
                                  double seconds, const std::optional<ParameterChange>& change) {
  SimRecordingResult result;
  config::ConfigErrors errors;
  const world::Course c = world::load_course_file(
      (testing::source_dir() / "config" / "courses" / course).string(), errors);
  if (!errors.empty()) {
    result.error = errors.format();
    return result;
  }
  Suite suite(c.world, config.boat);
  runner::MissionPilot pilot(config);
  runner::RunnerOptions options;
  options.tick_rate_hz = config.mission.tick_rate_hz;
  options.max_time_s = seconds;
  runner::LockstepRunner run(c, config.boat, options, &suite, &pilot);
  runner::RunRecorder recorder(mcap, config, run.store(), run.clock(), runner::course_json(c.world),
                               "coxswain test");
  if (!recorder.start()) {
    result.error = recorder.error();
    return result;
  }
  pilot.set_recorder(&recorder);
  bool changed = false;
  run.set_step_observer([&] {
    recorder.sample();
    if (change && !changed && run.clock().now_ns() >= core::sec_to_ns(change->at_s)) {
      mission::TunableParameters p = pilot.parameters();
      change->edit(p);
      pilot.request_parameters(p);  // applied before the next step
      changed = true;
    }
  });
  const runner::RunOutcome outcome = run.run();
  const record::RecorderStats stats =
      recorder.stop(runner::judge_json(outcome.score, pilot.status().finished));
  result.ticks = stats[record::RecordChannel::kTick].written;
  // Every channel: the simulator samples the store after each step, so not even /imu may drop.
  result.dropped = stats.total_dropped();
  result.parameters_error = pilot.parameters_error();
  result.ok = !stats.failed;
  if (stats.failed) result.error = stats.error;
  return result;
}

}  // namespace coxswain::test
