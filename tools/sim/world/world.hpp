// SPDX-License-Identifier: Apache-2.0
#pragma once
// The simulated world as plain data: what a course file (config/courses/*.yaml) describes once it
// is loaded and validated. Everything is in the navigation frame of the course's geodetic origin
// (X north, Y east, metres; headings 0 = north, clockwise, degrees). The sensors ray-cast and
// render against this; scoring judges the boat against it. Immutable once built, so it may be
// shared read-only between threads (batch runs).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "coxswain/core/frames.hpp"
#include "coxswain/core/geodesy.hpp"
#include "coxswain/msg/camera_detections.hpp"

namespace coxswain::sim::world {

/// A wall, pool edge or pier: a polyline of at least two points, solid on both sides.
struct Wall {
  std::vector<core::NavPoint> points;
  double height_m = 0.5;  // above the water, for the camera
};

/// A floating buoy: a vertical cylinder (lidar, collisions) drawn as a ball/cone by the camera.
struct Buoy {
  core::NavPoint center;
  double radius_m = 0.25;
  double height_m = 0.6;
  msg::Colour colour = msg::Colour::kOrange;
};

/// A gate: the boat passes it by crossing the segment left -> right in the course direction.
struct Gate {
  std::string name;
  core::NavPoint left;  // as seen by a boat passing in the intended direction
  core::NavPoint right;
};

/// A placard on a dock: a flat shape of `size_m` (width of the shape) centred `height_m` above
/// the water at `center`, facing `facing_deg` (the direction its front looks at).
struct Marker {
  msg::Colour colour = msg::Colour::kRed;
  msg::Shape shape = msg::Shape::kTriangle;
  double size_m = 0.6;
  double height_m = 1.0;
  core::NavPoint center;
  double facing_deg = 0.0;
};

/// One docking slip: its side and back walls, the marker above its back, and the point in the
/// middle of its mouth with the direction into the slip.
struct Dock {
  std::string name;
  std::vector<Wall> walls;
  Marker marker;
  core::NavPoint entrance;
  double entry_heading_deg = 0.0;  // heading of a boat driving straight in
  double depth_m = 2.0;            // entrance to back wall
  double width_m = 1.6;            // between the side walls
  // Side walls (fingers) this wide, outward of width_m. Floating docks are pontoons half a metre
  // or so across; a zero-width finger is invisible to a lidar looking straight down the slip.
  double finger_width_m = 0.3;
};

/// A named waypoint (arrival judged by the 2022 rule: half the hull inside radius_m).
struct Waypoint {
  std::string name;
  core::NavPoint position;
  double radius_m = 2.0;
};

/// A course region of a multi-course mission (2026: course 1, 2, 3) with its time limit.
struct Region {
  std::string name;
  std::vector<core::NavPoint> polygon;  // closed implicitly
  double time_limit_s = 0.0;            // 0 = none
};

/// The venue's sensor conditions (a course file's `conditions:` block). Every value given
/// overrides the simulated sensors' configuration for runs on this course, whatever the sensors
/// file or the batch's drawn disturbances say; a value not given leaves theirs.
struct SensorConditions {
  // GNSS: the bias's constant part (magnitude, bearing it points to), its wander (drift:
  // stationary sigma per axis and correlation time), the cap on its magnitude, the white noise.
  std::optional<double> gnss_bias_mean_m;
  std::optional<double> gnss_bias_direction_deg;
  std::optional<double> gnss_bias_wander_sigma_m;
  std::optional<double> gnss_bias_tau_s;
  std::optional<double> gnss_bias_max_m;
  std::optional<double> gnss_noise_sigma_m;
  // Camera: the venue's look (the sensors' camera.venue names: pool, harbour, overcast, low_sun),
  // sun glare / over-exposure, blur and pixel noise.
  std::optional<std::string> camera_venue;
  std::optional<bool> camera_glare;
  std::optional<double> camera_glare_gain;
  std::optional<double> camera_glare_saturation_loss;
  std::optional<double> camera_sun_bearing_deg;
  std::optional<double> camera_sun_elevation_deg;
  std::optional<double> camera_sun_blob_radius_px;
  std::optional<int> camera_blur_kernel_px;
  std::optional<double> camera_noise_sigma;

  [[nodiscard]] bool any() const {
    return gnss_bias_mean_m || gnss_bias_direction_deg || gnss_bias_wander_sigma_m ||
           gnss_bias_tau_s || gnss_bias_max_m || gnss_noise_sigma_m || camera_venue ||
           camera_glare || camera_glare_gain || camera_glare_saturation_loss ||
           camera_sun_bearing_deg || camera_sun_elevation_deg || camera_sun_blob_radius_px ||
           camera_blur_kernel_px || camera_noise_sigma;
  }
};

enum class CourseKind : std::uint8_t { kHopping = 0, kObstacle, kDocking, kKaboat2026 };

/// Everything in one course file, loaded and validated.
struct World {
  std::string name;
  std::string file;  // where it was loaded from ("" when generated)
  CourseKind kind = CourseKind::kHopping;
  core::GeoPoint origin;  // navigation frame origin
  core::NavPose start;    // where the boat starts
  std::vector<Wall> walls;
  std::vector<Buoy> buoys;
  std::vector<Gate> gates;
  std::vector<Dock> docks;
  std::vector<Waypoint> waypoints;
  std::vector<Region> regions;
  /// The dock marker the contest draws for this run (docking): colour and shape.
  msg::Colour target_colour = msg::Colour::kUnknown;
  msg::Shape target_shape = msg::Shape::kUnknown;
  double declination_deg = 0.0;  // magnetic declination at the site, east positive
  SensorConditions conditions;   // the venue's GNSS and camera conditions
};

}  // namespace coxswain::sim::world
