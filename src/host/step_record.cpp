// SPDX-License-Identifier: Apache-2.0
#include "coxswain/host/step_record.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>

#include "coxswain/core/geodesy.hpp"
#include "coxswain/mission/tunable_parameters.hpp"

namespace coxswain::host {

void fill_tick_viz(const mission::CoreOutput& out, const config::BoatConfig& boat,
                   record::TickViz& viz) {
  const mission::VizFrame& f = out.viz;
  viz = record::TickViz{};
  viz.pose_valid = f.pose_valid;
  viz.north_m = f.pose.position.north_m;
  viz.east_m = f.pose.position.east_m;
  viz.heading_deg = f.pose.heading_deg;
  viz.cov_valid = f.position_cov_valid;
  viz.cov_nn_m2 = f.position_cov_nn_m2;
  viz.cov_ne_m2 = f.position_cov_ne_m2;
  viz.cov_ee_m2 = f.position_cov_ee_m2;
  viz.hull_length_m = static_cast<float>(boat.hull.length_m);
  viz.hull_beam_m = static_cast<float>(boat.hull.beam_m);
  if (f.has_avoidance) {
    viz.target_valid = true;
    viz.target_bearing_deg = f.avoidance_bearing_body_deg;
  } else if (f.has_desired_heading && f.heading_valid) {
    viz.target_valid = true;
    viz.target_bearing_deg = f.desired_heading_deg - f.pose.heading_deg;
  }
  const auto point = [](core::NavPoint p) { return record::VizPoint{p.north_m, p.east_m}; };
  viz.goal_valid = f.has_goal;
  viz.goal = point(f.goal);
  viz.arrival_radius_m = f.arrival_radius_m;
  viz.leg_valid = f.has_leg;
  viz.leg_start = point(f.leg_start);
  viz.gate_valid = f.has_gate;
  viz.gate_by_lidar = f.gate_by_lidar;
  viz.gate_port = point(f.gate_port);
  viz.gate_starboard = point(f.gate_starboard);
  static_assert(record::TickViz::kMaxPathPoints >= mission::VizFrame::kMaxPathPoints);
  viz.path_count = std::min<std::uint32_t>(f.path_count, mission::VizFrame::kMaxPathPoints);
  for (std::uint32_t i = 0; i < viz.path_count; ++i) viz.path[i] = point(f.path[i]);
  // The blocked sector: from the first to the last bin judged more than half blocked.
  const std::uint32_t bins =
      std::min<std::uint32_t>(f.danger_count, mission::VizFrame::kMaxDangerBins);
  std::int64_t first = -1;
  std::int64_t last = -1;
  for (std::uint32_t i = 0; i < bins; ++i) {
    if (f.danger[i] > 0.5F) {
      if (first < 0) first = i;
      last = i;
    }
  }
  if (first >= 0) {
    viz.danger_valid = true;
    viz.danger_start_deg = f.danger_min_deg + static_cast<double>(first) * f.danger_bin_width_deg;
    viz.danger_end_deg = f.danger_min_deg + static_cast<double>(last + 1) * f.danger_bin_width_deg;
    viz.danger_range_m = 0.0;
  }
  // The nearest segments, each as a disc through its end points.
  std::array<std::pair<double, std::uint32_t>, mission::VizFrame::kMaxSegments> order{};
  const std::uint32_t n = std::min<std::uint32_t>(f.segment_count, mission::VizFrame::kMaxSegments);
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto& s = f.segments[i];
    const double mx = 0.5 * (s.begin.forward_m + s.end.forward_m);
    const double my = 0.5 * (s.begin.starboard_m + s.end.starboard_m);
    order[i] = {std::hypot(mx, my), i};
  }
  std::sort(order.begin(), order.begin() + n);
  for (std::uint32_t k = 0; k < n && viz.obstacle_count < record::TickViz::kMaxObstacles; ++k) {
    const auto& s = f.segments[order[k].second];
    record::VizObstacle& o = viz.obstacles[viz.obstacle_count++];
    o.x_m = static_cast<float>(0.5 * (s.begin.forward_m + s.end.forward_m));
    o.y_m = static_cast<float>(0.5 * (s.begin.starboard_m + s.end.starboard_m));
    o.radius_m = static_cast<float>(0.5 * std::hypot(s.end.forward_m - s.begin.forward_m,
                                                     s.end.starboard_m - s.begin.starboard_m));
  }
}

record::MapGeometry map_geometry(const config::MissionConfig& mission) {
  const core::LocalFrame frame(mission.origin);
  const auto vertex = [&](const core::GeoPoint& g) {
    const core::NavPoint p = frame.to_nav(g);
    return record::MapVertex{g.lat_deg, g.lon_deg, {p.north_m, p.east_m}};
  };
  record::MapGeometry geometry;
  for (const config::TaskConfig& task : mission.tasks) {
    for (std::size_t i = 0; i < task.waypoints.size(); ++i) {
      geometry.marks.push_back({record::MapMark::Kind::kWaypoint,
                                task.name + " " + std::to_string(i + 1),
                                vertex(task.waypoints[i])});
    }
    for (std::size_t i = 0; i < task.slips.size(); ++i) {
      geometry.marks.push_back({record::MapMark::Kind::kSlip,
                                task.name + " slip " + std::to_string(i + 1),
                                vertex(task.slips[i])});
    }
  }
  const auto area = [&](record::MapArea::Kind kind, std::string label,
                        const std::vector<core::GeoPoint>& corners) {
    record::MapArea a{kind, std::move(label), {}};
    for (const core::GeoPoint& g : corners) a.corners.push_back(vertex(g));
    geometry.areas.push_back(std::move(a));
  };
  if (!mission.planning.boundary.empty()) {
    area(record::MapArea::Kind::kBoundary, "boundary", mission.planning.boundary);
  }
  for (std::size_t i = 0; i < mission.planning.no_go.size(); ++i) {
    area(record::MapArea::Kind::kNoGo, "no-go " + std::to_string(i + 1), mission.planning.no_go[i]);
  }
  return geometry;
}

std::vector<record::NamedValue> named_values(const mission::TunableParameters& params) {
  std::vector<record::NamedValue> values;
  values.reserve(mission::tunable_specs().size());
  for (const mission::TunableSpec& spec : mission::tunable_specs()) {
    values.push_back({spec.name, spec.get(params)});
  }
  return values;
}

}  // namespace coxswain::host
