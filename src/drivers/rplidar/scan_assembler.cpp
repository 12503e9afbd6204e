// SPDX-License-Identifier: Apache-2.0
#include "coxswain/drivers/rplidar/scan_assembler.hpp"

#include <algorithm>
#include <cmath>

#include "coxswain/core/angles.hpp"

namespace coxswain::drivers::rplidar {

std::optional<std::string> ScanAssemblerParams::validate() const {
  if (!std::isfinite(mount.yaw_deg)) return "lidar mount yaw_deg must be finite";
  if (!std::isfinite(seam_body_deg)) return "seam_body_deg must be finite";
  if (!(min_range_m >= 0.0F)) return "min_range_m must be >= 0";
  if (!(max_range_m > min_range_m)) return "max_range_m must be greater than min_range_m";
  if (!(sample_duration_us >= 0.0) || sample_duration_us > 1e6) {
    return "sample_duration_us must be in [0, 1e6]";
  }
  return {};
}

ScanAssembler::ScanAssembler(const ScanAssemblerParams& params) : params_(params) {}

void ScanAssembler::reset() {
  building_.clear();
  started_ = false;
  have_phase_ = false;
  phase_deg_ = 0.0;
  sample_index_ = 0;
}

void ScanAssembler::set_range_limits(float min_range_m, float max_range_m) {
  params_.min_range_m = min_range_m;
  params_.max_range_m = max_range_m;
}

double ScanAssembler::body_bearing_deg(double lidar_deg) const {
  const double sensor_cw_deg = params_.clockwise ? lidar_deg : -lidar_deg;
  return core::sensor_bearing_to_body_deg(params_.mount, sensor_cw_deg);
}

bool ScanAssembler::add(const HqNode& node, core::TimeNs stamp_ns) {
  const double lidar_deg = node.angle_deg();
  const double bearing_deg = body_bearing_deg(lidar_deg);
  // Angle travelled past the seam in the direction of rotation: grows with the lidar angle
  // whichever way the lidar is mounted.
  const double dir = params_.clockwise ? 1.0 : -1.0;
  const double wrapped = core::wrap_deg_360(dir * (bearing_deg - params_.seam_body_deg));
  bool emitted = false;
  if (!have_phase_) {
    have_phase_ = true;
    phase_deg_ = wrapped;
  } else {
    // Unwrap with the shortest step, so jitter of a sample or two around the seam (capsule
    // angle corrections are not monotonic) never cuts twice.
    phase_deg_ += core::wrap_deg(wrapped - last_wrapped_);
  }
  last_wrapped_ = wrapped;
  if (phase_deg_ >= 360.0) {
    phase_deg_ -= 360.0;
    if (started_) {
      finish();
      emitted = true;
    }
    started_ = true;
    building_.clear();
    sample_index_ = 0;
  }

  if (building_.point_count == 0 && sample_index_ == 0) building_.stamp_ns = stamp_ns;
  const double offset_us = static_cast<double>(sample_index_) * params_.sample_duration_us;
  ++sample_index_;

  msg::LidarPoint p;
  p.bearing_deg = static_cast<float>(bearing_deg);
  p.offset_us = static_cast<std::int32_t>(std::lround(std::min(offset_us, 2.0e9)));
  const float range_m = static_cast<float>(static_cast<double>(node.dist_mm_q2) / 4000.0);
  const bool valid =
      node.dist_mm_q2 != 0 && range_m >= params_.min_range_m && range_m <= params_.max_range_m;
  if (valid) {
    p.range_m = range_m;
    p.quality = node.quality;
  } else if (!params_.keep_no_return) {
    return emitted;
  }
  if (!building_.push(p)) ++overflow_points_;
  return emitted;
}

void ScanAssembler::finish() {
  auto* begin = building_.points.data();
  auto* end = begin + building_.point_count;
  std::sort(begin, end, [](const msg::LidarPoint& a, const msg::LidarPoint& b) {
    if (a.bearing_deg != b.bearing_deg) return a.bearing_deg < b.bearing_deg;
    return a.offset_us < b.offset_us;
  });
  done_.stamp_ns = building_.stamp_ns;
  done_.duration_ns =
      sample_index_ > 0
          ? static_cast<core::TimeNs>(std::llround(static_cast<double>(sample_index_ - 1) *
                                                   params_.sample_duration_us * 1000.0))
          : 0;
  done_.min_range_m = params_.min_range_m;
  done_.max_range_m = params_.max_range_m;
  done_.revolution = revolution_++;
  done_.point_count = building_.point_count;
  std::copy(begin, end, done_.points.begin());
}

}  // namespace coxswain::drivers::rplidar
