// SPDX-License-Identifier: Apache-2.0
#pragma once
// Foxglove well-known message schemas (JSON Schema, message encoding "json") and converters from
// our messages, so a recording opens in Foxglove/Lichtblick with the boat, its track, the lidar
// and the avoidance picture. Frames: "map" is east-north-up (x east, y north) anchored at the
// navigation origin; "boat" is the body frame turned forward-left-up (x bow, y port, z up) because
// viewers assume right-handed z-up frames; "gnss" for fixes. Allocates: writer thread only.
// Pure functions; thread-safe.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "coxswain/core/time.hpp"
#include "coxswain/msg/camera_detections.hpp"
#include "coxswain/msg/gnss_fix.hpp"
#include "coxswain/msg/lidar_scan.hpp"
#include "coxswain/record/map_geometry.hpp"
#include "coxswain/record/tick_record.hpp"

namespace coxswain::record::foxglove {

enum class Schema : std::uint8_t {
  kLocationFix,
  kLaserScan,
  kFrameTransform,
  kLog,
  kSceneUpdate,
  kGeoJson,
  kCompressedImage,
  kImageAnnotations,
};

inline constexpr std::string_view kSchemaEncoding = "jsonschema";
inline constexpr std::string_view kMessageEncoding = "json";
inline constexpr std::string_view kMapFrame = "map";
inline constexpr std::string_view kBoatFrame = "boat";

/// "foxglove.LocationFix", ...
[[nodiscard]] std::string_view schema_name(Schema schema);
/// The JSON Schema text (draft 2020-12) with Foxglove's field names.
[[nodiscard]] std::string schema_json(Schema schema);

/// Foxglove log levels.
enum class LogLevel : std::uint8_t { kUnknown = 0, kDebug, kInfo, kWarning, kError, kFatal };

[[nodiscard]] std::string location_fix_json(const msg::GnssFix& fix);
/// The scan resampled into `bins` equal angular bins (nearest return per bin, 0 = none).
[[nodiscard]] std::string laser_scan_json(const msg::LidarScan& scan, std::size_t bins = 720);
[[nodiscard]] std::string frame_transform_json(core::TimeNs stamp_ns, const TickViz& viz);
[[nodiscard]] std::string log_json(core::TimeNs stamp_ns, LogLevel level, std::string_view name,
                                   std::string_view message);
/// Hull, obstacles, target arrow, danger sector and the state path as a text label (entity
/// "boat"); the goal, leg, judged gate and planned path in the "map" frame (entity "route").
[[nodiscard]] std::string scene_update_json(core::TimeNs stamp_ns, const TickViz& viz,
                                            std::string_view state_path);

/// Frame of the camera images and their annotations.
inline constexpr std::string_view kCameraFrame = "camera";

/// A JPEG frame as foxglove.CompressedImage (the bytes base64, as JSON carries bytes).
[[nodiscard]] std::string compressed_image_json(core::TimeNs stamp_ns,
                                                std::span<const std::uint8_t> jpeg);
/// The detections of a frame drawn on its image (foxglove.ImageAnnotations): a box in the
/// target's colour and a label (colour, shape, score) per detection. `scale` maps the detector's
/// pixels to the recorded image's (recorded width / detector width).
[[nodiscard]] std::string image_annotations_json(core::TimeNs stamp_ns,
                                                 const msg::CameraDetections& detections,
                                                 double scale);
/// RFC 4648 base64 (with padding).
[[nodiscard]] std::string base64(std::span<const std::uint8_t> bytes);

/// The mission's geometry and the track so far (navigation frame, oldest first) in the "map"
/// frame: entities "mission" and "track".
[[nodiscard]] std::string map_scene_json(core::TimeNs stamp_ns, const MapGeometry& geometry,
                                         std::span<const VizPoint> track);
/// The mission's geometry as a GeoJSON FeatureCollection (foxglove.GeoJSON, Map panel).
[[nodiscard]] std::string geojson_json(const MapGeometry& geometry);

}  // namespace coxswain::record::foxglove
