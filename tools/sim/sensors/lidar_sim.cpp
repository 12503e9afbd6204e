// SPDX-License-Identifier: Apache-2.0
#include "sim/sensors/lidar_sim.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "coxswain/core/angles.hpp"

namespace coxswain::sim::sensors {

LidarSimConfig LidarSimConfig::for_model(LidarModel model) {
  LidarSimConfig c;
  c.model = model;
  // Nominal figures of each model's typical mode (Slamtec datasheets): rate, samples per second
  // (step = 360 rate / samples per second) and the range limits protocol.cpp's model_info uses.
  switch (model) {
    case LidarModel::kA1:  // 5.5 Hz, 2 kSa/s standard mode
      c.rate_hz = 5.5;
      c.angular_step_deg = 0.99;
      c.min_range_m = 0.15;
      c.max_range_m = 12.0;
      break;
    case LidarModel::kA2M8:  // 10 Hz, 8 kSa/s express/boost
      c.rate_hz = 10.0;
      c.angular_step_deg = 0.45;
      c.min_range_m = 0.2;
      c.max_range_m = 12.0;
      break;
    case LidarModel::kA3:  // 10 Hz, 16 kSa/s
      c.rate_hz = 10.0;
      c.angular_step_deg = 0.225;
      c.min_range_m = 0.2;
      c.max_range_m = 25.0;
      break;
    case LidarModel::kS2:  // 10 Hz, 32 kSa/s dense
      c.rate_hz = 10.0;
      c.angular_step_deg = 0.1125;
      c.min_range_m = 0.05;
      c.max_range_m = 30.0;
      break;
    case LidarModel::kC1:  // 10 Hz, 5 kSa/s
      c.rate_hz = 10.0;
      c.angular_step_deg = 0.72;
      c.min_range_m = 0.05;
      c.max_range_m = 12.0;
      break;
  }
  return c;
}

int LidarSimConfig::beams_per_revolution() const {
  return static_cast<int>(std::lround(360.0 / angular_step_deg));
}

double LidarSimConfig::sample_duration_us() const {
  return 1e6 / (rate_hz * static_cast<double>(beams_per_revolution()));
}

std::optional<std::string> LidarSimConfig::validate() const {
  if (!(rate_hz >= 1.0 && rate_hz <= 50.0)) return "lidar rate_hz must be in [1, 50]";
  if (!(angular_step_deg >= 0.05 && angular_step_deg <= 10.0)) {
    return "lidar angular_step_deg must be in [0.05, 10]";
  }
  if (beams_per_revolution() + 8 > static_cast<int>(msg::LidarScan::kMaxPoints)) {
    return "lidar angular_step_deg gives more beams per revolution than a LidarScan holds";
  }
  if (!(min_range_m >= 0.0 && max_range_m > min_range_m && max_range_m <= 100.0)) {
    return "lidar ranges need 0 <= min_range_m < max_range_m <= 100";
  }
  if (!(range_sigma_m >= 0.0 && range_sigma_m <= 1.0)) return "lidar range_sigma_m in [0, 1]";
  if (!(range_sigma_fraction >= 0.0 && range_sigma_fraction <= 0.2)) {
    return "lidar range_sigma_fraction in [0, 0.2]";
  }
  if (!(dropout_probability >= 0.0 && dropout_probability <= 1.0)) {
    return "lidar dropout_probability in [0, 1]";
  }
  if (!(spurious_probability >= 0.0 && spurious_probability <= 1.0)) {
    return "lidar spurious_probability in [0, 1]";
  }
  if (!(spurious_max_range_m >= min_range_m && spurious_max_range_m <= max_range_m)) {
    return "lidar spurious_max_range_m must lie in [min_range_m, max_range_m]";
  }
  if (!std::isfinite(mount.yaw_deg) || !std::isfinite(mount.x_m) || !std::isfinite(mount.y_m)) {
    return "lidar mount must be finite";
  }
  if (!std::isfinite(seam_body_deg)) return "lidar seam_body_deg must be finite";
  return {};
}

drivers::rplidar::HqNode RawBeam::to_hq() const {
  drivers::rplidar::HqNode n;
  const long q14 = std::lround(static_cast<double>(angle_deg) * 16384.0 / 90.0);
  n.angle_z_q14 = static_cast<std::uint16_t>(static_cast<unsigned long>(q14) % 65536UL);
  n.dist_mm_q2 =
      range_m > 0.0F
          ? static_cast<std::uint32_t>(std::lround(static_cast<double>(range_m) * 4000.0))
          : 0U;
  n.quality = n.dist_mm_q2 != 0 ? quality : 0;
  n.flag = start_flag ? 1 : 0;
  return n;
}

namespace {
constexpr double kMinBinRadiusM = 0.1;

drivers::rplidar::ScanAssemblerParams assembler_params(const LidarSimConfig& c) {
  drivers::rplidar::ScanAssemblerParams p;
  p.mount = c.mount;
  p.clockwise = c.clockwise;
  p.seam_body_deg = c.seam_body_deg;
  p.min_range_m = static_cast<float>(c.min_range_m);
  p.max_range_m = static_cast<float>(c.max_range_m);
  p.sample_duration_us = c.sample_duration_us();
  p.keep_no_return = true;
  return p;
}
}  // namespace

LidarSim::LidarSim(const LidarSimConfig& config, const world::World& world)
    : LidarSim(config, RayScene(world)) {}

LidarSim::LidarSim(const LidarSimConfig& config, RayScene scene)
    : config_(config),
      scene_(std::move(scene)),
      rng_(config.seed),
      assembler_(std::make_unique<drivers::rplidar::ScanAssembler>(assembler_params(config))),
      beams_per_rev_(config.beams_per_revolution()),
      sample_ns_(config.sample_duration_us() * 1000.0) {
  raw_building_.reserve(static_cast<std::size_t>(beams_per_rev_));
  raw_done_.reserve(static_cast<std::size_t>(beams_per_rev_));
}

void LidarSim::reset(core::TimeNs t_ns, const BoatTruth& truth) {
  started_ = true;
  origin_ns_ = t_ns;
  next_beam_ = 0;
  last_ns_ = t_ns - 1;  // so the beam at t_ns itself is cast by the first update
  last_truth_ = truth;
  raw_building_.clear();
  assembler_->reset();
}

double LidarSim::beam_world_bearing_deg(double heading_deg, double lidar_deg) const {
  const double sensor_cw_deg = config_.clockwise ? lidar_deg : -lidar_deg;
  return heading_deg + config_.mount.yaw_deg + sensor_cw_deg;
}

void LidarSim::ensure_bins(core::NavPoint a, core::NavPoint b, double span_s) {
  // Centre the region ahead of the boat by half a revolution's travel at its current speed, so
  // one preparation lasts about a revolution; small regions keep the bins short.
  const double step = core::distance_m(a, b);
  const double speed = span_s > 0.0 ? step / span_s : 0.0;
  const double travel = speed / config_.rate_hz;
  const double needed = std::max(kMinBinRadiusM, 0.5 * travel + 0.02);
  // Keep the bins while they cover this step and are not much wider than needed (a jump of the
  // boat, e.g. a simulation reset, needs one wide region; the next step shrinks it again).
  if (scene_.covers(a) && scene_.covers(b) && scene_.prepared_radius_m() <= 4.0 * needed + 0.1) {
    return;
  }
  const double ahead = step > 1e-9 ? 0.5 * travel / step : 0.0;
  const core::NavPoint center{b.north_m + ahead * (b.north_m - a.north_m),
                              b.east_m + ahead * (b.east_m - a.east_m)};
  const double radius = std::max(needed, core::distance_m(center, a) + 0.02);
  scene_.prepare(center, radius, config_.max_range_m);
}

double LidarSim::true_range_m(const core::NavPose& pose, double lidar_deg) const {
  const core::NavPoint origin = core::body_to_nav(pose, {config_.mount.x_m, config_.mount.y_m});
  return scene_.cast_brute(origin, beam_world_bearing_deg(pose.heading_deg, lidar_deg),
                           config_.max_range_m);
}

LidarUpdate LidarSim::update(core::TimeNs now_ns, const BoatTruth& truth) {
  LidarUpdate out;
  if (!started_) reset(now_ns, truth);
  if (now_ns <= last_ns_) return out;
  const core::MountTransform& m = config_.mount;
  const core::NavPoint from = core::body_to_nav(last_truth_.pose, {m.x_m, m.y_m});
  const core::NavPoint to = core::body_to_nav(truth.pose, {m.x_m, m.y_m});
  ensure_bins(from, to, core::ns_to_sec(now_ns - last_ns_));
  const double span_ns = static_cast<double>(now_ns - last_ns_);
  const double turn_deg = core::wrap_deg(truth.pose.heading_deg - last_truth_.pose.heading_deg);
  const double lo_range = config_.min_range_m;
  const double hi_range = config_.max_range_m;
  // Within one update the beam's world bearing grows linearly with its index (lidar rotation
  // plus the interpolated turn), so its direction is stepped by a fixed rotation rather than a
  // sincos per beam; it is re-anchored every update so rounding never accumulates.
  bool anchored = false;
  double bearing_360 = 0.0;
  double dir_n = 1.0;
  double dir_e = 0.0;
  double step_cos = 1.0;
  double step_sin = 0.0;
  double step_deg = 0.0;
  const double sign = config_.clockwise ? 1.0 : -1.0;
  for (;;) {
    // Beam times are non-negative offsets, rounded to the nanosecond.
    const core::TimeNs t_ns =
        origin_ns_ +
        static_cast<core::TimeNs>(std::llround(static_cast<double>(next_beam_) * sample_ns_));
    if (t_ns > now_ns) break;
    const double f = static_cast<double>(t_ns - last_ns_) / span_ns;
    const core::NavPoint origin{from.north_m + f * (to.north_m - from.north_m),
                                from.east_m + f * (to.east_m - from.east_m)};
    const auto index = static_cast<int>(next_beam_ % static_cast<std::uint64_t>(beams_per_rev_));
    const double lidar_deg = static_cast<double>(index) * 360.0 / beams_per_rev_;
    if (!anchored) {
      anchored = true;
      const double heading_deg = last_truth_.pose.heading_deg + f * turn_deg;
      bearing_360 = core::wrap_deg_360(beam_world_bearing_deg(heading_deg, lidar_deg));
      const double rad = core::deg_to_rad(bearing_360);
      dir_n = std::cos(rad);
      dir_e = std::sin(rad);
      step_deg = sign * 360.0 / beams_per_rev_ + turn_deg * sample_ns_ / span_ns;
      step_cos = std::cos(core::deg_to_rad(step_deg));
      step_sin = std::sin(core::deg_to_rad(step_deg));
    } else {
      bearing_360 += step_deg;
      if (bearing_360 >= 360.0) bearing_360 -= 360.0;
      if (bearing_360 < 0.0) bearing_360 += 360.0;
      const double n = dir_n * step_cos - dir_e * step_sin;
      dir_e = dir_n * step_sin + dir_e * step_cos;
      dir_n = n;
    }

    double range = scene_.cast(origin, bearing_360, dir_n, dir_e);
    if (range >= 0.0) {
      range += rng_.normal(config_.range_sigma_m + config_.range_sigma_fraction * range);
    }
    // One draw decides the beam's fate: dropout, a spurious near echo, or the true return.
    const double fate = rng_.uniform();
    if (fate < config_.dropout_probability) {
      range = -1.0;
    } else if (fate < config_.dropout_probability + config_.spurious_probability) {
      range = rng_.uniform(lo_range, config_.spurious_max_range_m);
    }
    RawBeam beam;
    beam.angle_deg = static_cast<float>(lidar_deg);
    beam.start_flag = index == 0;
    beam.stamp_ns = t_ns;
    if (range >= lo_range && range <= hi_range) {
      beam.range_m = static_cast<float>(range);
      beam.quality = config_.quality;
    }
    if (index == 0) raw_building_.clear();
    raw_building_.push_back(beam);
    if (index == beams_per_rev_ - 1) {
      if (out.raw_ready) ++missed_scans_;
      std::swap(raw_building_, raw_done_);
      raw_building_.clear();
      out.raw_ready = true;
    }
    if (assembler_->add(beam.to_hq(), t_ns)) {
      if (out.scan_ready) ++missed_scans_;
      out.scan_ready = true;
    }
    ++next_beam_;
    ++out.beams;
  }
  last_ns_ = now_ns;
  last_truth_ = truth;
  return out;
}

}  // namespace coxswain::sim::sensors
