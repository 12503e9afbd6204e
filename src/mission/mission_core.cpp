// SPDX-License-Identifier: Apache-2.0
#include "coxswain/mission/mission_core.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <cstring>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "coxswain/control/actuator_mixer.hpp"
#include "coxswain/control/filters.hpp"
#include "coxswain/control/heading_pid.hpp"
#include "coxswain/control/speed_schedule.hpp"
#include "coxswain/core/angles.hpp"
#include "coxswain/core/geodesy.hpp"
#include "coxswain/guidance/gps_calibration.hpp"
#include "coxswain/guidance/mag_calibration.hpp"
#include "coxswain/guidance/nav_filter.hpp"
#include "coxswain/guidance/nav_map.hpp"
#include "coxswain/guidance/position_filter.hpp"
#include "coxswain/mission/tunable_parameters.hpp"
#include "coxswain/perception/lidar_clusterer.hpp"
#include "tasks.hpp"

namespace coxswain::mission {

std::string_view hold_reason_name(HoldReason r) {
  switch (r) {
    case HoldReason::kNone:
      return "none";
    case HoldReason::kLidarStale:
      return "lidar_stale";
    case HoldReason::kImuStale:
      return "imu_stale";
    case HoldReason::kGnssStale:
      return "gnss_stale";
    case HoldReason::kArduinoStale:
      return "arduino_stale";
    case HoldReason::kManualMode:
      return "manual_mode";
    case HoldReason::kEstop:
      return "estop";
    case HoldReason::kOperator:
      return "operator";
  }
  return "unknown";
}

namespace {

// Every field of the frame back to its default but the three arrays (14 KB a tick otherwise):
// nothing reads an array past its count, and each step writes up to the count it sets.
void reset_viz(VizFrame& v) {
  static_assert(std::is_standard_layout_v<VizFrame> && std::is_trivially_copyable_v<VizFrame>);
  static const VizFrame kEmpty{};
  const auto keep = [&](std::size_t from, std::size_t to) {
    std::memcpy(reinterpret_cast<unsigned char*>(&v) + from,
                reinterpret_cast<const unsigned char*>(&kEmpty) + from, to - from);
  };
  keep(0, offsetof(VizFrame, path));
  keep(offsetof(VizFrame, path) + sizeof(v.path), offsetof(VizFrame, segments));
  keep(offsetof(VizFrame, segments) + sizeof(v.segments), offsetof(VizFrame, danger));
  keep(offsetof(VizFrame, danger) + sizeof(v.danger), sizeof(VizFrame));
}

using detail::GuidanceRequest;
using detail::PlanRequest;
using detail::reason_printf;
using detail::Task;
using detail::TaskContext;
using detail::TaskResult;

control::MixerConfig mixer_config(const config::ActuatorsConfig& a) {
  control::MixerConfig mc;
  mc.layout = a.layout;
  mc.servo.center_us = a.servo.center_us;
  mc.servo.min_us = a.servo.min_us;
  mc.servo.max_us = a.servo.max_us;
  mc.servo.max_deflection_deg = a.servo.max_deflection_deg;
  mc.servo.sign = a.servo.reversed ? -1 : 1;
  control::ThrusterConfig t;
  t.neutral_us = a.thruster.neutral_us;
  t.min_us = a.thruster.min_us;
  t.max_us = a.thruster.max_us;
  t.forward_start_us = a.thruster.forward_start_us;
  t.forward_max_us = a.thruster.max_us;
  t.reverse_start_us = a.thruster.reverse_start_us;
  t.reverse_max_us = a.thruster.min_us;
  t.reverse_allowed = a.thruster.reverse_allowed;
  mc.thruster = t;
  mc.twin.track_width_m = a.twin_track_width_m;
  mc.twin.port = t;
  mc.twin.starboard = t;
  if (auto e = mc.validate()) throw std::invalid_argument("actuators: " + *e);
  return mc;
}

template <class T>
bool fresh(const core::Sample<T>& s, core::TimeNs now_ns, std::uint32_t limit_ms) {
  return s.valid() && !s.is_stale(now_ns, core::ms_to_ns(limit_ms));
}

// A driver that reports its device gone (port vanished, open failed) after the last sample it
// delivered: the device is down now, without waiting for the sample to age out.
bool device_down(const core::Snapshot& s, msg::DeviceId id, core::TimeNs last_sample_ns) {
  const auto& h = s.health[static_cast<std::size_t>(id)];
  if (!h.valid()) return false;
  const msg::DeviceState st = h.value.state;
  const bool down = st == msg::DeviceState::kAbsent || st == msg::DeviceState::kError ||
                    st == msg::DeviceState::kStale;
  return down && h.stamp_ns >= last_sample_ns;
}

double age_ms(const core::TimeNs age_ns) {
  return age_ns == INT64_MAX ? -1.0 : static_cast<double>(age_ns) / 1e6;
}

// The hull the avoidance keeps clear is the boat's (boat.yaml), not a mission setting.
config::MissionConfig with_hull(config::MissionConfig m, const config::HullConfig& hull) {
  m.avoidance.half_beam_m = 0.5 * hull.beam_m;
  m.avoidance.hull_length_m = hull.length_m;
  m.avoidance.bow_ahead_m = hull.bow_overhang_m;
  return m;
}

}  // namespace

struct MissionCore::Impl {
  enum class Top : std::uint8_t { kWaitForStart, kActive, kFinished };

  Impl(const config::BoatConfig& boat, const config::MissionConfig& mission,
       const guidance::MagCalibration& magnetometer)
      : m(with_hull(mission, boat.hull)),
        camera_timeout_ms(mission.camera_stale_ms),
        gnss_mount(boat.mounts.gnss),
        frame(mission.origin),
        mixer(mixer_config(boat.actuators)),
        pid(mission.heading_pid),
        schedule(mission.speed),
        ramp({mission.speed.rise_per_s, mission.speed.fall_per_s}),
        heading_filter({mission.navigation.heading_filter_tau_s}),
        calibration(mission.gps_calibration, core::NavPoint{}),
        position_filter({mission.navigation.position_gain}),
        kalman(mission.navigation.position_gain < 1.0),
        nav(mission.navigation.filter),
        clusterer(mission.clustering) {
    if (auto e = m.navigation.filter.validate()) throw std::invalid_argument(*e);
    mag_cal = magnetometer;
    mag_calibrated = magnetometer.hard_iron_x_ut != 0.0 || magnetometer.hard_iron_y_ut != 0.0 ||
                     magnetometer.soft_iron != std::array<double, 4>{1.0, 0.0, 0.0, 1.0};
    if (auto e = m.heading_pid.validate()) throw std::invalid_argument("heading_pid: " + *e);
    if (auto e = m.speed.validate()) throw std::invalid_argument("speed: " + *e);
    if (auto e = m.gps_calibration.validate()) throw std::invalid_argument(*e);
    if (auto e = m.waypoints.validate()) throw std::invalid_argument(*e);
    if (m.tasks.empty()) throw std::invalid_argument("mission has no tasks");
    tasks.reserve(m.tasks.size());
    for (const auto& t : m.tasks) {
      tasks.push_back(detail::make_task(t, m, frame));
      needs_union |= tasks.back()->needs();
    }
    status.task_count = static_cast<std::uint32_t>(tasks.size());
    path.assign("wait_for_start");
    build_map();
  }

  /// The map and its planner, for the tasks that plan (obstacle course, course 1); sized from the
  /// mission file once, here.
  void build_map() {
    // Only the planner reads the map: without it, no map is kept or fed on the tick.
    if (!m.planning.planner.enabled) return;
    bool plans = false;
    for (const auto& t : m.tasks) {
      plans = plans || t.type == config::TaskType::kObstacleCourse ||
              t.type == config::TaskType::kCourse1;
    }
    if (!plans) return;
    if (auto e = m.planning.validate()) {
      throw std::invalid_argument("planning: " + *e);
    }
    std::vector<core::NavPoint> boundary;
    for (const auto& g : m.planning.boundary) boundary.push_back(frame.to_nav(g));
    std::vector<std::vector<core::NavPoint>> no_go;
    for (const auto& poly : m.planning.no_go) {
      no_go.emplace_back();
      for (const auto& g : poly) no_go.back().push_back(frame.to_nav(g));
    }
    std::vector<core::NavPoint> extent;
    for (const auto& t : m.tasks) {
      for (const auto& g : t.waypoints) extent.push_back(frame.to_nav(g));
      for (const auto& g : t.slips) extent.push_back(frame.to_nav(g));
    }
    map.emplace(m.planning.map, boundary, no_go, extent);
    planner.emplace(*map, m.planning.planner, m.avoidance.half_beam_m);
  }

  // ---- per-tick inputs ----------------------------------------------------------------------

  void update_inputs(const core::Snapshot& s, core::TimeNs now) {
    lidar_fresh = fresh(s.lidar, now, m.lidar_stale_ms) &&
                  !device_down(s, msg::DeviceId::kLidar, s.lidar.stamp_ns);
    imu_fresh =
        fresh(s.imu, now, m.imu_stale_ms) && !device_down(s, msg::DeviceId::kImu, s.imu.stamp_ns);
    gnss_fresh = fresh(s.gnss, now, m.gnss_stale_ms) &&
                 !device_down(s, msg::DeviceId::kGnss, s.gnss.stamp_ns);
    arduino_fresh = fresh(s.arduino, now, m.arduino_stale_ms) &&
                    !device_down(s, msg::DeviceId::kArduino, s.arduino.stamp_ns);
    camera_fresh = fresh(s.camera, now, camera_timeout_ms);

    lidar_new = s.lidar.valid() && s.lidar.sequence != lidar_seq;
    if (lidar_new) {
      lidar_seq = s.lidar.sequence;
      clusterer.process(s.lidar.value, obstacles, profile);
    }
    camera_new = s.camera.valid() && s.camera.sequence != camera_seq;
    if (camera_new) camera_seq = s.camera.sequence;

    if (s.imu.valid() && s.imu.sequence != imu_seq) {
      imu_seq = s.imu.sequence;
      const msg::ImuSample& imu = s.imu.value;
      if (kalman) {
        double mag_heading_deg = imu.heading_deg;
        if (mag_calibrated && imu.has_inertial) {
          // The calibrated field's heading, turned by what the driver adds to the sensor's yaw
          // (declination - mount yaw). Level approximation.
          mag_heading_deg = core::wrap_deg(mag_cal.heading_deg(imu.mag_ut[0], imu.mag_ut[1]) +
                                           imu.heading_deg - imu.yaw_magnetic_deg);
        }
        nav.add_imu(s.imu.stamp_ns, mag_heading_deg, imu.has_inertial, imu.gyro_dps[2],
                    imu.accel_g[0], imu.accel_g[1], imu.roll_deg, imu.pitch_deg);
        if (nav.has_heading()) {
          heading_deg = nav.heading_deg();
          heading_stamp_ns = s.imu.stamp_ns;
          has_heading = true;
        }
      } else if (std::isfinite(imu.heading_deg)) {
        heading_deg = heading_filter.update(imu.heading_deg, s.imu.stamp_ns);
        heading_stamp_ns = s.imu.stamp_ns;
        has_heading = true;
      }
      yaw_rate_dps.reset();
      if (imu.has_inertial && std::isfinite(imu.gyro_dps[2])) {
        yaw_rate_dps = imu.gyro_dps[2] - (kalman ? nav.yaw_rate_bias_dps() : 0.0);
      }
    }
    heading_valid = imu_fresh && has_heading && std::isfinite(s.imu.value.heading_deg);

    if (s.gnss.valid() && s.gnss.sequence != gnss_seq) {
      gnss_seq = s.gnss.sequence;
      fix_usable = s.gnss.value.usable();
      if (fix_usable) {
        const core::NavPoint fix = frame.to_nav({s.gnss.value.lat_deg, s.gnss.value.lon_deg, 0.0});
        std::optional<core::NavPoint> vel;
        if (s.gnss.value.velocity_valid) {
          vel = core::NavPoint{s.gnss.value.vel_north_mps, s.gnss.value.vel_east_mps};
        }
        if (kalman) {
          const bool first = !nav.has_position();
          (void)nav.add_fix(s.gnss.stamp_ns, fix, s.gnss.value);
          if (first && nav.has_position() && !m.calibrate_gps_at_start) {
            // No start calibration: the mission takes the receiver's frame as the waypoints'
            // (RTK on a surveyed base, or points surveyed with this receiver).
            (void)nav.add_bias_measurement({0.0, 0.0}, nav.params().uncalibrated_bias_sigma_m);
          }
          if (s.gnss.value.h_acc_m > 0.0) last_h_acc_m = s.gnss.value.h_acc_m;
        } else {
          position_filter.add_fix(fix, s.gnss.stamp_ns, vel);
        }
        has_fix = true;
        if (top == Top::kWaitForStart && m.calibrate_gps_at_start) {
          // The known start point is the body origin; the antenna sits at its mount behind it,
          // so the fix is compared with the start point moved to the antenna's place.
          // It may also drift off the point with the current while it waits: the fix is taken
          // back by the distance the receiver's velocity says it moved since the first fix.
          core::NavPoint lever;
          core::NavPoint drift;
          if (m.navigation.start_lever_arm) lever = mount_offset();
          if (m.navigation.start_drift) {
            drift = kalman ? nav.travelled_m() : position_filter.travelled_m();
          }
          calibration.add({fix.north_m - lever.north_m - drift.north_m,
                           fix.east_m - lever.east_m - drift.east_m});
        }
      }
    }
    position_valid = gnss_fresh && fix_usable && has_fix;
    if (kalman) {
      nav.predict_to(now);
      if (nav.has_heading()) heading_deg = nav.heading_deg();
      if (nav.has_position()) antenna = nav.position();
    } else if (has_fix) {
      raw_antenna = position_filter.position_at(now);
    }
    update_pose();
    // The map takes each scan at the pose it was taken with (this tick's estimate), after the
    // tick (finish_planning).
    if (map && lidar_new && has_fix && has_heading) queue_scan(s.lidar.value);
  }

  /// The antenna's offset from the body origin in the navigation frame at the current heading.
  [[nodiscard]] core::NavPoint mount_offset() const {
    return core::body_to_nav(core::NavPose{{0.0, 0.0}, heading_deg},
                             {gnss_mount.x_m, gnss_mount.y_m});
  }

  void update_pose() {
    // The filter's antenna is already free of the receiver's bias (a state of its own).
    if (!kalman) antenna = offset.apply(raw_antenna);
    // The body origin is the bow sensor reference; the antenna sits at the gnss mount.
    const core::NavPoint lever = mount_offset();
    pose.position = {antenna.north_m - lever.north_m, antenna.east_m - lever.east_m};
    pose.heading_deg = heading_deg;
  }

  // ---- state paths and transitions ----------------------------------------------------------

  StatePath build_path() const {
    StatePath p;
    switch (top) {
      case Top::kWaitForStart:
        p.assign("wait_for_start");
        return p;
      case Top::kFinished:
        p.assign("finished");
        return p;
      case Top::kActive:
        break;
    }
    const Task& t = *tasks[task_index];
    (void)std::snprintf(p.chars.data(), p.chars.size(), "%s%.*s/%.*s", holding ? "hold/" : "",
                        static_cast<int>(t.name().size()), t.name().data(),
                        static_cast<int>(entered ? t.phase().size() : 7),
                        entered ? t.phase().data() : "refused");
    return p;
  }

  void transition(std::string_view reason, core::TimeNs now, CoreOutput& out) {
    const StatePath next = build_path();
    if (next.view() == path.view()) return;
    TransitionLog& log = out.transitions;
    if (log.count < TransitionLog::kCapacity) {
      Transition& tr = log.entries[log.count++];
      tr.stamp_ns = now;
      tr.from = path;
      tr.to = next;
      tr.reason.assign(reason);
    } else {
      ++log.dropped;
    }
    path = next;
    status.last_transition_reason.assign(reason);
    ++status.transition_count;
  }

  // ---- safety layer -------------------------------------------------------------------------

  /// First reason to hold, or kNone.
  HoldReason hold_check(const core::Snapshot& s, core::TimeNs now, ReasonText& detail) const {
    if (m.require_arduino) {
      if (!arduino_fresh) {
        detail = reason_printf("arduino silent for %.0f ms", age_ms(s.arduino.age_ns(now)));
        return HoldReason::kArduinoStale;
      }
      if (s.arduino.value.estop) {
        detail = reason_printf("arduino reports e-stop");
        return HoldReason::kEstop;
      }
      if (s.arduino.value.mode != msg::ControlMode::kAutonomous) {
        detail = reason_printf("arduino in manual mode");
        return HoldReason::kManualMode;
      }
    }
    if (s.operator_input.valid() && s.operator_input.value.hold) {
      detail = reason_printf("operator hold");
      return HoldReason::kOperator;
    }
    const std::uint8_t needs = tasks[task_index]->needs();
    if ((needs & detail::kNeedLidar) != 0 && !lidar_fresh) {
      detail = reason_printf("lidar stale (no scan for %.0f ms)", age_ms(s.lidar.age_ns(now)));
      return HoldReason::kLidarStale;
    }
    if ((needs & detail::kNeedImu) != 0 && !imu_fresh) {
      detail = reason_printf("imu stale (no sample for %.0f ms)", age_ms(s.imu.age_ns(now)));
      return HoldReason::kImuStale;
    }
    if ((needs & detail::kNeedGnss) != 0) {
      if (!gnss_fresh) {
        detail = reason_printf("gnss stale (no fix for %.0f ms)", age_ms(s.gnss.age_ns(now)));
        return HoldReason::kGnssStale;
      }
      // Mid-task a lost fix is a hold; before entry the task refuses instead.
      if (entered && !fix_usable) {
        detail = reason_printf("gnss reports no usable fix");
        return HoldReason::kGnssStale;
      }
    }
    return HoldReason::kNone;
  }

  /// Empty when every start condition holds, else the first one missing.
  ReasonText start_blocker(const core::Snapshot& s, core::TimeNs now) {
    if (m.require_arduino) {
      if (!arduino_fresh) return reason_printf("arduino silent");
      if (s.arduino.value.estop) return reason_printf("arduino reports e-stop");
      if (s.arduino.value.mode != msg::ControlMode::kAutonomous) {
        return reason_printf("arduino in manual mode");
      }
    }
    if ((needs_union & detail::kNeedLidar) != 0 && !lidar_fresh) return reason_printf("no lidar");
    if ((needs_union & detail::kNeedImu) != 0 && !imu_fresh) return reason_printf("no imu");
    if ((needs_union & detail::kNeedGnss) != 0 && !gnss_fresh) return reason_printf("no gnss");
    if (m.calibrate_gps_at_start) {
      const guidance::CalibrationResult r = calibration.result();
      if (r.status != guidance::CalibrationStatus::kOk) {
        return reason_printf("gps calibration: %s (%zu fixes, spread %.2f m)",
                             guidance::to_string(r.status), r.fix_count, r.spread_m);
      }
    }
    switch (m.start_mode) {
      case config::StartMode::kImmediate:
        break;
      case config::StartMode::kArduinoSwitch:
        if (!arduino_fresh || !s.arduino.value.start_switch) {
          return reason_printf("start switch");
        }
        break;
      case config::StartMode::kControl:
        if (!s.operator_input.valid() || s.operator_input.value.start_count == consumed_start) {
          return reason_printf("start from the control interface");
        }
        break;
    }
    (void)now;
    return {};
  }

  // ---- task level -----------------------------------------------------------------------------

  TaskContext context(const core::Snapshot& s, core::TimeNs now, CoreOutput& out) {
    TaskContext c;
    c.now_ns = now;
    c.position_valid = position_valid;
    c.heading_valid = heading_valid;
    c.pose = pose;
    c.antenna = antenna;
    c.position_cov_valid = kalman && nav.has_position();
    if (c.position_cov_valid) c.position_cov = nav.position_covariance();
    c.lidar_fresh = lidar_fresh && lidar_seq != 0;
    c.lidar_new = lidar_new;
    c.obstacles = &obstacles;
    c.profile = &profile;
    c.camera_fresh = camera_fresh;
    c.camera_new = camera_new;
    c.camera = s.camera.valid() ? &s.camera.value : nullptr;
    c.map = map ? &*map : nullptr;
    c.planner = planner ? &*planner : nullptr;
    c.plan = planner ? &plan_request : nullptr;
    const config::TaskConfig& tc = m.tasks[task_index];
    c.target_colour = tc.target_colour;
    c.target_shape = tc.target_shape;
    if (s.operator_input.valid()) {
      if (s.operator_input.value.target_colour != msg::Colour::kUnknown) {
        c.target_colour = s.operator_input.value.target_colour;
      }
      if (s.operator_input.value.target_shape != msg::Shape::kUnknown) {
        c.target_shape = s.operator_input.value.target_shape;
      }
    }
    c.course_zero_deg = course_zero_deg;
    c.task_elapsed_s = core::ns_to_sec(now - task_start_ns);
    c.viz = &out.viz;
    c.status = &status;
    return c;
  }

  /// Tries to enter the current task; on refusal records why (counted once per new reason).
  bool try_enter(const TaskContext& ctx) {
    const ReasonText refusal = tasks[task_index]->enter(ctx);
    if (refusal.empty()) {
      entered = true;
      status.waiting_for.assign("");
      (void)tasks[task_index]->take_phase_change();
      return true;
    }
    if (refusal.view() != status.waiting_for.view()) ++status.refusal_count;
    status.waiting_for = refusal;
    return false;
  }

  /// Leaves the current task and opens the next (or finishes); tries to enter it at once.
  void next_task(std::string_view why, const core::Snapshot& s, core::TimeNs now, CoreOutput& out,
                 bool finish = false) {
    if (entered) tasks[task_index]->exit();
    entered = false;
    pid.reset();
    if (finish || task_index + 1 >= tasks.size()) {
      top = Top::kFinished;
      status.finished = true;
      finish_ns = now;
      holding = false;
      status.hold_reason = HoldReason::kNone;
      transition(why, now, out);
      return;
    }
    ++task_index;
    task_start_ns = now;
    open_task(why, s, now, out);
  }

  void open_task(std::string_view why, const core::Snapshot& s, core::TimeNs now, CoreOutput& out) {
    ReasonText reason;
    reason.assign(why);
    if (!holding) {
      const TaskContext ctx = context(s, now, out);
      if (!try_enter(ctx)) {
        reason = reason_printf("%.*s; %.*s refused: %s", static_cast<int>(why.size()), why.data(),
                               static_cast<int>(tasks[task_index]->name().size()),
                               tasks[task_index]->name().data(), status.waiting_for.chars.data());
      }
    }
    transition(reason.view(), now, out);
  }

  /// The map and plan work of the last tick, when the caller has not had it done yet: it always
  /// comes before anything of the next tick, so where and when it runs changes no result.
  void finish_planning() {
    if (scan_queued) {
      scan_queued = false;
      map->add_scan(*queued_scan, queued_pose, queued_hull);
    }
    if (plan_request.pending) {
      plan_request.pending = false;
      plan_request.status =
          planner->plan(*map, plan_request.start, plan_request.goal,
                        std::span(plan_request.walls).first(plan_request.wall_count));
      plan_request.made_for = plan_request.owner;
      ++plan_request.made;
    }
  }

  /// Keeps this tick's scan (its returns only) and pose for finish_planning().
  void queue_scan(const msg::LidarScan& scan) {
    msg::LidarScan& q = *queued_scan;
    q.stamp_ns = scan.stamp_ns;
    q.duration_ns = scan.duration_ns;
    q.max_range_m = scan.max_range_m;
    q.min_range_m = scan.min_range_m;
    q.revolution = scan.revolution;
    q.point_count = std::min<std::uint32_t>(scan.point_count, msg::LidarScan::kMaxPoints);
    std::copy_n(scan.points.begin(), q.point_count, q.points.begin());
    queued_pose = pose;
    queued_hull = m.clustering.hull;
    scan_queued = true;
  }

  void step(const core::Snapshot& s, core::TimeNs now, CoreOutput& out) {
    finish_planning();
    out.transitions.count = 0;
    out.transitions.dropped = 0;
    reset_viz(out.viz);
    ++status.tick_count;
    update_inputs(s, now);
    GuidanceRequest req;

    if (top == Top::kWaitForStart) {
      const ReasonText blocker = start_blocker(s, now);
      status.waiting_for = blocker;
      if (blocker.empty()) start(s, now, out);
    }
    if (top == Top::kActive) run_active(s, now, out, req);

    output(s, now, req, out);
    fill_status(now, out);
  }

  void start(const core::Snapshot& s, core::TimeNs now, CoreOutput& out) {
    const char* how = "immediately";
    if (m.start_mode == config::StartMode::kArduinoSwitch) how = "by the start switch";
    if (m.start_mode == config::StartMode::kControl) {
      how = "from the control interface";
      consumed_start = s.operator_input.value.start_count;
    }
    if (m.calibrate_gps_at_start) {
      const guidance::CalibrationResult r = calibration.result();
      if (kalman) {
        // The start point measures the receiver's bias: the mean of the waiting fixes, as
        // uncertain as the boat's placement on the point and the fixes' averaged noise.
        const double place = nav.params().start_placement_sigma_m;
        const double noise = last_h_acc_m / std::sqrt(2.0);
        const double n = static_cast<double>(std::max<std::size_t>(r.fix_count, 1));
        (void)nav.add_bias_measurement({r.offset.north_m, r.offset.east_m},
                                       std::sqrt(place * place + noise * noise / n));
        antenna = nav.position();
      } else {
        offset = r.offset;
      }
      status.gps_calibrated = true;
      update_pose();
    }
    // What was mapped while waiting sits where the uncalibrated fixes put it (this tick's scan
    // too: its pose is from before the calibration).
    if (map) {
      map->clear_evidence();
      scan_queued = false;
    }
    course_zero_deg = m.navigation.course_zero_deg.value_or(heading_deg);
    top = Top::kActive;
    status.started = true;
    start_ns = now;
    task_start_ns = now;
    task_index = 0;
    const ReasonText why = reason_printf("started %s", how);
    open_task(why.view(), s, now, out);
  }

  void run_active(const core::Snapshot& s, core::TimeNs now, CoreOutput& out,
                  GuidanceRequest& req) {
    // Time limit: defined outcome, never a stall.
    const config::TaskConfig& tc = m.tasks[task_index];
    if (core::ns_to_sec(now - task_start_ns) >= tc.time_limit_s) {
      ++status.tasks_timed_out;
      const ReasonText why = reason_printf("%.*s time limit %.0f s reached",
                                           static_cast<int>(tasks[task_index]->name().size()),
                                           tasks[task_index]->name().data(), tc.time_limit_s);
      next_task(why.view(), s, now, out, tc.on_timeout == config::TimeoutOutcome::kFinish);
      if (top != Top::kActive) return;
    }

    ReasonText detail;
    const HoldReason reason = hold_check(s, now, detail);
    if (reason != HoldReason::kNone && !holding) {
      holding = true;
      ++status.hold_count;
      status.hold_reason = reason;
      transition(detail.view(), now, out);
    } else if (reason == HoldReason::kNone && holding) {
      holding = false;
      const ReasonText why = reason_printf(
          "resume: %.*s recovered", static_cast<int>(hold_reason_name(status.hold_reason).size()),
          hold_reason_name(status.hold_reason).data());
      status.hold_reason = HoldReason::kNone;
      pid.reset();
      ramp.reset(0.0);
      transition(why.view(), now, out);
    } else if (holding) {
      status.hold_reason = reason;
    }
    hold_detail = holding ? detail : ReasonText{};
    if (holding) return;

    const TaskContext ctx = context(s, now, out);
    if (!entered) {
      if (try_enter(ctx)) transition("entry allowed", now, out);
      return;
    }
    Task& task = *tasks[task_index];
    const TaskResult r = task.step(ctx, req);
    if (task.take_phase_change()) transition(task.reason().view(), now, out);
    if (r != TaskResult::kRunning) {
      const ReasonText why = r == TaskResult::kDone
                                 ? task.reason()
                                 : reason_printf("failed: %s", task.reason().chars.data());
      const std::optional<msg::LedColour> keep_led = req.led;
      req = GuidanceRequest{};
      req.led = keep_led;
      next_task(why.view(), s, now, out);
    }
  }

  // ---- control pipeline -----------------------------------------------------------------------

  void output(const core::Snapshot& s, core::TimeNs now, const GuidanceRequest& req,
              CoreOutput& out) {
    (void)s;
    if (req.led) led = *req.led;
    const bool drive = top == Top::kActive && entered && !holding && req.steer && heading_valid;
    if (drive) {
      control::HeadingPidInput in;
      in.desired_heading_deg = req.desired_heading_deg;
      in.heading_deg = heading_deg;
      in.stamp_ns = heading_stamp_ns;
      in.yaw_rate_dps = yaw_rate_dps;
      const double turn = pid.update(in);
      double setpoint =
          req.schedule_distance_m ? schedule.scheduled(*req.schedule_distance_m) : req.thrust_frac;
      setpoint *= req.speed_factor;
      const double thrust = ramp.update(std::clamp(setpoint, -1.0, 1.0), now);
      out.command = mixer.mix({turn, thrust}, now);
      out.viz.has_desired_heading = true;
      out.viz.desired_heading_deg = req.desired_heading_deg;
      out.viz.turn_command = turn;
      out.viz.thrust_command = thrust;
    } else {
      // Neutral thrust; the ramp restarts from zero so a resume cannot lurch.
      out.command = mixer.neutral(now);
      pid.reset();
      ramp.reset(0.0);
    }
    out.command.led = led;
  }

  void fill_status(core::TimeNs now, CoreOutput& out) {
    status.state_path = path;
    status.task_index = top == Top::kFinished ? static_cast<std::uint32_t>(tasks.size())
                                              : static_cast<std::uint32_t>(task_index);
    status.holding = holding;
    if (holding) status.waiting_for = hold_detail;
    const core::TimeNs end_ns = top == Top::kFinished ? finish_ns : now;
    status.mission_elapsed_s = status.started ? core::ns_to_sec(end_ns - start_ns) : 0.0;
    status.task_elapsed_s = top == Top::kActive ? core::ns_to_sec(now - task_start_ns) : 0.0;
    status.position_valid = position_valid;
    status.heading_valid = heading_valid;
    if (kalman) {
      status.gps_offset_north_m = nav.gnss_bias_m().north_m;
      status.gps_offset_east_m = nav.gnss_bias_m().east_m;
      status.position_cov_valid = nav.has_position();
      const guidance::PositionCovariance cov = nav.position_covariance();
      status.position_cov_nn_m2 = cov.nn_m2;
      status.position_cov_ne_m2 = cov.ne_m2;
      status.position_cov_ee_m2 = cov.ee_m2;
      status.heading_sigma_deg = nav.has_heading() ? nav.heading_sigma_deg() : 0.0;
      status.mag_disagrees = nav.mag_disagrees();
      status.mag_cog_mean_deg = nav.mag_cog_mean_deg();
      status.gnss_fixes_rejected = nav.counters().fixes_rejected;
    } else {
      status.gps_offset_north_m = offset.north_m;
      status.gps_offset_east_m = offset.east_m;
    }
    status.course_zero_deg = course_zero_deg;
    out.status = status;

    VizFrame& v = out.viz;
    v.stamp_ns = now;
    v.pose_valid = position_valid;
    v.pose = pose;
    v.position_cov_valid = status.position_cov_valid;
    v.position_cov_nn_m2 = status.position_cov_nn_m2;
    v.position_cov_ne_m2 = status.position_cov_ne_m2;
    v.position_cov_ee_m2 = status.position_cov_ee_m2;
    v.heading_valid = heading_valid;
    v.segment_count = std::min<std::uint32_t>(obstacles.count, VizFrame::kMaxSegments);
    for (std::uint32_t i = 0; i < v.segment_count; ++i) {
      const perception::ObstacleSegment& seg = obstacles.segments[i];
      v.segments[i] = {seg.begin, seg.end, seg.kind == perception::ObstacleKind::kWall};
    }
  }

  // Configuration.
  config::MissionConfig m;
  std::uint32_t camera_timeout_ms;
  core::MountTransform gnss_mount;
  core::LocalFrame frame;
  // Engines below the task level.
  control::ActuatorMixer mixer;
  control::HeadingPid pid;
  control::SpeedSchedule schedule;
  control::RateLimiter ramp;
  control::AngleLowPass heading_filter;
  guidance::GpsCalibration calibration;
  guidance::PositionFilter position_filter;  // the documents' raw fixes (position_gain 1)
  bool kalman;                               // else the GNSS + IMU Kalman filter
  guidance::NavFilter nav;
  guidance::MagCalibration mag_cal;  // devices file, `coxswain calibrate mag`
  bool mag_calibrated = false;
  double last_h_acc_m = 0.8;  // the receiver's last hAcc (start calibration noise)
  perception::LidarClusterer clusterer;
  perception::ObstacleList obstacles;
  perception::RangeProfile profile;
  std::optional<guidance::NavMap> map;
  std::optional<guidance::MapPlanner> planner;
  // The work after a tick (finish_planning): the scan for the map and the plan a task asked for.
  std::unique_ptr<msg::LidarScan> queued_scan = std::make_unique<msg::LidarScan>();
  core::NavPose queued_pose;
  perception::HullBox queued_hull;
  bool scan_queued = false;
  PlanRequest plan_request;
  // The camera detectors' tunables: kept for the live view, used by the camera thread.
  perception::VisionParams vision = perception::VisionParams::defaults();
  std::vector<std::unique_ptr<Task>> tasks;
  std::uint8_t needs_union = 0;

  // State machine.
  Top top = Top::kWaitForStart;
  std::size_t task_index = 0;
  bool entered = false;
  bool holding = false;
  ReasonText hold_detail;
  StatePath path;
  MissionStatus status;
  core::TimeNs start_ns = 0;
  core::TimeNs task_start_ns = 0;
  core::TimeNs finish_ns = 0;
  std::uint32_t consumed_start = 0;
  msg::LedColour led = msg::LedColour::kOff;

  // Inputs and the navigation estimate.
  std::uint64_t lidar_seq = 0;
  std::uint64_t imu_seq = 0;
  std::uint64_t gnss_seq = 0;
  std::uint64_t camera_seq = 0;
  bool lidar_fresh = false;
  bool lidar_new = false;
  bool imu_fresh = false;
  bool gnss_fresh = false;
  bool arduino_fresh = false;
  bool camera_fresh = false;
  bool camera_new = false;
  bool has_heading = false;
  bool heading_valid = false;
  double heading_deg = 0.0;
  core::TimeNs heading_stamp_ns = 0;
  std::optional<double> yaw_rate_dps;
  bool has_fix = false;
  bool fix_usable = false;
  bool position_valid = false;
  core::NavPoint raw_antenna;
  core::NavPoint antenna;
  guidance::GpsOffset offset;
  core::NavPose pose;
  double course_zero_deg = 0.0;
};

MissionCore::MissionCore(const config::BoatConfig& boat, const config::MissionConfig& mission,
                         const guidance::MagCalibration& magnetometer)
    : impl_(std::make_unique<Impl>(boat, mission, magnetometer)) {}
MissionCore::~MissionCore() = default;
MissionCore::MissionCore(MissionCore&&) noexcept = default;
MissionCore& MissionCore::operator=(MissionCore&&) noexcept = default;

void MissionCore::step(const core::Snapshot& snapshot, core::TimeNs now_ns, CoreOutput& out) {
  impl_->step(snapshot, now_ns, out);
}

void MissionCore::finish_tick() { impl_->finish_planning(); }

std::string MissionCore::apply_parameters(const TunableParameters& params) {
  Impl& im = *impl_;
  im.finish_planning();  // the last tick's work with the parameters it ran under
  const TunableParameters before = parameters();
  // The named values that changed, each checked against its range; the rest stay as they are.
  TunableParameters next = before;
  for (const TunableSpec& spec : tunable_specs()) {
    const double value = spec.get(params);
    const double was = spec.get(before);
    if (std::bit_cast<std::uint64_t>(value) == std::bit_cast<std::uint64_t>(was)) continue;
    if (std::string e = check_tunable(spec, value); !e.empty()) return e;
    spec.set(next, value);
  }
  if (std::string e = validate_tunables(next); !e.empty()) return e;
  im.m.heading_pid = next.heading_pid;
  im.pid = control::HeadingPid(next.heading_pid);
  if (tunables_differ(before, next, TunableGroup::kClustering)) {
    im.m.clustering = next.clustering;
    // Rebuilding the clusterer allocates its work buffers once: an operator action, not a tick.
    im.clusterer = perception::LidarClusterer(next.clustering);
  }
  if (tunables_differ(before, next, TunableGroup::kAvoidance)) {
    im.m.avoidance = next.avoidance;
    for (const auto& task : im.tasks) task->retune_avoidance(next.avoidance);
  }
  if (tunables_differ(before, next, TunableGroup::kSpeed)) {
    im.m.speed = next.speed;
    im.schedule = control::SpeedSchedule(next.speed);
    const double thrust = im.ramp.value();
    im.ramp = control::RateLimiter({next.speed.rise_per_s, next.speed.fall_per_s});
    im.ramp.reset(thrust);
  }
  im.vision = next.vision;
  return {};
}

std::string MissionCore::set_vision(const perception::VisionParams& vision) {
  if (auto e = vision.validate()) return "vision: " + *e;
  impl_->vision = vision;
  return {};
}

const guidance::NavMap* MissionCore::nav_map() const { return impl_->map ? &*impl_->map : nullptr; }

const guidance::MapPlanner* MissionCore::map_planner() const {
  return impl_->planner ? &*impl_->planner : nullptr;
}

TunableParameters MissionCore::parameters() const {
  return {impl_->m.heading_pid, impl_->m.clustering, impl_->m.avoidance, impl_->m.speed,
          impl_->vision};
}

}  // namespace coxswain::mission
