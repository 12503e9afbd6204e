// SPDX-License-Identifier: Apache-2.0
#include "sim/runner/realistic_sensors.hpp"

#include "coxswain/perception/vision_params.hpp"

namespace coxswain::sim::runner {

sensors::SensorConfig fitted_sensor_config(const sensors::SensorConfig& base,
                                           const world::World& world,
                                           const config::Configuration& config,
                                           std::uint64_t seed) {
  sensors::SensorConfig s = base;
  const auto& mounts = config.boat.mounts;
  s.lidar.mount = mounts.lidar;
  s.gnss.mount = mounts.gnss;
  s.imu.mount_yaw_deg = mounts.imu.yaw_deg;
  s.imu.declination_deg = world.declination_deg;
  s.camera.mount = mounts.camera;
  s.camera.hfov_deg = config.devices.camera.hfov_deg;
  s.camera.width_px = static_cast<int>(config.devices.camera.width_px);
  s.camera.height_px = static_cast<int>(config.devices.camera.height_px);
  // Distinct, reproducible streams per sensor and run.
  const std::uint64_t k = 0x9e3779b97f4a7c15ULL;
  s.seed = seed;
  s.lidar.seed = seed * k + 11;
  s.gnss.seed = seed * k + 22;
  s.imu.seed = seed * k + 33;
  s.camera.seed = seed * k + 44;
  return s;
}

RealisticSensorSuite::RealisticSensorSuite(const world::World& world,
                                           const config::Configuration& config,
                                           const sensors::SensorConfig& sensors,
                                           RealisticSensorOptions options)
    : options_(std::move(options)),
      lidar_(std::make_unique<sensors::LidarSim>(sensors.lidar, world)),
      gnss_(std::make_unique<sensors::GnssSim>(sensors.gnss, world.origin)),
      imu_(std::make_unique<sensors::ImuSim>(sensors.imu)),
      detections_(std::make_unique<msg::CameraDetections>()) {
  if (options_.camera) {
    camera_ = std::make_unique<sensors::CameraSim>(sensors.camera, world);
    pipeline_ = std::make_unique<perception::CameraPipeline>(perception::VisionParams::defaults(),
                                                             config.devices.camera.hfov_deg,
                                                             config.boat.mounts.camera);
  }
}

RealisticSensorSuite::~RealisticSensorSuite() = default;

void RealisticSensorSuite::step(const dynamics::TruthState& truth, core::TimeNs now_ns,
                                core::LatestStore& store) {
  const sensors::BoatTruth b = to_boat_truth(truth);
  if (!started_) {
    started_ = true;
    lidar_->reset(now_ns, b);
    // The control interface: the operator presses start once and names the target marker.
    msg::OperatorInput in;
    in.stamp_ns = now_ns;
    in.start_count = options_.press_start ? 1 : 0;
    in.target_colour = options_.target_colour;
    in.target_shape = options_.target_shape;
    store.operator_input.publish(in, now_ns);
  }
  if (imu_->update(now_ns, b) && imu_on_) store.imu.publish(imu_->sample(), now_ns);
  if (gnss_->update(now_ns, b) && gnss_on_) store.gnss.publish(gnss_->fix(), now_ns);
  const sensors::LidarUpdate lu = lidar_->update(now_ns, b);
  if (lu.scan_ready && lidar_on_) store.lidar.publish(lidar_->scan(), now_ns);
  if (camera_ && (!options_.camera_wanted || options_.camera_wanted())) {
    if (camera_->update(now_ns, truth.pose, frame_)) {
      if (pipeline_->process(frame_, now_ns, *detections_)) {
        store.camera.publish(*detections_, now_ns);
        ++frames_;
      }
    }
  }
}

}  // namespace coxswain::sim::runner
