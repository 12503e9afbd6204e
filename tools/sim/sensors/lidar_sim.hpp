// SPDX-License-Identifier: Apache-2.0
#pragma once
// Simulated RPLIDAR: beams at the model's rate and angular step, each cast at the pose the boat
// has at that beam's own time (motion skew), with range noise, dropouts and spurious near returns
// (spray, the hull). Outputs both what the driver publishes (msg::LidarScan in the body frame,
// produced by the driver's own ScanAssembler so the seam, order and offsets agree exactly) and the
// raw per-beam samples in the lidar's own frame and order, for the RPLIDAR emulator to serve.
// Deterministic for a seed. Not thread-safe; no allocation per update once built.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "coxswain/core/frames.hpp"
#include "coxswain/core/time.hpp"
#include "coxswain/drivers/rplidar/protocol.hpp"
#include "coxswain/drivers/rplidar/scan_assembler.hpp"
#include "coxswain/msg/lidar_scan.hpp"
#include "sim/rng/rng.hpp"
#include "sim/sensors/ray_scene.hpp"
#include "sim/sensors/truth.hpp"
#include "sim/world/world.hpp"

namespace coxswain::sim::sensors {

/// RPLIDAR models with their nominal (datasheet) scan figures in their typical scan mode.
enum class LidarModel : std::uint8_t { kA1, kA2M8, kA3, kS2, kC1 };

struct LidarSimConfig {
  LidarModel model = LidarModel::kA2M8;
  double rate_hz = 10.0;           // revolutions per second
  double angular_step_deg = 0.45;  // between consecutive beams (= 360 rate us_per_sample / 1e6)
  double min_range_m = 0.2;        // model limits; returns outside are "no return"
  double max_range_m = 12.0;
  double range_sigma_m = 0.01;          // white range noise, plus...
  double range_sigma_fraction = 0.005;  // ...this fraction of the range
  double dropout_probability = 0.01;    // a beam returns nothing (dark or wet surface)
  double spurious_probability = 0.002;  // a beam returns a near echo (spray, own hull)
  double spurious_max_range_m = 0.6;    // spurious echoes lie in [min_range_m, this]
  std::uint8_t quality = 188;           // quality of a valid return (capsule modes report 188)
  /// Lidar mount (boat.yaml mounts.lidar): yaw 180 = its 0 deg faces the stern (2022 boat).
  core::MountTransform mount{180.0, 0.0, 0.0};
  bool clockwise = true;         // lidar angle grows clockwise seen from above
  double seam_body_deg = 180.0;  // where the driver cuts revolutions (ScanAssembler)
  std::uint64_t seed = 1;

  /// Figures of `model` (rate, step, ranges); the other fields keep their defaults.
  [[nodiscard]] static LidarSimConfig for_model(LidarModel model);
  [[nodiscard]] int beams_per_revolution() const;
  [[nodiscard]] double sample_duration_us() const;
  /// Empty when valid, else what is wrong.
  [[nodiscard]] std::optional<std::string> validate() const;
};

/// One raw beam as the lidar measures it: its own angle (clockwise from its own 0), the range,
/// the quality and the time of the sample.
struct RawBeam {
  float angle_deg = 0.0F;  // [0, 360)
  float range_m = 0.0F;    // 0 = no return
  std::uint8_t quality = 0;
  bool start_flag = false;  // first beam of a lidar revolution
  core::TimeNs stamp_ns = 0;
  /// The same in the SDK's HQ node form (what the decoder hands the ScanAssembler).
  [[nodiscard]] drivers::rplidar::HqNode to_hq() const;
};

/// What one update produced.
struct LidarUpdate {
  bool scan_ready = false;  // a new body-frame revolution: read scan()
  bool raw_ready = false;   // a new raw lidar revolution: read raw_revolution()
  std::uint32_t beams = 0;  // beams cast in this update
};

class LidarSim {
 public:
  LidarSim(const LidarSimConfig& config, const world::World& world);
  LidarSim(const LidarSimConfig& config, RayScene scene);

  /// Starts the rotation at lidar angle 0 at time `t_ns` with the boat at `truth`.
  void reset(core::TimeNs t_ns, const BoatTruth& truth);
  /// Casts every beam whose time lies in (previous update, now], interpolating the pose between
  /// the previous truth and this one. The first call (or one after reset) starts the rotation.
  /// Call at least once per revolution; a revolution completed and superseded within one call
  /// is counted in missed_scans().
  LidarUpdate update(core::TimeNs now_ns, const BoatTruth& truth);

  /// The latest body-frame revolution (valid after an update returned scan_ready).
  [[nodiscard]] const msg::LidarScan& scan() const { return assembler_->scan(); }
  /// The latest complete lidar revolution, raw, in the lidar's own order (angle 0 first).
  [[nodiscard]] std::span<const RawBeam> raw_revolution() const { return raw_done_; }
  [[nodiscard]] const LidarSimConfig& config() const { return config_; }
  [[nodiscard]] const RayScene& scene() const { return scene_; }
  [[nodiscard]] std::uint64_t missed_scans() const { return missed_scans_; }

  /// Sensor-frame range the lidar sees along its own angle `lidar_deg` from `pose`, no noise;
  /// negative when nothing is in range. For tests and the emulator.
  [[nodiscard]] double true_range_m(const core::NavPose& pose, double lidar_deg) const;

 private:
  [[nodiscard]] double beam_world_bearing_deg(double heading_deg, double lidar_deg) const;
  void ensure_bins(core::NavPoint a, core::NavPoint b, double span_s);

  LidarSimConfig config_;
  RayScene scene_;
  Rng rng_;
  std::unique_ptr<drivers::rplidar::ScanAssembler> assembler_;
  int beams_per_rev_ = 0;
  double sample_ns_ = 0.0;
  bool started_ = false;
  core::TimeNs origin_ns_ = 0;  // time of beam 0
  std::uint64_t next_beam_ = 0;
  core::TimeNs last_ns_ = 0;
  BoatTruth last_truth_;
  std::vector<RawBeam> raw_building_;
  std::vector<RawBeam> raw_done_;
  std::uint64_t missed_scans_ = 0;
};

}  // namespace coxswain::sim::sensors
