// SPDX-License-Identifier: Apache-2.0
#pragma once
// The one table of every parameter struct (see core/param_table.hpp): the engines' parameters,
// the mission's own settings, the boat and the devices. `param_table<S>()` is the table of S;
// `for_each_mission_section` and friends say where each struct sits in its file. Pure data, no
// file format: the core's live tuning and the YAML loader both walk these.
#include <span>
#include <string_view>

#include "coxswain/config/boat_config.hpp"
#include "coxswain/config/devices_config.hpp"
#include "coxswain/config/mission_config.hpp"
#include "coxswain/core/param_table.hpp"
#include "coxswain/perception/vision_params.hpp"

namespace coxswain::config {

template <class S>
std::span<const core::ParamSpec<S>> param_table();

// Engines.
template <>
std::span<const core::ParamSpec<control::HeadingPidParams>> param_table();
template <>
std::span<const core::ParamSpec<control::SpeedScheduleParams>> param_table();
template <>
std::span<const core::ParamSpec<guidance::AvoidanceParams>> param_table();
template <>
std::span<const core::ParamSpec<guidance::WaypointFollowerParams>> param_table();
template <>
std::span<const core::ParamSpec<guidance::GpsCalibrationParams>> param_table();
template <>
std::span<const core::ParamSpec<perception::LidarClusterParams>> param_table();
template <>
std::span<const core::ParamSpec<perception::MarkerVoteParams>> param_table();
// The camera detectors (the vision file: the top level and each entry of its `colours` list).
template <>
std::span<const core::ParamSpec<perception::VisionParams>> param_table();
template <>
std::span<const core::ParamSpec<perception::ColourRange>> param_table();
// Mission settings.
template <>
std::span<const core::ParamSpec<MissionConfig>> param_table();
template <>
std::span<const core::ParamSpec<NavigationConfig>> param_table();
template <>
std::span<const core::ParamSpec<Course1Config>> param_table();
template <>
std::span<const core::ParamSpec<Course2Config>> param_table();
template <>
std::span<const core::ParamSpec<DockingConfig>> param_table();
template <>
std::span<const core::ParamSpec<guidance::PlanningConfig>> param_table();
// Boat.
template <>
std::span<const core::ParamSpec<BoatConfig>> param_table();
// Devices.
template <>
std::span<const core::ParamSpec<LidarDeviceConfig>> param_table();
template <>
std::span<const core::ParamSpec<ImuDeviceConfig>> param_table();
template <>
std::span<const core::ParamSpec<GnssDeviceConfig>> param_table();
template <>
std::span<const core::ParamSpec<ArduinoDeviceConfig>> param_table();
template <>
std::span<const core::ParamSpec<CameraDeviceConfig>> param_table();
template <>
std::span<const core::ParamSpec<LiveConfig>> param_table();

/// Calls `f(section_key, member)` for every table-driven section of a mission file, in file
/// order ("" = the file's top level). `M` is MissionConfig or const MissionConfig.
template <class M, class F>
void for_each_mission_section(M& m, F&& f) {
  f(std::string_view{}, m);
  f(std::string_view{"navigation"}, m.navigation);
  f(std::string_view{"gps_calibration"}, m.gps_calibration);
  f(std::string_view{"waypoints"}, m.waypoints);
  f(std::string_view{"heading_pid"}, m.heading_pid);
  f(std::string_view{"speed"}, m.speed);
  f(std::string_view{"avoidance"}, m.avoidance);
  f(std::string_view{"clustering"}, m.clustering);
  f(std::string_view{"vision_vote"}, m.vision_vote);
  f(std::string_view{"course1"}, m.course1);
  f(std::string_view{"course2"}, m.course2);
  f(std::string_view{"docking"}, m.docking);
  f(std::string_view{"planning"}, m.planning);
}

/// The same for a devices file.
template <class D, class F>
void for_each_devices_section(D& d, F&& f) {
  f(std::string_view{"lidar"}, d.lidar);
  f(std::string_view{"imu"}, d.imu);
  f(std::string_view{"gnss"}, d.gnss);
  f(std::string_view{"arduino"}, d.arduino);
  f(std::string_view{"camera"}, d.camera);
  f(std::string_view{"live"}, d.live);
}

/// Names of the colours a file may use (course buoys, targets).
[[nodiscard]] std::span<const core::ParamChoice> colour_choices();

}  // namespace coxswain::config
