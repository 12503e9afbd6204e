// SPDX-License-Identifier: Apache-2.0
#pragma once
// Turns the decoder's HQ nodes into full revolutions (msg::LidarScan) in the BODY frame.
// Protocol reference: docs/protocols.md 1.6-1.9 and 1.12.
//
// The seam is placed astern: a revolution is cut where the samples cross the body-frame bearing
// `seam_body_deg` (default 180 = stern), not at the lidar's own start flag. On the 2022 boat the
// lidar faced astern, so its own seam pointed at the bow, splitting every obstacle ahead in two.
// The first partial revolution after start or reset() is dropped.
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "coxswain/core/frames.hpp"
#include "coxswain/core/time.hpp"
#include "coxswain/drivers/rplidar/protocol.hpp"
#include "coxswain/msg/lidar_scan.hpp"

namespace coxswain::drivers::rplidar {

struct ScanAssemblerParams {
  /// Lidar mount: yaw_deg = where the lidar's 0 deg points, clockwise from the bow (from
  /// boat.yaml). Offsets are not applied here (points stay polar about the lidar).
  core::MountTransform mount;
  /// True when the lidar's angle grows clockwise seen from above (Slamtec datasheets); false
  /// for a lidar mounted upside down.
  bool clockwise = true;
  /// Body-frame bearing of the seam, degrees (default: dead astern).
  double seam_body_deg = 180.0;
  /// Returns outside [min_range_m, max_range_m] are reported as "no return" (range 0, quality 0).
  /// Defaults fit an A1/A2; set them from model_info() or config.
  float min_range_m = 0.15F;
  float max_range_m = 12.0F;
  /// Microseconds per sample (GET_SAMPLERATE / SCAN_MODE_US_PER_SAMPLE); gives offset_us and
  /// duration_ns. 0 = unknown (offsets stay 0).
  double sample_duration_us = 0.0;
  /// Keep samples without a valid return as range-0 points (true) or drop them (false).
  bool keep_no_return = true;

  /// Empty when valid, else what is wrong.
  [[nodiscard]] std::optional<std::string> validate() const;
};

/// Accumulates HQ nodes into revolutions. Fixed arrays (two LidarScans, ~130 kB: allocate the
/// assembler once, e.g. with make_unique); no allocation per call. Not thread-safe.
class ScanAssembler {
 public:
  explicit ScanAssembler(const ScanAssemblerParams& params);

  /// Adds one sample. `stamp_ns` is the adapter's time estimate for this sample (used for the
  /// first sample of a revolution). Returns true when a revolution was completed by this sample
  /// (the sample itself starts the next one); read it with scan() before the next add().
  [[nodiscard]] bool add(const HqNode& node, core::TimeNs stamp_ns);
  [[nodiscard]] const msg::LidarScan& scan() const { return done_; }
  /// Forgets the revolution in progress (after a decoder reset, a gap or a mode change).
  void reset();
  void set_sample_duration_us(double us) { params_.sample_duration_us = us; }
  void set_range_limits(float min_range_m, float max_range_m);
  [[nodiscard]] const ScanAssemblerParams& params() const { return params_; }

  /// Samples dropped because a revolution exceeded LidarScan::kMaxPoints.
  [[nodiscard]] std::uint64_t overflow_points() const { return overflow_points_; }
  /// Revolutions emitted so far.
  [[nodiscard]] std::uint32_t revolutions() const { return revolution_; }

  /// Body-frame bearing (-180, 180] of a lidar angle under these params.
  [[nodiscard]] double body_bearing_deg(double lidar_deg) const;

 private:
  void finish();

  ScanAssemblerParams params_;
  msg::LidarScan building_;
  msg::LidarScan done_;
  bool started_ = false;  // a seam crossing has been seen: building_ is a full revolution
  bool have_phase_ = false;
  double phase_deg_ = 0.0;     // unwrapped angle travelled since the last seam, [0, 360) + jitter
  double last_wrapped_ = 0.0;  // previous sample's phase in [0, 360)
  std::uint32_t sample_index_ = 0;
  std::uint32_t revolution_ = 0;
  std::uint64_t overflow_points_ = 0;
};

}  // namespace coxswain::drivers::rplidar
