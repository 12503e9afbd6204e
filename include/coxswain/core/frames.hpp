// SPDX-License-Identifier: Apache-2.0
#pragma once
// Named frames (docs/conventions.md):
// - navigation frame: origin at a chosen point, X = north, Y = east (metres);
// - body frame: origin at the sensor mount reference (bow), x forward, y starboard (metres);
// - sensor frame: a sensor's own axes, related to the body frame by a MountTransform.
// Because the navigation frame is (north, east) and headings are clockwise from north, the same
// rotation formula serves body->navigation as sensor->body: both frames are "x ahead, y right".

namespace coxswain::core {

/// A point in the navigation frame.
struct NavPoint {
  double north_m = 0.0;
  double east_m = 0.0;
};

/// A point in the body frame.
struct BodyPoint {
  double forward_m = 0.0;
  double starboard_m = 0.0;
};

/// A point in a sensor's own frame (x ahead of the sensor, y to its right).
struct SensorPoint {
  double x_m = 0.0;
  double y_m = 0.0;
};

/// Boat pose in the navigation frame; heading in (-180, 180], 0 = north, clockwise positive.
struct NavPose {
  NavPoint position;
  double heading_deg = 0.0;
};

/// How a sensor sits on the hull: its x axis is turned `yaw_deg` clockwise from the bow, and its
/// origin is at (x_m forward, y_m starboard) of the body origin. From config (boat.yaml).
struct MountTransform {
  double yaw_deg = 0.0;
  double x_m = 0.0;
  double y_m = 0.0;
};

[[nodiscard]] BodyPoint sensor_to_body(const MountTransform& mount, SensorPoint p);
/// Bearing in the body frame (0 = bow, + starboard) of a sensor-frame bearing, in (-180, 180].
[[nodiscard]] double sensor_bearing_to_body_deg(const MountTransform& mount, double bearing_deg);
[[nodiscard]] NavPoint body_to_nav(const NavPose& pose, BodyPoint p);
[[nodiscard]] BodyPoint nav_to_body(const NavPose& pose, NavPoint p);

/// Bearing from `from` to `to` in the navigation frame, (-180, 180]: a plain atan2(east, north).
[[nodiscard]] double bearing_deg(NavPoint from, NavPoint to);
[[nodiscard]] double distance_m(NavPoint a, NavPoint b);

}  // namespace coxswain::core
