// SPDX-License-Identifier: Apache-2.0
// Foxglove JSON channels: every schema is a JSON Schema object with Foxglove's field names, and
// every message we produce validates against its schema (a small validator for the keywords the
// schemas use; the integration test also checks them with ajv).
#include <gtest/gtest.h>

#include <memory>
#include <nlohmann/json.hpp>

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
