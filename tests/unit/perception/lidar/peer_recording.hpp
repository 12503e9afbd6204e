// SPDX-License-Identifier: Apache-2.0
#pragma once
// Reads the source team's recorded run (the shared test data
// folder/peer/tricat221-0223-scans.jsonl, see its README entry): ROS LaserScan records and the
// obstacle lists their node published for them. Shared by the lidar tests and
// bench_lidar_clustering. Test/tool code: allocates freely.
//
// Frames. rplidar_ros publishes in frame `laser` with theta_ros = pi - theta_raw (raw RPLIDAR
// angles run clockwise from the lidar's front), so the lidar's front is at theta_ros = +-pi. On
// their 2022 boat the lidar front faced the bow, so the laser frame's x axis points ASTERN and its
// y axis (90 deg counter-clockwise of astern, seen from above) points to STARBOARD:
//   body forward = -x_laser, body starboard = +y_laser, body bearing = wrap(180 - theta_ros_deg).
// Their scan therefore starts at the bow (theta_ros = -pi) and walks towards port.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "coxswain/core/angles.hpp"
#include "coxswain/core/frames.hpp"
#include "coxswain/msg/lidar_scan.hpp"

namespace coxswain::testing::peer {

struct PeerSegment {
  core::BodyPoint begin;
  core::BodyPoint end;
};

struct PeerScan {
  std::unique_ptr<msg::LidarScan> scan;  // body frame, sorted by bearing ascending
  bool has_segments = false;             // one scan of 174 has no obstacle list
  std::vector<PeerSegment> segments;     // theirs, turned into the body frame
};

inline core::BodyPoint laser_to_body(double x_laser_m, double y_laser_m) {
  return core::BodyPoint{-x_laser_m, y_laser_m};
}

/// One ROS LaserScan JSON record -> msg::LidarScan in the body frame. Null ranges (no return) are
/// left out; intensities (RPLIDAR quality) become `quality`.
inline std::unique_ptr<msg::LidarScan> laser_scan_to_body(const nlohmann::json& rec) {
  auto scan = std::make_unique<msg::LidarScan>();
  scan->stamp_ns = rec.at("stamp_ns").get<std::int64_t>();
  scan->max_range_m = rec.at("range_max").get<float>();
  scan->min_range_m = rec.at("range_min").get<float>();
  scan->duration_ns = static_cast<std::int64_t>(rec.at("scan_time").get<double>() * 1e9);
  const double angle_min = rec.at("angle_min").get<double>();
  const double increment = rec.at("angle_increment").get<double>();
  const auto& ranges = rec.at("ranges");
  const auto& intensities = rec.at("intensities");
  const std::size_t n = ranges.size();
  for (std::size_t i = 0; i < n && i < msg::LidarScan::kMaxPoints; ++i) {
    if (ranges[i].is_null()) continue;
    const double theta_ros = angle_min + static_cast<double>(i) * increment;
    msg::LidarPoint p;
    p.bearing_deg = static_cast<float>(core::wrap_deg(180.0 - core::rad_to_deg(theta_ros)));
    p.range_m = ranges[i].get<float>();
    const double q = i < intensities.size() ? intensities[i].get<double>() : 0.0;
    p.quality = static_cast<std::uint8_t>(std::clamp(q, 0.0, 255.0));
    p.offset_us = static_cast<std::int32_t>(static_cast<double>(i) / static_cast<double>(n) *
                                            static_cast<double>(scan->duration_ns) / 1e3);
    (void)scan->push(p);
  }
  std::stable_sort(scan->points.begin(), scan->points.begin() + scan->point_count,
                   [](const msg::LidarPoint& a, const msg::LidarPoint& b) {
                     return a.bearing_deg < b.bearing_deg;
                   });
  return scan;
}

/// All scans of the recording in order, each with their obstacle list when one was recorded.
inline std::vector<PeerScan> load_peer_recording(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<PeerScan> scans;
  std::unordered_map<std::int64_t, std::vector<PeerSegment>> obstacles;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const nlohmann::json rec = nlohmann::json::parse(line);
    const std::string topic = rec.at("topic").get<std::string>();
    if (topic == "scan") {
      scans.push_back(PeerScan{laser_scan_to_body(rec), false, {}});
    } else if (topic == "obstacles") {
      std::vector<PeerSegment> segs;
      for (const auto& s : rec.at("segments")) {
        segs.push_back(PeerSegment{laser_to_body(s.at(0).get<double>(), s.at(1).get<double>()),
                                   laser_to_body(s.at(2).get<double>(), s.at(3).get<double>())});
      }
      obstacles[rec.at("stamp_ns").get<std::int64_t>()] = std::move(segs);
    }
  }
  for (auto& s : scans) {
    const auto it = obstacles.find(s.scan->stamp_ns);
    if (it != obstacles.end()) {
      s.has_segments = true;
      s.segments = it->second;
    }
  }
  return scans;
}

}  // namespace coxswain::testing::peer
