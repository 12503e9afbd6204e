// SPDX-License-Identifier: Apache-2.0
#include "coxswain/record/foxglove.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>

namespace coxswain::record::foxglove {
namespace {

using nlohmann::json;

constexpr double kDegToRad = std::numbers::pi / 180.0;

// ---- schema building blocks (JSON Schema) ----
json num(std::string_view description) {
  return {{"type", "number"}, {"description", description}};
}
json str(std::string_view description) {
  return {{"type", "string"}, {"description", description}};
}
json integer(std::string_view description, std::int64_t min, std::int64_t max) {
  return {{"type", "integer"}, {"description", description}, {"minimum", min}, {"maximum", max}};
}
json object(std::string_view title, json properties) {
  json required = json::array();
  for (const auto& [k, v] : properties.items()) required.push_back(k);
  return {{"type", "object"},
          {"title", title},
          {"properties", std::move(properties)},
          {"required", std::move(required)}};
}
json array_of(json items, std::string_view description) {
  return {{"type", "array"}, {"description", description}, {"items", std::move(items)}};
}
json time_schema(std::string_view description) {
  json t = object("time", {{"sec", integer("seconds", 0, 4294967295)},
                           {"nsec", integer("nanoseconds", 0, 999999999)}});
  t["description"] = description;
  return t;
}
json duration_schema(std::string_view description) {
  json t = object("duration", {{"sec", integer("seconds", -2147483648, 2147483647)},
                               {"nsec", integer("nanoseconds", 0, 999999999)}});
  t["description"] = description;
  return t;
}
json vector3_schema(std::string_view title) {
  return object(title, {{"x", num("x")}, {"y", num("y")}, {"z", num("z")}});
}
json quaternion_schema() {
  return object("foxglove.Quaternion",
                {{"x", num("x")}, {"y", num("y")}, {"z", num("z")}, {"w", num("w")}});
}
json pose_schema() {
  return object("foxglove.Pose", {{"position", vector3_schema("foxglove.Vector3")},
                                  {"orientation", quaternion_schema()}});
}
json color_schema() {
  return object("foxglove.Color", {{"r", num("red 0-1")},
                                   {"g", num("green 0-1")},
                                   {"b", num("blue 0-1")},
                                   {"a", num("alpha 0-1")}});
}

json location_fix_schema() {
  json cov = array_of(num("m^2"), "ENU position covariance, row-major 3x3");
  cov["minItems"] = 9;
  cov["maxItems"] = 9;
  return object("foxglove.LocationFix",
                {{"timestamp", time_schema("time of the fix")},
                 {"frame_id", str("frame of the sensor")},
                 {"latitude", num("latitude, degrees")},
                 {"longitude", num("longitude, degrees")},
                 {"altitude", num("altitude, metres")},
                 {"position_covariance", cov},
                 {"position_covariance_type",
                  integer("0 unknown, 1 approximated, 2 diagonal known, 3 known", 0, 3)}});
}

json laser_scan_schema() {
  return object("foxglove.LaserScan",
                {{"timestamp", time_schema("time of the scan")},
                 {"frame_id", str("frame of the scan")},
                 {"pose", pose_schema()},
                 {"start_angle", num("bearing of the first range, radians")},
                 {"end_angle", num("bearing of the last range, radians")},
                 {"ranges", array_of(num("metres"), "ranges at equal angular steps")},
                 {"intensities", array_of(num("intensity"), "intensity per range")}});
}

json frame_transform_schema() {
  return object("foxglove.FrameTransform", {{"timestamp", time_schema("time of the transform")},
                                            {"parent_frame_id", str("parent frame")},
                                            {"child_frame_id", str("child frame")},
                                            {"translation", vector3_schema("foxglove.Vector3")},
                                            {"rotation", quaternion_schema()}});
}

json log_schema() {
  return object(
      "foxglove.Log",
      {{"timestamp", time_schema("time of the log line")},
       {"level", integer("0 unknown, 1 debug, 2 info, 3 warning, 4 error, 5 fatal", 0, 5)},
       {"message", str("log message")},
       {"name", str("logger name")},
       {"file", str("source file")},
       {"line", integer("source line", 0, 4294967295)}});
}

json point2_schema() { return object("foxglove.Point2", {{"x", num("x")}, {"y", num("y")}}); }

json compressed_image_schema() {
  json data = str("compressed image data");
  data["contentEncoding"] = "base64";
  return object("foxglove.CompressedImage", {{"timestamp", time_schema("capture time")},
                                             {"frame_id", str("frame of the camera")},
                                             {"data", data},
                                             {"format", str("jpeg")}});
}

json image_annotations_schema() {
  const json circle = object("foxglove.CircleAnnotation", {{"timestamp", time_schema("time")},
                                                           {"position", point2_schema()},
                                                           {"diameter", num("pixels")},
                                                           {"thickness", num("pixels")},
                                                           {"fill_color", color_schema()},
                                                           {"outline_color", color_schema()}});
  const json points = object(
      "foxglove.PointsAnnotation",
      {{"timestamp", time_schema("time")},
       {"type", integer("0 unknown, 1 points, 2 line loop, 3 line strip, 4 line list", 0, 4)},
       {"points", array_of(point2_schema(), "pixels")},
       {"outline_color", color_schema()},
       {"outline_colors", array_of(color_schema(), "per-point colours")},
       {"fill_color", color_schema()},
       {"thickness", num("pixels")}});
  const json text = object("foxglove.TextAnnotation", {{"timestamp", time_schema("time")},
                                                       {"position", point2_schema()},
                                                       {"text", str("text")},
                                                       {"font_size", num("pixels")},
                                                       {"text_color", color_schema()},
                                                       {"background_color", color_schema()}});
  return object("foxglove.ImageAnnotations", {{"circles", array_of(circle, "circles")},
                                              {"points", array_of(points, "points")},
                                              {"texts", array_of(text, "texts")}});
}

json geojson_schema() {
  return object("foxglove.GeoJSON", {{"geojson", str("GeoJSON data encoded as a UTF-8 string")}});
}

json scene_update_schema() {
  const json colors = array_of(color_schema(), "per-vertex colors");
  const json points = array_of(vector3_schema("foxglove.Point3"), "points");
  const json indices = array_of(integer("index", 0, 4294967295), "vertex indices");
  const json arrow = object("foxglove.ArrowPrimitive", {{"pose", pose_schema()},
                                                        {"shaft_length", num("metres")},
                                                        {"shaft_diameter", num("metres")},
                                                        {"head_length", num("metres")},
                                                        {"head_diameter", num("metres")},
                                                        {"color", color_schema()}});
  const json cube = object("foxglove.CubePrimitive", {{"pose", pose_schema()},
                                                      {"size", vector3_schema("foxglove.Vector3")},
                                                      {"color", color_schema()}});
  const json sphere =
      object("foxglove.SpherePrimitive", {{"pose", pose_schema()},
                                          {"size", vector3_schema("foxglove.Vector3")},
                                          {"color", color_schema()}});
  const json cylinder =
      object("foxglove.CylinderPrimitive", {{"pose", pose_schema()},
                                            {"size", vector3_schema("foxglove.Vector3")},
                                            {"bottom_scale", num("ratio")},
                                            {"top_scale", num("ratio")},
                                            {"color", color_schema()}});
  const json line = object("foxglove.LinePrimitive",
                           {{"type", integer("0 line strip, 1 line loop, 2 line list", 0, 2)},
                            {"pose", pose_schema()},
                            {"thickness", num("metres or pixels")},
                            {"scale_invariant", {{"type", "boolean"}}},
                            {"points", points},
                            {"color", color_schema()},
                            {"colors", colors},
                            {"indices", indices}});
  const json triangles = object("foxglove.TriangleListPrimitive", {{"pose", pose_schema()},
                                                                   {"points", points},
                                                                   {"color", color_schema()},
                                                                   {"colors", colors},
                                                                   {"indices", indices}});
  const json text = object("foxglove.TextPrimitive", {{"pose", pose_schema()},
                                                      {"billboard", {{"type", "boolean"}}},
                                                      {"font_size", num("size")},
                                                      {"scale_invariant", {{"type", "boolean"}}},
                                                      {"color", color_schema()},
                                                      {"text", str("text")}});
  const json model = object("foxglove.ModelPrimitive",
                            {{"pose", pose_schema()},
                             {"scale", vector3_schema("foxglove.Vector3")},
                             {"color", color_schema()},
                             {"override_color", {{"type", "boolean"}}},
                             {"url", str("model URL")},
                             {"media_type", str("media type")},
                             {"data", {{"type", "string"}, {"contentEncoding", "base64"}}}});
  const json entity = object(
      "foxglove.SceneEntity",
      {{"timestamp", time_schema("time of the entity")},
       {"frame_id", str("frame")},
       {"id", str("entity id")},
       {"lifetime", duration_schema("0 = forever")},
       {"frame_locked", {{"type", "boolean"}}},
       {"metadata",
        array_of(object("foxglove.KeyValuePair", {{"key", str("key")}, {"value", str("value")}}),
                 "metadata")},
       {"arrows", array_of(arrow, "arrows")},
       {"cubes", array_of(cube, "cubes")},
       {"spheres", array_of(sphere, "spheres")},
       {"cylinders", array_of(cylinder, "cylinders")},
       {"lines", array_of(line, "lines")},
       {"triangles", array_of(triangles, "triangles")},
       {"texts", array_of(text, "texts")},
       {"models", array_of(model, "models")}});
  const json deletion =
      object("foxglove.SceneEntityDeletion", {{"timestamp", time_schema("time of the deletion")},
                                              {"type", integer("0 matching id, 1 all", 0, 1)},
                                              {"id", str("entity id")}});
  return object("foxglove.SceneUpdate", {{"deletions", array_of(deletion, "deletions")},
                                         {"entities", array_of(entity, "entities")}});
}

// ---- message building blocks ----
// Numbers are rounded to what the views can show (a millimetre, a micro-unit of a quaternion):
// JSON prints a double's shortest exact form, so 0.30000000000000004 m would cost 19 bytes
// where "0.3" does; the scene is most of a recording's bytes.
// Dividing by a whole number of steps (exact in a double) gives the double nearest the decimal.
double rounded(double v, double steps_per_unit) {
  return std::round(v * steps_per_unit) / steps_per_unit;
}
double mm(double v_m) { return rounded(v_m, 1e3); }

json stamp(core::TimeNs t_ns) {
  const core::TimeNs t = std::max<core::TimeNs>(t_ns, 0);
  return {{"sec", t / core::kNsPerSec}, {"nsec", t % core::kNsPerSec}};
}
/// A position in metres.
json vec3(double x, double y, double z) { return {{"x", mm(x)}, {"y", mm(y)}, {"z", mm(z)}}; }
/// Rotation about +z by `yaw_rad`.
json yaw_quat(double yaw_rad) {
  constexpr double kSteps = 1e6;
  return {{"x", 0.0},
          {"y", 0.0},
          {"z", rounded(std::sin(yaw_rad / 2.0), kSteps)},
          {"w", rounded(std::cos(yaw_rad / 2.0), kSteps)}};
}
json pose(double x, double y, double z, double yaw_rad) {
  return {{"position", vec3(x, y, z)}, {"orientation", yaw_quat(yaw_rad)}};
}
json color(double r, double g, double b, double a) {
  return {{"r", r}, {"g", g}, {"b", b}, {"a", a}};
}
/// A body-frame point (x forward, y starboard) in the "boat" frame (x forward, y port).
json body_point(double x_m, double y_m) { return vec3(x_m, -y_m, 0.0); }
/// Body-frame bearing (clockwise from the bow) as a "boat"-frame yaw (counterclockwise).
double bearing_to_yaw(double bearing_deg) { return -bearing_deg * kDegToRad; }

json empty_entity(core::TimeNs t_ns, std::string_view id, std::string_view frame = kBoatFrame) {
  return {{"timestamp", stamp(t_ns)},
          {"frame_id", frame},
          {"id", id},
          {"lifetime", {{"sec", 0}, {"nsec", 0}}},
          {"frame_locked", frame == kBoatFrame},
          {"metadata", json::array()},
          {"arrows", json::array()},
          {"cubes", json::array()},
          {"spheres", json::array()},
          {"cylinders", json::array()},
          {"lines", json::array()},
          {"triangles", json::array()},
          {"texts", json::array()},
          {"models", json::array()}};
}

/// A navigation-frame point (north, east) in the "map" frame (east, north, up).
json map_point(const VizPoint& p, double z_m = 0.0) { return vec3(p.east_m, p.north_m, z_m); }

json line_strip(json points, double thickness_m, json colour, double z_m = 0.0) {
  return {{"type", 0},
          {"pose", pose(0.0, 0.0, z_m, 0.0)},
          {"thickness", thickness_m},
          {"scale_invariant", false},
          {"points", std::move(points)},
          {"color", std::move(colour)},
          {"colors", json::array()},
          {"indices", json::array()}};
}

/// Where the boat is going, in the map frame: the goal's arrival circle, the leg, the gate being
/// judged and the planner's path.
json route_entity(core::TimeNs stamp_ns, const TickViz& viz) {
  json route = empty_entity(stamp_ns, "route", kMapFrame);
  if (viz.goal_valid) {
    const double d = 2.0 * std::max(viz.arrival_radius_m, 0.1);
    route["cylinders"].push_back(
        {{"pose", {{"position", map_point(viz.goal, 0.02)}, {"orientation", yaw_quat(0.0)}}},
         {"size", vec3(d, d, 0.04)},
         {"bottom_scale", 1.0},
         {"top_scale", 1.0},
         {"color", color(1.0, 0.85, 0.1, 0.35)}});
    if (viz.leg_valid) {
      route["lines"].push_back(
          line_strip(json::array({map_point(viz.leg_start, 0.02), map_point(viz.goal, 0.02)}), 0.05,
                     color(1.0, 0.85, 0.1, 0.8)));
    }
  }
  if (viz.gate_valid) {
    route["lines"].push_back(
        line_strip(json::array({map_point(viz.gate_port, 0.3), map_point(viz.gate_starboard, 0.3)}),
                   0.1, viz.gate_by_lidar ? color(0.1, 0.9, 0.3, 1.0) : color(0.6, 0.6, 0.6, 0.8)));
  }
  const std::size_t n = std::min<std::size_t>(viz.path_count, TickViz::kMaxPathPoints);
  if (n > 0) {
    json points = json::array();
    for (std::size_t i = 0; i < n; ++i) points.push_back(map_point(viz.path[i], 0.05));
    route["lines"].push_back(line_strip(std::move(points), 0.08, color(0.2, 0.5, 1.0, 1.0)));
  }
  return route;
}

}  // namespace

std::string_view schema_name(Schema schema) {
  switch (schema) {
    case Schema::kLocationFix:
      return "foxglove.LocationFix";
    case Schema::kLaserScan:
      return "foxglove.LaserScan";
    case Schema::kFrameTransform:
      return "foxglove.FrameTransform";
    case Schema::kLog:
      return "foxglove.Log";
    case Schema::kSceneUpdate:
      return "foxglove.SceneUpdate";
    case Schema::kGeoJson:
      return "foxglove.GeoJSON";
    case Schema::kCompressedImage:
      return "foxglove.CompressedImage";
    case Schema::kImageAnnotations:
      return "foxglove.ImageAnnotations";
  }
  return "";
}

std::string schema_json(Schema schema) {
  json s;
  switch (schema) {
    case Schema::kLocationFix:
      s = location_fix_schema();
      break;
    case Schema::kLaserScan:
      s = laser_scan_schema();
      break;
    case Schema::kFrameTransform:
      s = frame_transform_schema();
      break;
    case Schema::kLog:
      s = log_schema();
      break;
    case Schema::kSceneUpdate:
      s = scene_update_schema();
      break;
    case Schema::kGeoJson:
      s = geojson_schema();
      break;
    case Schema::kCompressedImage:
      s = compressed_image_schema();
      break;
    case Schema::kImageAnnotations:
      s = image_annotations_schema();
      break;
  }
  s["$schema"] = "https://json-schema.org/draft/2020-12/schema";
  return s.dump();
}

std::string location_fix_json(const msg::GnssFix& fix) {
  const bool known = fix.h_acc_m >= 0.0 && fix.v_acc_m >= 0.0;
  constexpr double kDegSteps = 1e9;  // about 0.1 mm
  constexpr double kVarianceSteps = 1e6;
  const double h2 = known ? rounded(fix.h_acc_m * fix.h_acc_m, kVarianceSteps) : 0.0;
  const double v2 = known ? rounded(fix.v_acc_m * fix.v_acc_m, kVarianceSteps) : 0.0;
  const json j = {{"timestamp", stamp(fix.stamp_ns)},
                  {"frame_id", "gnss"},
                  {"latitude", rounded(fix.lat_deg, kDegSteps)},
                  {"longitude", rounded(fix.lon_deg, kDegSteps)},
                  {"altitude", mm(fix.height_msl_m)},
                  {"position_covariance", {h2, 0.0, 0.0, 0.0, h2, 0.0, 0.0, 0.0, v2}},
                  {"position_covariance_type", known ? 2 : 0}};
  return j.dump();
}

std::string laser_scan_json(const msg::LidarScan& scan, std::size_t bins) {
  bins = std::max<std::size_t>(bins, 2);
  // "boat" yaw angles in [-pi, pi): bin i covers [start + i*step, start + (i+1)*step).
  const double step = 2.0 * std::numbers::pi / static_cast<double>(bins);
  const double start = -std::numbers::pi;
  std::vector<double> ranges(bins, 0.0);
  // Whole numbers (the lidar's quality is an integer): "47", not "47.0", in every bin's text.
  std::vector<int> intensities(bins, 0);
  const std::size_t n = std::min<std::size_t>(scan.point_count, msg::LidarScan::kMaxPoints);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = scan.points[i];
    if (!(p.range_m > 0.0F) || !std::isfinite(p.range_m)) continue;
    const double yaw = bearing_to_yaw(static_cast<double>(p.bearing_deg));
    auto bin = static_cast<std::int64_t>(std::floor((yaw - start) / step));
    bin = ((bin % static_cast<std::int64_t>(bins)) + static_cast<std::int64_t>(bins)) %
          static_cast<std::int64_t>(bins);
    const auto b = static_cast<std::size_t>(bin);
    if (ranges[b] == 0.0 || static_cast<double>(p.range_m) < ranges[b]) {
      ranges[b] = static_cast<double>(p.range_m);
      intensities[b] = static_cast<int>(p.quality);
    }
  }
  for (double& r : ranges) r = mm(r);
  const json j = {{"timestamp", stamp(scan.stamp_ns)},
                  {"frame_id", kBoatFrame},
                  {"pose", pose(0.0, 0.0, 0.0, 0.0)},
                  {"start_angle", start + step / 2.0},
                  {"end_angle", start + step / 2.0 + step * static_cast<double>(bins - 1)},
                  {"ranges", ranges},
                  {"intensities", intensities}};
  return j.dump();
}

std::string frame_transform_json(core::TimeNs stamp_ns, const TickViz& viz) {
  // map is east-north-up: a heading (clockwise from north) is a yaw of 90 deg - heading.
  const json j = {{"timestamp", stamp(stamp_ns)},
                  {"parent_frame_id", kMapFrame},
                  {"child_frame_id", kBoatFrame},
                  {"translation", vec3(viz.east_m, viz.north_m, 0.0)},
                  {"rotation", yaw_quat((90.0 - viz.heading_deg) * kDegToRad)}};
  return j.dump();
}

std::string log_json(core::TimeNs stamp_ns, LogLevel level, std::string_view name,
                     std::string_view message) {
  const json j = {{"timestamp", stamp(stamp_ns)},
                  {"level", static_cast<int>(level)},
                  {"message", message},
                  {"name", name},
                  {"file", ""},
                  {"line", 0}};
  // Replace invalid UTF-8 (raw device text in a log line) rather than throw.
  return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string scene_update_json(core::TimeNs stamp_ns, const TickViz& viz,
                              std::string_view state_path) {
  json boat = empty_entity(stamp_ns, "boat");
  const double length = static_cast<double>(viz.hull_length_m);
  const double beam = static_cast<double>(viz.hull_beam_m);
  boat["cubes"].push_back({{"pose", pose(-length / 2.0 + 0.1, 0.0, 0.0, 0.0)},
                           {"size", vec3(length, beam, 0.3)},
                           {"color", color(0.9, 0.9, 0.9, 0.8)}});
  boat["texts"].push_back({{"pose", pose(0.0, 0.0, 1.0, 0.0)},
                           {"billboard", true},
                           {"font_size", 14.0},
                           {"scale_invariant", true},
                           {"color", color(1.0, 1.0, 1.0, 1.0)},
                           {"text", state_path}});
  if (viz.target_valid) {
    boat["arrows"].push_back({{"pose", pose(0.0, 0.0, 0.2, bearing_to_yaw(viz.target_bearing_deg))},
                              {"shaft_length", 2.0},
                              {"shaft_diameter", 0.08},
                              {"head_length", 0.4},
                              {"head_diameter", 0.25},
                              {"color", color(0.1, 0.9, 0.2, 1.0)}});
  }
  if (viz.danger_valid) {
    json points = json::array({body_point(0.0, 0.0)});
    double sweep = viz.danger_end_deg - viz.danger_start_deg;
    while (sweep < 0.0) sweep += 360.0;
    const int steps = std::max(2, static_cast<int>(sweep / 5.0));
    for (int i = 0; i <= steps; ++i) {
      const double b = (viz.danger_start_deg + sweep * i / steps) * kDegToRad;
      points.push_back(
          body_point(viz.danger_range_m * std::cos(b), viz.danger_range_m * std::sin(b)));
    }
    points.push_back(body_point(0.0, 0.0));
    boat["lines"].push_back(line_strip(std::move(points), 0.05, color(1.0, 0.2, 0.1, 1.0), 0.1));
  }
  if (viz.cov_valid) {
    // The 95 % confidence ellipse of the position (2 dof: sqrt(chi2) = 2.4477 sigma), drawn in
    // the boat frame: navigation offsets turned by the heading.
    constexpr double kK95 = 2.4477;
    const double mean = 0.5 * (viz.cov_nn_m2 + viz.cov_ee_m2);
    const double half = 0.5 * (viz.cov_nn_m2 - viz.cov_ee_m2);
    const double r = std::sqrt(half * half + viz.cov_ne_m2 * viz.cov_ne_m2);
    const double a = kK95 * std::sqrt(std::max(0.0, mean + r));
    const double b = kK95 * std::sqrt(std::max(0.0, mean - r));
    const double axis = 0.5 * std::atan2(2.0 * viz.cov_ne_m2, viz.cov_nn_m2 - viz.cov_ee_m2);
    const double psi = viz.heading_deg * kDegToRad;
    json points = json::array();
    constexpr int kSteps = 36;
    for (int i = 0; i <= kSteps; ++i) {
      const double t = 2.0 * 3.14159265358979323846 * i / kSteps;
      const double u = a * std::cos(t);
      const double v = b * std::sin(t);
      const double dn = u * std::cos(axis) - v * std::sin(axis);
      const double de = u * std::sin(axis) + v * std::cos(axis);
      points.push_back(body_point(dn * std::cos(psi) + de * std::sin(psi),
                                  -dn * std::sin(psi) + de * std::cos(psi)));
    }
    boat["lines"].push_back(line_strip(std::move(points), 0.04, color(0.2, 0.6, 1.0, 1.0), 0.05));
    char text[96];
    (void)std::snprintf(text, sizeof text, "%.6g %.6g %.6g", viz.cov_nn_m2, viz.cov_ne_m2,
                        viz.cov_ee_m2);
    boat["metadata"].push_back({{"key", "position_cov_nn_ne_ee_m2"}, {"value", text}});
  }
  const std::size_t n = std::min<std::size_t>(viz.obstacle_count, TickViz::kMaxObstacles);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& o = viz.obstacles[i];
    const double d = 2.0 * static_cast<double>(o.radius_m);
    boat["cylinders"].push_back(
        {{"pose",
          {{"position", body_point(static_cast<double>(o.x_m), static_cast<double>(o.y_m))},
           {"orientation", yaw_quat(0.0)}}},
         {"size", vec3(d, d, 0.5)},
         {"bottom_scale", 1.0},
         {"top_scale", 1.0},
         {"color", color(1.0, 0.6, 0.0, 0.8)}});
  }
  json entities = json::array({boat});
  if (viz.goal_valid || viz.gate_valid || viz.path_count > 0) {
    entities.push_back(route_entity(stamp_ns, viz));
  }
  const json j = {{"deletions", json::array()}, {"entities", std::move(entities)}};
  return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

namespace {

json mark_colour(MapMark::Kind kind) {
  return kind == MapMark::Kind::kSlip ? color(0.9, 0.3, 0.9, 0.9) : color(1.0, 0.85, 0.1, 0.9);
}
json area_colour(MapArea::Kind kind) {
  return kind == MapArea::Kind::kNoGo ? color(1.0, 0.2, 0.1, 1.0) : color(0.9, 0.9, 0.9, 1.0);
}
std::string_view mark_kind_name(MapMark::Kind kind) {
  return kind == MapMark::Kind::kSlip ? "slip" : "waypoint";
}
std::string_view area_kind_name(MapArea::Kind kind) {
  return kind == MapArea::Kind::kNoGo ? "no_go" : "boundary";
}
/// GeoJSON positions are [longitude, latitude].
json geo_position(const MapVertex& v) {
  constexpr double kDegSteps = 1e9;
  return json::array({rounded(v.lon_deg, kDegSteps), rounded(v.lat_deg, kDegSteps)});
}

}  // namespace

std::string map_scene_json(core::TimeNs stamp_ns, const MapGeometry& geometry,
                           std::span<const VizPoint> track) {
  json mission = empty_entity(stamp_ns, "mission", kMapFrame);
  for (const MapMark& m : geometry.marks) {
    mission["spheres"].push_back(
        {{"pose", {{"position", map_point(m.at.nav, 0.2)}, {"orientation", yaw_quat(0.0)}}},
         {"size", vec3(0.4, 0.4, 0.4)},
         {"color", mark_colour(m.kind)}});
    mission["texts"].push_back(
        {{"pose", {{"position", map_point(m.at.nav, 0.8)}, {"orientation", yaw_quat(0.0)}}},
         {"billboard", true},
         {"font_size", 12.0},
         {"scale_invariant", true},
         {"color", color(1.0, 1.0, 1.0, 1.0)},
         {"text", m.label}});
  }
  for (const MapArea& a : geometry.areas) {
    if (a.corners.empty()) continue;
    json points = json::array();
    for (const MapVertex& v : a.corners) points.push_back(map_point(v.nav));
    points.push_back(map_point(a.corners.front().nav));
    mission["lines"].push_back(line_strip(std::move(points), 0.1, area_colour(a.kind)));
  }
  json trail = empty_entity(stamp_ns, "track", kMapFrame);
  if (track.size() >= 2) {
    json points = json::array();
    for (const VizPoint& p : track) points.push_back(map_point(p, 0.01));
    trail["lines"].push_back(line_strip(std::move(points), 0.06, color(0.3, 0.8, 1.0, 0.9)));
  }
  const json j = {{"deletions", json::array()},
                  {"entities", json::array({std::move(mission), std::move(trail)})}};
  return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string geojson_json(const MapGeometry& geometry) {
  json features = json::array();
  for (const MapMark& m : geometry.marks) {
    features.push_back({{"type", "Feature"},
                        {"geometry", {{"type", "Point"}, {"coordinates", geo_position(m.at)}}},
                        {"properties", {{"name", m.label}, {"kind", mark_kind_name(m.kind)}}}});
  }
  for (const MapArea& a : geometry.areas) {
    if (a.corners.empty()) continue;
    json ring = json::array();
    for (const MapVertex& v : a.corners) ring.push_back(geo_position(v));
    ring.push_back(geo_position(a.corners.front()));
    const bool no_go = a.kind == MapArea::Kind::kNoGo;
    features.push_back(
        {{"type", "Feature"},
         {"geometry", {{"type", "Polygon"}, {"coordinates", json::array({std::move(ring)})}}},
         {"properties",
          {{"name", a.label},
           {"kind", area_kind_name(a.kind)},
           {"style", {{"color", no_go ? "#ff3319" : "#e6e6e6"}, {"fill", no_go}}}}}});
  }
  const json collection = {{"type", "FeatureCollection"}, {"features", std::move(features)}};
  const json j = {{"geojson", collection.dump(-1, ' ', false, json::error_handler_t::replace)}};
  return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string base64(std::span<const std::uint8_t> bytes) {
  static constexpr char kAlphabet[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const std::uint32_t v = (std::uint32_t{bytes[i]} << 16U) | (std::uint32_t{bytes[i + 1]} << 8U) |
                            std::uint32_t{bytes[i + 2]};
    out += kAlphabet[(v >> 18U) & 63U];
    out += kAlphabet[(v >> 12U) & 63U];
    out += kAlphabet[(v >> 6U) & 63U];
    out += kAlphabet[v & 63U];
  }
  if (const std::size_t rest = bytes.size() - i; rest > 0) {
    std::uint32_t v = std::uint32_t{bytes[i]} << 16U;
    if (rest == 2) v |= std::uint32_t{bytes[i + 1]} << 8U;
    out += kAlphabet[(v >> 18U) & 63U];
    out += kAlphabet[(v >> 12U) & 63U];
    out += rest == 2 ? kAlphabet[(v >> 6U) & 63U] : '=';
    out += '=';
  }
  return out;
}

std::string compressed_image_json(core::TimeNs stamp_ns, std::span<const std::uint8_t> jpeg) {
  const json j = {{"timestamp", stamp(stamp_ns)},
                  {"frame_id", kCameraFrame},
                  {"data", base64(jpeg)},
                  {"format", "jpeg"}};
  return j.dump();
}

namespace {

json target_colour(msg::Colour c) {
  switch (c) {
    case msg::Colour::kRed:
      return color(1.0, 0.1, 0.1, 1.0);
    case msg::Colour::kGreen:
      return color(0.1, 0.9, 0.2, 1.0);
    case msg::Colour::kBlue:
      return color(0.2, 0.4, 1.0, 1.0);
    case msg::Colour::kYellow:
      return color(1.0, 0.9, 0.1, 1.0);
    case msg::Colour::kOrange:
      return color(1.0, 0.55, 0.0, 1.0);
    case msg::Colour::kPurple:
      return color(0.7, 0.2, 0.9, 1.0);
    case msg::Colour::kBlack:
      return color(0.1, 0.1, 0.1, 1.0);
    case msg::Colour::kWhite:
    case msg::Colour::kUnknown:
      break;
  }
  return color(1.0, 1.0, 1.0, 1.0);
}

json pixel(double x, double y) { return {{"x", rounded(x, 10.0)}, {"y", rounded(y, 10.0)}}; }

}  // namespace

std::string image_annotations_json(core::TimeNs stamp_ns, const msg::CameraDetections& detections,
                                   double scale) {
  json boxes = json::array();
  json labels = json::array();
  const std::size_t n =
      std::min<std::size_t>(detections.count, msg::CameraDetections::kMaxDetections);
  for (std::size_t i = 0; i < n; ++i) {
    const msg::Detection& d = detections.detections[i];
    const double cx = static_cast<double>(d.center_x_px) * scale;
    const double cy = static_cast<double>(d.center_y_px) * scale;
    const double hw = 0.5 * static_cast<double>(d.width_px) * scale;
    const double hh = 0.5 * static_cast<double>(d.height_px) * scale;
    const json colour = target_colour(d.colour);
    boxes.push_back({{"timestamp", stamp(stamp_ns)},
                     {"type", 2},  // line loop
                     {"points", json::array({pixel(cx - hw, cy - hh), pixel(cx + hw, cy - hh),
                                             pixel(cx + hw, cy + hh), pixel(cx - hw, cy + hh)})},
                     {"outline_color", colour},
                     {"outline_colors", json::array()},
                     {"fill_color", color(0.0, 0.0, 0.0, 0.0)},
                     {"thickness", 2.0}});
    char text[64];
    (void)std::snprintf(
        text, sizeof text, "%s %s %.2f", std::string(msg::colour_name(d.colour)).c_str(),
        std::string(msg::shape_name(d.shape)).c_str(), static_cast<double>(d.score));
    labels.push_back({{"timestamp", stamp(stamp_ns)},
                      {"position", pixel(cx - hw, std::max(0.0, cy - hh - 4.0))},
                      {"text", text},
                      {"font_size", 14.0},
                      {"text_color", colour},
                      {"background_color", color(0.0, 0.0, 0.0, 0.6)}});
  }
  const json j = {
      {"circles", json::array()}, {"points", std::move(boxes)}, {"texts", std::move(labels)}};
  return j.dump();
}

}  // namespace coxswain::record::foxglove
