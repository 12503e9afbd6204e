// SPDX-License-Identifier: Apache-2.0
#include "sim/sensors/sensor_config.hpp"

#include <algorithm>

namespace coxswain::sim::sensors {

using config::Bounds;
using config::MapReader;

std::optional<std::string> SensorConfig::validate() const {
  for (auto e : {lidar.validate(), gnss.validate(), imu.validate(), camera.validate()}) {
    if (e) return e;
  }
  return std::nullopt;
}

namespace {

core::MountTransform read_mount(MapReader& r, core::MountTransform fallback) {
  std::optional<MapReader> m = r.map("mount");
  if (!m) return fallback;
  core::MountTransform out;
  out.yaw_deg = m->get<double>("yaw_deg", fallback.yaw_deg, {-360.0, 360.0});
  out.x_m = m->get<double>("x_m", fallback.x_m, {-10.0, 10.0});
  out.y_m = m->get<double>("y_m", fallback.y_m, {-10.0, 10.0});
  m->finish();
  return out;
}

std::uint64_t read_seed(MapReader& r, std::uint64_t derived) {
  if (!r.has("seed")) return derived;
  return r.get<std::uint64_t>("seed", derived);
}

void check(MapReader& r, const std::optional<std::string>& problem) {
  if (problem) r.error("", *problem);
}

LidarSimConfig read_lidar(MapReader& r, std::uint64_t seed) {
  const LidarModel model = r.get_enum<LidarModel>("model", LidarModel::kA2M8,
                                                  {{"a1", LidarModel::kA1},
                                                   {"a2m8", LidarModel::kA2M8},
                                                   {"a3", LidarModel::kA3},
                                                   {"s2", LidarModel::kS2},
                                                   {"c1", LidarModel::kC1}});
  LidarSimConfig c = LidarSimConfig::for_model(model);
  c.rate_hz = r.get<double>("rate_hz", c.rate_hz);
  c.angular_step_deg = r.get<double>("angular_step_deg", c.angular_step_deg);
  c.min_range_m = r.get<double>("min_range_m", c.min_range_m);
  c.max_range_m = r.get<double>("max_range_m", c.max_range_m);
  c.range_sigma_m = r.get<double>("range_sigma_m", c.range_sigma_m);
  c.range_sigma_fraction = r.get<double>("range_sigma_fraction", c.range_sigma_fraction);
  c.dropout_probability = r.get<double>("dropout_probability", c.dropout_probability);
  c.spurious_probability = r.get<double>("spurious_probability", c.spurious_probability);
  c.spurious_max_range_m = r.get<double>("spurious_max_range_m", c.spurious_max_range_m);
  c.quality = static_cast<std::uint8_t>(r.get<int>("quality", c.quality, {1, 255}));
  c.mount = read_mount(r, c.mount);
  c.clockwise = r.get<bool>("clockwise", c.clockwise);
  c.seam_body_deg = r.get<double>("seam_body_deg", c.seam_body_deg);
  c.seed = read_seed(r, seed);
  check(r, c.validate());
  r.finish();
  return c;
}

GnssSimConfig read_gnss(MapReader& r, std::uint64_t seed) {
  GnssSimConfig c;
  c.rate_hz = r.get<double>("rate_hz", c.rate_hz);
  c.mount = read_mount(r, c.mount);
  c.antenna_height_m = r.get<double>("antenna_height_m", c.antenna_height_m);
  c.bias_mean_m = r.get<double>("bias_mean_m", c.bias_mean_m);
  c.bias_direction_deg = r.get<double>("bias_direction_deg", c.bias_direction_deg);
  c.bias_wander_sigma_m = r.get<double>("bias_wander_sigma_m", c.bias_wander_sigma_m);
  c.bias_tau_s = r.get<double>("bias_tau_s", c.bias_tau_s);
  c.bias_max_m = r.get<double>("bias_max_m", c.bias_max_m);
  c.noise_sigma_m = r.get<double>("noise_sigma_m", c.noise_sigma_m);
  c.height_noise_sigma_m = r.get<double>("height_noise_sigma_m", c.height_noise_sigma_m);
  c.velocity_noise_mps = r.get<double>("velocity_noise_mps", c.velocity_noise_mps);
  c.outage_rate_per_min = r.get<double>("outage_rate_per_min", c.outage_rate_per_min);
  c.outage_mean_s = r.get<double>("outage_mean_s", c.outage_mean_s);
  c.rtk = r.get_enum<RtkMode>(
      "rtk", c.rtk,
      {{"off", RtkMode::kOff}, {"float", RtkMode::kFloat}, {"fixed", RtkMode::kFixed}});
  c.rtk_fixed_sigma_m = r.get<double>("rtk_fixed_sigma_m", c.rtk_fixed_sigma_m);
  c.rtk_float_sigma_m = r.get<double>("rtk_float_sigma_m", c.rtk_float_sigma_m);
  c.rtk_float_bias_m = r.get<double>("rtk_float_bias_m", c.rtk_float_bias_m);
  c.rtk_fix_delay_s = r.get<double>("rtk_fix_delay_s", c.rtk_fix_delay_s);
  c.satellites = r.get<int>("satellites", c.satellites);
  c.hdop = r.get<double>("hdop", c.hdop);
  c.utc_at_zero_ns = r.get<std::int64_t>("utc_at_zero_ns", c.utc_at_zero_ns);
  c.seed = read_seed(r, seed);
  check(r, c.validate());
  r.finish();
  return c;
}

ImuSimConfig read_imu(MapReader& r, std::uint64_t seed) {
  ImuSimConfig c;
  c.rate_hz = r.get<double>("rate_hz", c.rate_hz);
  c.mount_yaw_deg = r.get<double>("mount_yaw_deg", c.mount_yaw_deg);
  c.declination_deg = r.get<double>("declination_deg", c.declination_deg);
  c.yaw_noise_sigma_deg = r.get<double>("yaw_noise_sigma_deg", c.yaw_noise_sigma_deg);
  c.yaw_drift_deg_per_sqrt_s =
      r.get<double>("yaw_drift_deg_per_sqrt_s", c.yaw_drift_deg_per_sqrt_s);
  c.yaw_drift_max_deg = r.get<double>("yaw_drift_max_deg", c.yaw_drift_max_deg);
  const std::vector<YAML::Node> items = r.sequence("disturbances");
  for (std::size_t i = 0; i < items.size(); ++i) {
    std::optional<MapReader> d = r.element(items[i], i, "disturbances");
    if (!d) continue;
    MagneticDisturbance m;
    m.center.north_m = d->require<double>("north_m");
    m.center.east_m = d->require<double>("east_m");
    m.radius_m = d->get<double>("radius_m", m.radius_m, {1e-3, 1e4});
    m.offset_deg = d->get<double>("offset_deg", m.offset_deg, {-180.0, 180.0});
    d->finish();
    c.disturbances.push_back(m);
  }
  c.sinusoid_amplitude_deg = r.get<double>("sinusoid_amplitude_deg", c.sinusoid_amplitude_deg);
  c.sinusoid_wavelength_m = r.get<double>("sinusoid_wavelength_m", c.sinusoid_wavelength_m);
  c.sinusoid_direction_deg = r.get<double>("sinusoid_direction_deg", c.sinusoid_direction_deg);
  c.roll_amplitude_deg = r.get<double>("roll_amplitude_deg", c.roll_amplitude_deg);
  c.pitch_amplitude_deg = r.get<double>("pitch_amplitude_deg", c.pitch_amplitude_deg);
  c.wave_period_s = r.get<double>("wave_period_s", c.wave_period_s);
  c.attitude_noise_sigma_deg =
      r.get<double>("attitude_noise_sigma_deg", c.attitude_noise_sigma_deg);
  c.gyro_noise_sigma_dps = r.get<double>("gyro_noise_sigma_dps", c.gyro_noise_sigma_dps);
  c.accel_noise_sigma_g = r.get<double>("accel_noise_sigma_g", c.accel_noise_sigma_g);
  c.field_horizontal_ut = r.get<double>("field_horizontal_ut", c.field_horizontal_ut);
  c.field_down_ut = r.get<double>("field_down_ut", c.field_down_ut);
  c.temperature_c = r.get<double>("temperature_c", c.temperature_c);
  c.seed = read_seed(r, seed);
  check(r, c.validate());
  r.finish();
  return c;
}

CameraSimConfig read_camera(MapReader& r, std::uint64_t seed) {
  CameraSimConfig c;
  c.width_px = r.get<int>("width_px", c.width_px);
  c.height_px = r.get<int>("height_px", c.height_px);
  c.hfov_deg = r.get<double>("hfov_deg", c.hfov_deg);
  c.rate_hz = r.get<double>("rate_hz", c.rate_hz);
  c.mount = read_mount(r, c.mount);
  c.height_m = r.get<double>("height_m", c.height_m);
  c.tilt_down_deg = r.get<double>("tilt_down_deg", c.tilt_down_deg);
  c.wall_piece_m = r.get<double>("wall_piece_m", c.wall_piece_m);
  c.glare = r.get<bool>("glare", c.glare);
  c.glare_gain = r.get<double>("glare_gain", c.glare_gain);
  c.glare_saturation_loss = r.get<double>("glare_saturation_loss", c.glare_saturation_loss);
  c.sun_bearing_deg = r.get<double>("sun_bearing_deg", c.sun_bearing_deg);
  c.sun_elevation_deg = r.get<double>("sun_elevation_deg", c.sun_elevation_deg);
  c.sun_blob_radius_px = r.get<double>("sun_blob_radius_px", c.sun_blob_radius_px);
  c.blur_kernel_px = r.get<int>("blur_kernel_px", c.blur_kernel_px);
  c.noise_sigma = r.get<double>("noise_sigma", c.noise_sigma);
  c.venue = r.get_enum("venue", c.venue,
                       {{"pool", Venue::kPool},
                        {"harbour", Venue::kHarbour},
                        {"overcast", Venue::kOvercast},
                        {"low_sun", Venue::kLowSun}});
  c.seed = read_seed(r, seed);
  check(r, c.validate());
  r.finish();
  return c;
}

}  // namespace

void apply_conditions(const world::SensorConditions& c, SensorConfig& config) {
  GnssSimConfig& g = config.gnss;
  if (c.gnss_bias_mean_m) g.bias_mean_m = *c.gnss_bias_mean_m;
  if (c.gnss_bias_direction_deg) g.bias_direction_deg = *c.gnss_bias_direction_deg;
  if (c.gnss_bias_wander_sigma_m) g.bias_wander_sigma_m = *c.gnss_bias_wander_sigma_m;
  if (c.gnss_bias_tau_s) g.bias_tau_s = *c.gnss_bias_tau_s;
  if (c.gnss_noise_sigma_m) g.noise_sigma_m = *c.gnss_noise_sigma_m;
  if (c.gnss_bias_max_m) {
    g.bias_max_m = *c.gnss_bias_max_m;
  } else if (c.gnss_bias_mean_m) {
    g.bias_max_m = std::max(g.bias_max_m, g.bias_mean_m + 2.0 * g.bias_wander_sigma_m);
  }
  CameraSimConfig& k = config.camera;
  if (c.camera_venue) {
    if (const std::optional<Venue> v = parse_venue(*c.camera_venue)) k.venue = *v;
  }
  if (c.camera_glare) k.glare = *c.camera_glare;
  if (c.camera_glare_gain) k.glare_gain = *c.camera_glare_gain;
  if (c.camera_glare_saturation_loss) k.glare_saturation_loss = *c.camera_glare_saturation_loss;
  if (c.camera_sun_bearing_deg) k.sun_bearing_deg = *c.camera_sun_bearing_deg;
  if (c.camera_sun_elevation_deg) k.sun_elevation_deg = *c.camera_sun_elevation_deg;
  if (c.camera_sun_blob_radius_px) k.sun_blob_radius_px = *c.camera_sun_blob_radius_px;
  if (c.camera_blur_kernel_px) k.blur_kernel_px = *c.camera_blur_kernel_px;
  if (c.camera_noise_sigma) k.noise_sigma = *c.camera_noise_sigma;
}

SensorConfig load_sensor_config(MapReader& reader) {
  SensorConfig c;
  c.seed = reader.get<std::uint64_t>("seed", c.seed);
  const auto sub = [&](std::string_view key, auto read, auto& field, std::uint64_t stream) {
    const std::uint64_t derived = derive_seed(c.seed, stream);
    if (std::optional<MapReader> m = reader.map(key)) {
      field = read(*m, derived);
    } else {
      field.seed = derived;
    }
  };
  sub("lidar", read_lidar, c.lidar, 1);
  sub("gnss", read_gnss, c.gnss, 2);
  sub("imu", read_imu, c.imu, 3);
  sub("camera", read_camera, c.camera, 4);
  reader.finish();
  return c;
}

SensorConfig load_sensor_config(const YAML::Node& node, const std::string& file,
                                config::ConfigErrors& errors) {
  MapReader reader(node, file, "sensors", errors);
  return load_sensor_config(reader);
}

std::optional<SensorConfig> load_sensor_config_file(const std::string& path,
                                                    config::ConfigErrors& errors) {
  const std::optional<YAML::Node> root = config::load_yaml_file(path, errors);
  if (!root) return std::nullopt;
  MapReader top(*root, path, "", errors);
  std::optional<MapReader> block = top.map("sensors", true);
  std::optional<SensorConfig> out;
  if (block) out = load_sensor_config(*block);
  // Other top-level keys (kind, name...) belong to whoever owns the file.
  if (!errors.empty()) return std::nullopt;
  return out;
}

}  // namespace coxswain::sim::sensors
