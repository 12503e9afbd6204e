// SPDX-License-Identifier: Apache-2.0
// Foxglove JSON channels: every schema is a JSON Schema object with Foxglove's field names, and
// every message we produce validates against its schema (a small validator for the keywords the
// schemas use; the integration test also checks them with ajv).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <span>
#include <string_view>
#include <vector>

#include "coxswain/record/foxglove.hpp"

namespace coxswain::record::foxglove {
namespace {

using nlohmann::json;

/// Validates `v` against `s` for type, properties, required, items, min/maxItems,
/// minimum/maximum. Returns the first problem, empty when valid.
std::string validate(const json& s, const json& v, const std::string& at = "$") {
  const std::string type = s.value("type", "");
  if (type == "object") {
    if (!v.is_object()) return at + ": not an object";
    if (s.contains("required")) {
      for (const auto& r : s.at("required")) {
        if (!v.contains(r.get<std::string>())) return at + ": missing " + r.get<std::string>();
      }
    }
    if (s.contains("properties")) {
      const json& props = s.at("properties");
      for (auto it = props.begin(); it != props.end(); ++it) {
        if (!v.contains(it.key())) continue;
        if (auto e = validate(it.value(), v.at(it.key()), at + "." + it.key()); !e.empty()) {
          return e;
        }
      }
    }
  } else if (type == "array") {
    if (!v.is_array()) return at + ": not an array";
    if (s.contains("minItems") && v.size() < s["minItems"].get<std::size_t>())
      return at + ": short";
    if (s.contains("maxItems") && v.size() > s["maxItems"].get<std::size_t>()) return at + ": long";
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (auto e = validate(s["items"], v[i], at + "[" + std::to_string(i) + "]"); !e.empty())
        return e;
    }
  } else if (type == "number" || type == "integer") {
    if (!v.is_number()) return at + ": not a number";
    if (type == "integer" && !v.is_number_integer()) return at + ": not an integer";
    if (s.contains("minimum") && v.get<double>() < s["minimum"].get<double>())
      return at + ": < min";
    if (s.contains("maximum") && v.get<double>() > s["maximum"].get<double>())
      return at + ": > max";
  } else if (type == "string") {
    if (!v.is_string()) return at + ": not a string";
  } else if (type == "boolean") {
    if (!v.is_boolean()) return at + ": not a boolean";
  }
  return {};
}

json schema(Schema s) { return json::parse(schema_json(s)); }

TEST(Foxglove, SchemasAreObjectsWithFoxgloveFieldNames) {
  const std::vector<std::pair<Schema, std::vector<std::string>>> expected{
      {Schema::kLocationFix,
       {"timestamp", "frame_id", "latitude", "longitude", "altitude", "position_covariance",
        "position_covariance_type"}},
      {Schema::kLaserScan,
       {"timestamp", "frame_id", "pose", "start_angle", "end_angle", "ranges", "intensities"}},
      {Schema::kFrameTransform,
       {"timestamp", "parent_frame_id", "child_frame_id", "translation", "rotation"}},
      {Schema::kLog, {"timestamp", "level", "message", "name", "file", "line"}},
      {Schema::kSceneUpdate, {"deletions", "entities"}},
      {Schema::kGeoJson, {"geojson"}},
      {Schema::kCompressedImage, {"timestamp", "frame_id", "data", "format"}},
      {Schema::kImageAnnotations, {"circles", "points", "texts"}},
  };
  for (const auto& [s, fields] : expected) {
    const json j = schema(s);
    EXPECT_EQ(j["type"], "object") << schema_name(s);
    EXPECT_EQ(j["title"], schema_name(s));
    for (const auto& f : fields)
      EXPECT_TRUE(j["properties"].contains(f)) << schema_name(s) << " " << f;
  }
  const json entity = schema(Schema::kSceneUpdate)["properties"]["entities"]["items"];
  for (const char* f : {"arrows", "cubes", "cylinders", "lines", "texts", "frame_id", "lifetime"}) {
    EXPECT_TRUE(entity["properties"].contains(f)) << f;
  }
}

TEST(Foxglove, MessagesValidateAgainstTheirSchemas) {
  msg::GnssFix fix;
  fix.stamp_ns = 1'500'000'000;
  fix.lat_deg = 35.1;
  fix.lon_deg = 129.0;
  fix.h_acc_m = 0.5;
  fix.v_acc_m = 1.0;
  const json f = json::parse(location_fix_json(fix));
  EXPECT_EQ(validate(schema(Schema::kLocationFix), f), "");
  EXPECT_EQ(f["timestamp"]["sec"], 1);
  EXPECT_EQ(f["timestamp"]["nsec"], 500000000);
  EXPECT_EQ(f["position_covariance_type"], 2);
  EXPECT_DOUBLE_EQ(f["position_covariance"][0].get<double>(), 0.25);

  auto scan = std::make_unique<msg::LidarScan>();
  scan->stamp_ns = 10;
  ASSERT_TRUE(scan->push({0.0F, 5.0F, 40, 0}));   // dead ahead
  ASSERT_TRUE(scan->push({90.5F, 3.0F, 40, 0}));  // starboard beam
  ASSERT_TRUE(scan->push({90.7F, 2.0F, 40, 0}));  // same bin: nearest wins
  ASSERT_TRUE(scan->push({-45.0F, 0.0F, 0, 0}));  // no return
  const json l = json::parse(laser_scan_json(*scan, 360));
  EXPECT_EQ(validate(schema(Schema::kLaserScan), l), "");
  ASSERT_EQ(l["ranges"].size(), 360U);
  // Bin of angle a: (a - start)/step with start = -pi, step = 1 deg. Bow = angle 0 -> bin 180;
  // starboard (bearing +90.5) = angle -90.5 deg in the forward-left-up frame -> bin 89.
  EXPECT_DOUBLE_EQ(l["ranges"][180].get<double>(), 5.0);
  EXPECT_DOUBLE_EQ(l["ranges"][89].get<double>(), 2.0);
  int returns = 0;
  for (const auto& r : l["ranges"]) returns += r.get<double>() > 0.0 ? 1 : 0;
  EXPECT_EQ(returns, 2);

  TickViz viz;
  viz.pose_valid = true;
  viz.north_m = 10.0;
  viz.east_m = 5.0;
  viz.heading_deg = 90.0;  // east: yaw 0 in the east-north-up map
  viz.target_valid = true;
  viz.target_bearing_deg = 20.0;
  viz.danger_valid = true;
  viz.danger_start_deg = -30.0;
  viz.danger_end_deg = 30.0;
  viz.danger_range_m = 4.0;
  viz.obstacle_count = 2;
  viz.obstacles[0] = {3.0F, 1.0F, 0.5F};
  viz.obstacles[1] = {5.0F, -2.0F, 0.3F};
  const json t = json::parse(frame_transform_json(20, viz));
  EXPECT_EQ(validate(schema(Schema::kFrameTransform), t), "");
  EXPECT_DOUBLE_EQ(t["translation"]["x"].get<double>(), 5.0);
  EXPECT_DOUBLE_EQ(t["translation"]["y"].get<double>(), 10.0);
  EXPECT_NEAR(t["rotation"]["w"].get<double>(), 1.0, 1e-12);

  const json s = json::parse(scene_update_json(20, viz, "ACTIVE:HOPPING"));
  EXPECT_EQ(validate(schema(Schema::kSceneUpdate), s), "");
  const json& e = s["entities"][0];
  EXPECT_EQ(e["cylinders"].size(), 2U);
  EXPECT_DOUBLE_EQ(e["cylinders"][0]["pose"]["position"]["y"].get<double>(), -1.0);  // starboard
  EXPECT_EQ(e["arrows"].size(), 1U);
  EXPECT_EQ(e["lines"].size(), 1U);
  EXPECT_EQ(e["texts"][0]["text"], "ACTIVE:HOPPING");

  const json g = json::parse(log_json(30, LogLevel::kWarning, "coxswain", "bad \xff byte"));
  EXPECT_EQ(validate(schema(Schema::kLog), g), "");
  EXPECT_EQ(g["level"], 3);
}

TEST(Foxglove, NumbersAreRoundedToWhatTheViewsShow) {
  TickViz viz;
  viz.pose_valid = true;
  viz.north_m = 0.1 + 0.2;  // 0.30000000000000004
  viz.east_m = 1.23456789;
  viz.heading_deg = 33.3;
  const std::string t = frame_transform_json(0, viz);
  const json j = json::parse(t);
  EXPECT_EQ(j["translation"]["y"].dump(), "0.3");
  EXPECT_EQ(j["translation"]["x"].dump(), "1.235");
  EXPECT_LE(j["rotation"]["z"].dump().size(), 9U);  // at most six decimals
  EXPECT_NEAR(j["rotation"]["z"].get<double>(), std::sin((90.0 - 33.3) * std::numbers::pi / 360.0),
              1e-6);
}

TEST(Foxglove, RouteIsDrawnInTheMapFrame) {
  TickViz viz;
  viz.pose_valid = true;
  EXPECT_EQ(json::parse(scene_update_json(0, viz, "S"))["entities"].size(), 1U);  // no route
  viz.goal_valid = true;
  viz.goal = {20.0, 10.0};
  viz.arrival_radius_m = 1.5;
  viz.leg_valid = true;
  viz.leg_start = {0.0, 0.0};
  viz.gate_valid = true;
  viz.gate_by_lidar = true;
  viz.gate_port = {20.0, 8.5};
  viz.gate_starboard = {20.0, 11.5};
  viz.path_count = 3;
  viz.path[0] = {0.0, 0.0};
  viz.path[1] = {10.0, 2.0};
  viz.path[2] = {20.0, 10.0};
  const json s = json::parse(scene_update_json(0, viz, "S"));
  EXPECT_EQ(validate(schema(Schema::kSceneUpdate), s), "");
  ASSERT_EQ(s["entities"].size(), 2U);
  const json& route = s["entities"][1];
  EXPECT_EQ(route["id"], "route");
  EXPECT_EQ(route["frame_id"], "map");
  EXPECT_FALSE(route["frame_locked"].get<bool>());
  ASSERT_EQ(route["cylinders"].size(), 1U);  // the goal's arrival circle
  EXPECT_DOUBLE_EQ(route["cylinders"][0]["size"]["x"].get<double>(), 3.0);
  // map is east-north-up: x east, y north.
  EXPECT_DOUBLE_EQ(route["cylinders"][0]["pose"]["position"]["x"].get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(route["cylinders"][0]["pose"]["position"]["y"].get<double>(), 20.0);
  ASSERT_EQ(route["lines"].size(), 3U);  // leg, gate, path
  EXPECT_EQ(route["lines"][0]["points"].size(), 2U);
  EXPECT_DOUBLE_EQ(route["lines"][1]["points"][0]["x"].get<double>(), 8.5);
  EXPECT_EQ(route["lines"][2]["points"].size(), 3U);
  EXPECT_DOUBLE_EQ(route["lines"][2]["points"][1]["x"].get<double>(), 2.0);
  EXPECT_DOUBLE_EQ(route["lines"][2]["points"][1]["y"].get<double>(), 10.0);
}

MapGeometry sample_geometry() {
  MapGeometry g;
  g.marks.push_back({MapMark::Kind::kWaypoint, "hopping 1", {35.1, 129.0, {0.0, 0.0}}});
  g.marks.push_back({MapMark::Kind::kSlip, "docking slip 1", {35.1001, 129.0002, {11.1, 18.2}}});
  g.areas.push_back({MapArea::Kind::kBoundary,
                     "boundary",
                     {{35.0999, 128.9999, {-11.1, -9.1}},
                      {35.0999, 129.0003, {-11.1, 27.3}},
                      {35.1002, 129.0003, {22.2, 27.3}}}});
  g.areas.push_back({MapArea::Kind::kNoGo, "no-go 1", {}});  // nothing to draw
  return g;
}

TEST(Foxglove, MapSceneHoldsTheMissionAndTheTrack) {
  const MapGeometry g = sample_geometry();
  const std::vector<VizPoint> track{{0.0, 0.0}, {1.0, 1.0}, {2.0, 3.0}};
  const json s = json::parse(map_scene_json(7, g, track));
  EXPECT_EQ(validate(schema(Schema::kSceneUpdate), s), "");
  ASSERT_EQ(s["entities"].size(), 2U);
  const json& mission = s["entities"][0];
  EXPECT_EQ(mission["id"], "mission");
  EXPECT_EQ(mission["frame_id"], "map");
  ASSERT_EQ(mission["spheres"].size(), 2U);
  EXPECT_DOUBLE_EQ(mission["spheres"][1]["pose"]["position"]["x"].get<double>(), 18.2);  // east
  EXPECT_EQ(mission["texts"][1]["text"], "docking slip 1");
  ASSERT_EQ(mission["lines"].size(), 1U);  // the empty no-go area is left out
  const json& ring = mission["lines"][0]["points"];
  ASSERT_EQ(ring.size(), 4U);  // closed
  EXPECT_EQ(ring[0], ring[3]);
  const json& trail = s["entities"][1];
  EXPECT_EQ(trail["id"], "track");
  ASSERT_EQ(trail["lines"].size(), 1U);
  EXPECT_EQ(trail["lines"][0]["points"].size(), 3U);
  EXPECT_DOUBLE_EQ(trail["lines"][0]["points"][2]["x"].get<double>(), 3.0);
  // A single point is no line yet.
  const std::vector<VizPoint> one{{0.0, 0.0}};
  EXPECT_TRUE(json::parse(map_scene_json(7, g, one))["entities"][1]["lines"].empty());
}

TEST(Foxglove, GeoJsonPlacesTheMissionOnTheGlobe) {
  const json j = json::parse(geojson_json(sample_geometry()));
  EXPECT_EQ(validate(schema(Schema::kGeoJson), j), "");
  const json c = json::parse(j["geojson"].get<std::string>());
  EXPECT_EQ(c["type"], "FeatureCollection");
  ASSERT_EQ(c["features"].size(), 3U);
  const json& wp = c["features"][0];
  EXPECT_EQ(wp["geometry"]["type"], "Point");
  // GeoJSON positions are [longitude, latitude].
  EXPECT_DOUBLE_EQ(wp["geometry"]["coordinates"][0].get<double>(), 129.0);
  EXPECT_DOUBLE_EQ(wp["geometry"]["coordinates"][1].get<double>(), 35.1);
  EXPECT_EQ(wp["properties"]["name"], "hopping 1");
  EXPECT_EQ(c["features"][1]["properties"]["kind"], "slip");
  const json& area = c["features"][2];
  EXPECT_EQ(area["geometry"]["type"], "Polygon");
  const json& ring = area["geometry"]["coordinates"][0];
  ASSERT_EQ(ring.size(), 4U);
  EXPECT_EQ(ring.front(), ring.back());
  EXPECT_DOUBLE_EQ(ring[1][0].get<double>(), 129.0003);
  EXPECT_EQ(area["properties"]["kind"], "boundary");
  // Nothing at all: an empty collection, still valid.
  const json none = json::parse(json::parse(geojson_json({}))["geojson"].get<std::string>());
  EXPECT_TRUE(none["features"].empty());
}

TEST(Foxglove, Base64IsRfc4648) {
  const auto b64 = [](std::string_view text) {
    return base64(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(text.data()),
                                                text.size()));
  };
  // The test vectors of RFC 4648, section 10.
  EXPECT_EQ(b64(""), "");
  EXPECT_EQ(b64("f"), "Zg==");
  EXPECT_EQ(b64("fo"), "Zm8=");
  EXPECT_EQ(b64("foo"), "Zm9v");
  EXPECT_EQ(b64("foob"), "Zm9vYg==");
  EXPECT_EQ(b64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(b64("foobar"), "Zm9vYmFy");
  const std::vector<std::uint8_t> high{0xFF, 0xFE, 0xFD};
  EXPECT_EQ(base64(high), "//79");
}

TEST(Foxglove, CameraImageAndItsDetections) {
  const std::vector<std::uint8_t> jpeg{0xFF, 0xD8, 0xFF, 0xE0, 0x00};
  const json image = json::parse(compressed_image_json(3'000'000'001, jpeg));
  EXPECT_EQ(validate(schema(Schema::kCompressedImage), image), "");
  EXPECT_EQ(image["format"], "jpeg");
  EXPECT_EQ(image["frame_id"], "camera");
  EXPECT_EQ(image["data"], base64(jpeg));
  EXPECT_EQ(image["timestamp"]["sec"], 3);

  msg::CameraDetections d;
  d.image_width_px = 1280;
  d.image_height_px = 960;
  ASSERT_TRUE(d.push({msg::Colour::kRed, msg::Shape::kTriangle, 0.0F, 640.0F, 480.0F, 100.0F, 60.0F,
                      3000.0F, 0.9F}));
  ASSERT_TRUE(d.push(
      {msg::Colour::kGreen, msg::Shape::kBuoy, 0.0F, 20.0F, 10.0F, 10.0F, 10.0F, 100.0F, 0.5F}));
  // The recorded image is half the detector's width: boxes at half the pixels.
  const json a = json::parse(image_annotations_json(3'000'000'001, d, 0.5));
  EXPECT_EQ(validate(schema(Schema::kImageAnnotations), a), "");
  ASSERT_EQ(a["points"].size(), 2U);
  const json& box = a["points"][0];
  EXPECT_EQ(box["type"], 2);  // a closed loop
  ASSERT_EQ(box["points"].size(), 4U);
  EXPECT_DOUBLE_EQ(box["points"][0]["x"].get<double>(), 295.0);  // (640 - 50) / 2
  EXPECT_DOUBLE_EQ(box["points"][0]["y"].get<double>(), 225.0);  // (480 - 30) / 2
  EXPECT_DOUBLE_EQ(box["points"][2]["x"].get<double>(), 345.0);
  EXPECT_DOUBLE_EQ(box["outline_color"]["r"].get<double>(), 1.0);  // red
  ASSERT_EQ(a["texts"].size(), 2U);
  EXPECT_EQ(a["texts"][0]["text"], "red triangle 0.90");
  EXPECT_EQ(a["texts"][1]["text"], "green buoy 0.50");
  EXPECT_GE(a["texts"][1]["position"]["y"].get<double>(), 0.0);  // kept on the image
  // No detections: empty lists, still valid.
  const json none = json::parse(image_annotations_json(0, msg::CameraDetections{}, 1.0));
  EXPECT_EQ(validate(schema(Schema::kImageAnnotations), none), "");
  EXPECT_TRUE(none["points"].empty());
}

TEST(Foxglove, ValidatorRejectsWrongMessages) {
  // The validator used above can fail: a message missing a field or with a wrong type.
  json f = json::parse(location_fix_json(msg::GnssFix{}));
  f.erase("latitude");
  EXPECT_NE(validate(schema(Schema::kLocationFix), f), "");
  json g = json::parse(log_json(0, LogLevel::kInfo, "a", "b"));
  g["level"] = 9;
  EXPECT_NE(validate(schema(Schema::kLog), g), "");
}

}  // namespace
}  // namespace coxswain::record::foxglove
