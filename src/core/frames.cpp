// SPDX-License-Identifier: Apache-2.0
#include "coxswain/core/frames.hpp"

#include <cmath>

#include "coxswain/core/angles.hpp"

namespace coxswain::core {
namespace {

// Rotates a right-handed-about-down "x ahead, y right" vector by `yaw_deg` clockwise.
struct Rotated {
  double x;
  double y;
};
Rotated rotate_cw(double x, double y, double yaw_deg) {
  const double c = std::cos(deg_to_rad(yaw_deg));
  const double s = std::sin(deg_to_rad(yaw_deg));
  return {c * x - s * y, s * x + c * y};
}

}  // namespace

BodyPoint sensor_to_body(const MountTransform& mount, SensorPoint p) {
  const Rotated r = rotate_cw(p.x_m, p.y_m, mount.yaw_deg);
  return {r.x + mount.x_m, r.y + mount.y_m};
}

double sensor_bearing_to_body_deg(const MountTransform& mount, double bearing_deg) {
  return wrap_deg(bearing_deg + mount.yaw_deg);
}

NavPoint body_to_nav(const NavPose& pose, BodyPoint p) {
  const Rotated r = rotate_cw(p.forward_m, p.starboard_m, pose.heading_deg);
  return {pose.position.north_m + r.x, pose.position.east_m + r.y};
}

BodyPoint nav_to_body(const NavPose& pose, NavPoint p) {
  const Rotated r = rotate_cw(p.north_m - pose.position.north_m, p.east_m - pose.position.east_m,
                              -pose.heading_deg);
  return {r.x, r.y};
}

double bearing_deg(NavPoint from, NavPoint to) {
  return wrap_deg(rad_to_deg(std::atan2(to.east_m - from.east_m, to.north_m - from.north_m)));
}

double distance_m(NavPoint a, NavPoint b) {
  return std::hypot(b.north_m - a.north_m, b.east_m - a.east_m);
}

}  // namespace coxswain::core
