// SPDX-License-Identifier: Apache-2.0
#pragma once
// Test rig for MissionCore: a configuration built in code, a Snapshot filled by hand in virtual
// time, and a unicycle boat that integrates the core's pulse widths (a deliberately small model;
// the simulator proper comes from tools/sim).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "coxswain/config/config.hpp"
#include "coxswain/core/angles.hpp"
#include "coxswain/core/geodesy.hpp"
#include "coxswain/core/latest_store.hpp"
#include "coxswain/mission/mission_core.hpp"

namespace coxswain::mission::test {

inline constexpr core::TimeNs kTickNs = 20 * core::kNsPerMs;  // 50 Hz

/// A mission with one task and the defaults of every engine; immediate start, no calibration.
inline config::Configuration base_config(config::TaskType type) {
  config::Configuration c;
  c.mission.name = "test";
  c.mission.origin = {35.0695, 128.828, 0.0};
  c.mission.start_mode = config::StartMode::kImmediate;
  c.mission.calibrate_gps_at_start = false;
  c.mission.gnss_stale_ms = 450;
  config::TaskConfig t;
  t.type = type;
  t.name = std::string(config::task_type_name(type));
  c.mission.tasks.push_back(t);
  return c;
}

/// The obstacle course to one waypoint `goal_north_m` due north of the origin.
inline config::Configuration obstacle_config(double goal_north_m = 40.0) {
  config::Configuration c = base_config(config::TaskType::kObstacleCourse);
  const core::LocalFrame f(c.mission.origin);
  c.mission.tasks[0].waypoints.push_back(f.to_geo({goal_north_m, 0.0}));
  return c;
}

/// Body-frame lidar returns of a circle (buoy) of `radius_m` at (forward, starboard).
inline void add_circle(msg::LidarScan& scan, double forward_m, double starboard_m,
                       double radius_m) {
  // Only the bearings the circle can cover (the scan is 0.5 deg; the test scenes are small).
  const double dist = std::hypot(forward_m, starboard_m);
  if (dist <= radius_m) return;
  const double centre_deg = core::rad_to_deg(std::atan2(starboard_m, forward_m));
  const double half_deg = core::rad_to_deg(std::asin(radius_m / dist)) + 0.5;
  for (int i = 0; i < 720; ++i) {
    const double b = -180.0 + 0.5 * i;
    if (std::abs(core::angle_diff_deg(b, centre_deg)) > half_deg) continue;
    const double ux = std::cos(core::deg_to_rad(b));
    const double uy = std::sin(core::deg_to_rad(b));
    const double proj = forward_m * ux + starboard_m * uy;
    const double d2 = forward_m * forward_m + starboard_m * starboard_m - proj * proj;
    if (proj <= 0.0 || d2 > radius_m * radius_m) continue;
    const double r = proj - std::sqrt(radius_m * radius_m - d2);
    (void)scan.push({static_cast<float>(b), static_cast<float>(r), 200, 0});
  }
}

/// Returns of a straight wall perpendicular to the bow at `forward_m`, +-half_width_m.
inline void add_wall_ahead(msg::LidarScan& scan, double forward_m, double half_width_m) {
  for (int i = 0; i < 720; ++i) {
    const double b = -180.0 + 0.5 * i;
    const double ux = std::cos(core::deg_to_rad(b));
    if (ux <= 0.0) continue;
    const double r = forward_m / ux;
    if (std::abs(r * std::sin(core::deg_to_rad(b))) > half_width_m) continue;
    (void)scan.push({static_cast<float>(b), static_cast<float>(r), 200, 0});
  }
}

/// A slip round the bow: its back wall `back_m` ahead and its sides `half_width_m` either side of
/// the centre line, from the back to 2 m astern (one return per half degree, the nearest).
inline void add_slip_around(msg::LidarScan& scan, double back_m, double half_width_m) {
  for (int i = 0; i < 720; ++i) {
    const double b = -180.0 + 0.5 * i;
    const double ux = std::cos(core::deg_to_rad(b));
    const double uy = std::sin(core::deg_to_rad(b));
    double r = 1e9;
    if (ux > 0.0 && std::abs(back_m / ux * uy) <= half_width_m) r = back_m / ux;
    if (std::abs(uy) > 1e-9) {
      const double side = half_width_m / std::abs(uy);
      const double x = side * ux;
      if (x >= -2.0 && x <= back_m) r = std::min(r, side);
    }
    if (r < 1e8) (void)scan.push({static_cast<float>(b), static_cast<float>(r), 200, 0});
  }
}

/// Drives a MissionCore in virtual time.
class Rig {
 public:
  explicit Rig(const config::Configuration& c)
      : config(c),
        frame(c.mission.origin),
        core(c.boat, c.mission),
        snap(std::make_unique<core::Snapshot>()) {
    arduino_autonomous();
  }

  // ---- sensors ----
  void imu(double measured_deg) {
    auto& s = snap->imu;
    s.value.heading_deg = measured_deg;
    s.value.stamp_ns = now;
    s.stamp_ns = now;
    ++s.sequence;
  }
  void gnss(core::NavPoint p, bool usable = true) {
    const core::GeoPoint g = frame.to_geo(p);
    auto& s = snap->gnss;
    s.value.lat_deg = g.lat_deg;
    s.value.lon_deg = g.lon_deg;
    s.value.fix_ok = usable;
    s.value.fix_type = usable ? msg::FixType::k3D : msg::FixType::kNoFix;
    s.value.h_acc_m = gnss_h_acc_m;
    s.value.velocity_valid = gnss_velocity.has_value();
    if (gnss_velocity) {
      s.value.vel_north_mps = gnss_velocity->north_m;
      s.value.vel_east_mps = gnss_velocity->east_m;
    }
    s.value.stamp_ns = now;
    s.stamp_ns = now;
    ++s.sequence;
  }
  void lidar() {  // publishes `scan`
    auto& s = snap->lidar;
    s.value = scan;
    s.value.stamp_ns = now;
    s.stamp_ns = now;
    ++s.sequence;
  }
  void camera(std::initializer_list<msg::Detection> dets) {
    auto& s = snap->camera;
    s.value.count = 0;
    for (const auto& d : dets) (void)s.value.push(d);
    s.value.stamp_ns = now;
    s.stamp_ns = now;
    ++s.sequence;
  }
  void arduino_autonomous(bool start_switch = false) {
    arduino.mode = msg::ControlMode::kAutonomous;
    arduino.estop = false;
    arduino.start_switch = start_switch;
  }
  void publish_arduino() {
    snap->arduino.value = arduino;
    snap->arduino.stamp_ns = now;
    ++snap->arduino.sequence;
  }

  /// Publishes the live sensors (boat pose from the unicycle) and steps once.
  void tick() {
    if (live_imu) imu(heading_deg + heading_noise());
    if (live_gnss && (tick_count_ % 10 == 0)) {  // 5 Hz
      gnss({position.north_m + gnss_bias.north_m, position.east_m + gnss_bias.east_m}, gnss_usable);
    }
    if (live_lidar && (tick_count_ % 5 == 0)) {  // 10 Hz
      if (!world_buoys.empty() || !world_walls.empty()) scan_world();
      lidar();
    }
    if (live_arduino && (tick_count_ % 5 == 0)) publish_arduino();
    if (!world_objects.empty() && (tick_count_ % 5 == 0)) see_world();
    core.step(*snap, now, out);
    for (std::uint32_t i = 0; i < out.transitions.count; ++i) {
      const Transition& t = out.transitions.entries[i];
      log.push_back("[" + std::to_string(core::ns_to_sec(now)) + "] " + std::string(t.from.view()) +
                    " -> " + std::string(t.to.view()) + ": " + std::string(t.reason.view()));
    }
    if (finish_after_step) core.finish_tick();
    if (move) integrate();
    now += kTickNs;
    ++tick_count_;
  }
  void run_for(double seconds) {
    const auto n = static_cast<int>(seconds / core::ns_to_sec(kTickNs));
    for (int i = 0; i < n; ++i) tick();
  }
  /// Ticks until `pred` or the time runs out; true when `pred` held.
  template <class Pred>
  bool run_until(Pred pred, double max_s) {
    const auto n = static_cast<int>(max_s / core::ns_to_sec(kTickNs));
    for (int i = 0; i < n; ++i) {
      tick();
      if (pred()) return true;
    }
    return false;
  }
  [[nodiscard]] std::string path() const { return std::string(out.status.state_path.view()); }
  [[nodiscard]] bool logged(const std::string& fragment) const {
    return std::any_of(log.begin(), log.end(),
                       [&](const std::string& l) { return l.find(fragment) != std::string::npos; });
  }
  [[nodiscard]] std::string log_text() const {
    std::string s;
    for (const auto& l : log) s += l + "\n";
    return s;
  }
  [[nodiscard]] bool neutral() const {
    return out.command.pulse_us[0] == 1500 && out.command.pulse_us[1] == 1500 &&
           !out.command.active;
  }
  /// Thrust fraction the ESC pulse means (servo-thruster layout, boat.yaml defaults).
  [[nodiscard]] double thrust_frac() const {
    const double p = out.command.pulse_us[1];
    return p <= 1550.0 ? 0.0 : (p - 1550.0) / (1900.0 - 1550.0);
  }

  /// Rebuilds `scan` from `world_buoys` and `world_walls` as seen from the boat's pose: a
  /// 0.5-degree revolution, each buoy's returns buoy by buoy (the rig does not occlude), one ray
  /// per bearing to the nearest wall, then a "no return" (range 0) on each bearing over open
  /// water, as the scanner gives it.
  void scan_world() {
    scan.clear();
    const core::NavPose pose{position, heading_deg};
    for (const WorldBuoy& b : world_buoys) {
      const core::BodyPoint p = core::nav_to_body(pose, b.centre);
      add_circle(scan, p.forward_m, p.starboard_m, b.radius_m);
    }
    // One ray per 0.5 degrees, to the nearest wall within the lidar's 12 m.
    for (int i = 0; i < 720 && !world_walls.empty(); ++i) {
      const double b = -180.0 + 0.5 * i + 0.25;
      const double dx = std::cos(core::deg_to_rad(b));
      const double dy = std::sin(core::deg_to_rad(b));
      double nearest = 12.0;
      for (const WorldWall& w : world_walls) {
        const core::BodyPoint p0 = core::nav_to_body(pose, w.from);
        const core::BodyPoint p1 = core::nav_to_body(pose, w.to);
        const double ex = p1.forward_m - p0.forward_m;
        const double ey = p1.starboard_m - p0.starboard_m;
        const double den = dx * ey - dy * ex;
        if (std::abs(den) < 1e-12) continue;
        const double t = (p0.forward_m * ey - p0.starboard_m * ex) / den;  // along the ray
        const double u = (p0.forward_m * dy - p0.starboard_m * dx) / den;  // along the wall
        if (t > 0.05 && u >= 0.0 && u <= 1.0) nearest = std::min(nearest, t);
      }
      if (nearest < 12.0) {
        (void)scan.push({static_cast<float>(b), static_cast<float>(nearest), 200, 0});
      }
    }
    std::array<bool, 720> covered{};
    for (std::uint32_t k = 0; k < scan.point_count; ++k) {
      const auto bin = static_cast<long>(
          std::floor((static_cast<double>(scan.points[k].bearing_deg) + 180.0) * 2.0));
      covered[static_cast<std::size_t>(std::clamp(bin, 0L, 719L))] = true;
    }
    for (std::size_t i = 0; i < covered.size(); ++i) {
      if (!covered[i])
        (void)scan.push({static_cast<float>(-180.0 + 0.5 * static_cast<double>(i)), 0.0F, 0, 0});
    }
  }
  struct WorldWall {
    core::NavPoint from;
    core::NavPoint to;
  };
  std::vector<WorldWall> world_walls;
  /// Publishes a camera frame of the `world_objects` inside the camera's field of view.
  void see_world() {
    auto& s = snap->camera;
    s.value.count = 0;
    const core::NavPose pose{position, heading_deg};
    for (const WorldObject& o : world_objects) {
      const core::BodyPoint p = core::nav_to_body(pose, o.centre);
      const double range = std::hypot(p.forward_m, p.starboard_m);
      const double bearing = core::rad_to_deg(std::atan2(p.starboard_m, p.forward_m));
      if (range > 20.0 || std::abs(core::angle_diff_deg(bearing, camera_yaw_deg)) > 40.0) continue;
      msg::Detection d;
      d.colour = o.colour;
      d.shape = o.shape;
      d.bearing_deg = static_cast<float>(bearing);
      d.area_px = static_cast<float>(5000.0 / (range * range + 1.0));
      (void)s.value.push(d);
    }
    s.value.stamp_ns = now;
    s.stamp_ns = now;
    ++s.sequence;
  }
  struct WorldObject {
    core::NavPoint centre;
    msg::Colour colour = msg::Colour::kUnknown;
    msg::Shape shape = msg::Shape::kUnknown;
  };
  std::vector<WorldObject> world_objects;
  double camera_yaw_deg = -90.0;  // the 2026 plan: the camera looks to port

  struct WorldBuoy {
    core::NavPoint centre;
    double radius_m = 0.5;
  };
  std::vector<WorldBuoy> world_buoys;

  // ---- the unicycle boat ----
  void integrate() {
    const double dt = core::ns_to_sec(kTickNs);
    const double deflection_deg = (out.command.pulse_us[0] - 1500.0) / 400.0 * 25.0;
    // Astern (boat.yaml's 1450..1120 us) the propeller is weaker, and the turned thruster pulls
    // the stern the other way: the same deflection turns the boat the other way.
    const double esc_us = out.command.pulse_us[1];
    const double astern_frac = esc_us >= 1450.0 ? 0.0 : (1450.0 - esc_us) / (1450.0 - 1120.0);
    const double target_speed = 1.5 * thrust_frac() - 0.9 * astern_frac;
    speed_mps += (target_speed - speed_mps) * std::min(1.0, dt / 1.0);  // 1 s surge lag
    const double wash = astern_frac > 0.0 ? -1.0 : 1.0;
    const double yaw_rate_dps =
        wash * 4.0 * deflection_deg * std::min(1.0, std::abs(speed_mps) + 0.2);
    heading_deg = core::wrap_deg(heading_deg + yaw_rate_dps * dt);
    position.north_m += speed_mps * dt * std::cos(core::deg_to_rad(heading_deg));
    position.east_m += speed_mps * dt * std::sin(core::deg_to_rad(heading_deg));
  }

  config::Configuration config;
  core::LocalFrame frame;
  MissionCore core;
  std::unique_ptr<core::Snapshot> snap;
  CoreOutput out;
  std::vector<std::string> log;
  core::TimeNs now = 10 * core::kNsPerSec;
  msg::ArduinoStatus arduino;
  msg::LidarScan scan;
  bool live_imu = true;
  bool live_gnss = true;
  bool gnss_usable = true;
  std::optional<core::NavPoint> gnss_velocity;  // reported with each fix when set
  core::NavPoint gnss_bias;                     // added to every live fix (receiver error)
  double gnss_h_acc_m = 0.1;  // the receiver's accuracy estimate (noise-free fixes here)
  bool live_lidar = true;
  bool live_arduino = true;
  bool move = false;
  /// Calls MissionCore::finish_tick() after each step, as the daemon does; else the work runs
  /// as the next step begins.
  bool finish_after_step = false;
  core::NavPoint position;
  double heading_deg = 0.0;
  double speed_mps = 0.0;
  double noise_amplitude_deg = 0.0;

 private:
  double heading_noise() {
    if (noise_amplitude_deg == 0.0) return 0.0;
    // Deterministic pseudo-random noise in [-a, a] (a 32-bit LCG).
    lcg_ = lcg_ * 1664525U + 1013904223U;
    return noise_amplitude_deg * (static_cast<double>(lcg_ >> 8U) / 8388608.0 - 1.0);
  }
  std::uint32_t lcg_ = 12345U;
  std::uint64_t tick_count_ = 0;
};

}  // namespace coxswain::mission::test
