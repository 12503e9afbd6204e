// SPDX-License-Identifier: Apache-2.0
#pragma once
// The simulated sensors of tools/sim/sensors behind the runner's SensorSuite: LidarSim (scans
// through the driver's own ScanAssembler), GnssSim (bias, noise), ImuSim (magnetic yaw, drift)
// and, while the mission looks through the camera, CameraSim frames run through the daemon's
// own perception::CameraPipeline into the store's camera slot. Also plays the control interface:
// publishes the operator input (one start press, the target marker) as the daemon's control
// socket would. Sensor mounts come from the boat config, the declination from the course, so
// the simulated sensors and the core agree. Deterministic for a seed (no clock, no threads).
// Runner thread only.
#include <functional>
#include <memory>

#include <opencv2/core.hpp>

#include "coxswain/config/config.hpp"
#include "coxswain/perception/camera_pipeline.hpp"
#include "sim/runner/boat_truth.hpp"
#include "sim/runner/sensor_suite.hpp"
#include "sim/sensors/sensor_config.hpp"
#include "sim/sensors/truth.hpp"
#include "sim/world/world.hpp"

namespace coxswain::sim::runner {

/// The sensor config as the suite uses it: mounts from `boat`, the IMU declination from the
/// world, the camera geometry from `devices`, per-sensor seeds derived from `seed`.
[[nodiscard]] sensors::SensorConfig fitted_sensor_config(const sensors::SensorConfig& base,
                                                         const world::World& world,
                                                         const config::Configuration& config,
                                                         std::uint64_t seed);

struct RealisticSensorOptions {
  bool camera = true;  // render and process frames while camera_wanted() says so
  /// Whether the mission currently uses the camera (MissionPilot::camera_wanted); empty = always.
  std::function<bool()> camera_wanted;
  msg::Colour target_colour = msg::Colour::kUnknown;  // operator input (docking target)
  msg::Shape target_shape = msg::Shape::kUnknown;
  bool press_start = true;  // one "start" from the control interface at time 0
};

class RealisticSensorSuite final : public SensorSuite {
 public:
  /// `world` must outlive the suite. `sensors` is used as given (see fitted_sensor_config).
  RealisticSensorSuite(const world::World& world, const config::Configuration& config,
                       const sensors::SensorConfig& sensors, RealisticSensorOptions options);
  ~RealisticSensorSuite() override;
  void step(const dynamics::TruthState& truth, core::TimeNs now_ns,
            core::LatestStore& store) override;

  /// Silences (false) or restores (true) a sensor: while silent it still measures, but nothing
  /// reaches the store, as when its driver loses the device.
  void set_gnss_publishing(bool on) { gnss_on_ = on; }
  void set_lidar_publishing(bool on) { lidar_on_ = on; }
  void set_imu_publishing(bool on) { imu_on_ = on; }

  [[nodiscard]] std::uint64_t frames_processed() const { return frames_; }
  [[nodiscard]] const sensors::GnssSim& gnss() const { return *gnss_; }

 private:
  RealisticSensorOptions options_;
  std::unique_ptr<sensors::LidarSim> lidar_;
  std::unique_ptr<sensors::GnssSim> gnss_;
  std::unique_ptr<sensors::ImuSim> imu_;
  std::unique_ptr<sensors::CameraSim> camera_;
  std::unique_ptr<perception::CameraPipeline> pipeline_;
  std::unique_ptr<msg::CameraDetections> detections_;
  cv::Mat frame_;
  bool started_ = false;
  bool gnss_on_ = true;
  bool lidar_on_ = true;
  bool imu_on_ = true;
  std::uint64_t frames_ = 0;
};

}  // namespace coxswain::sim::runner
