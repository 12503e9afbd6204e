// SPDX-License-Identifier: Apache-2.0
#pragma once
// The mission's fixed geometry as the viewers draw it: waypoints, slips, the field boundary and
// the no-go areas, each in WGS-84 (Foxglove's Map panel) and in the navigation frame (its 3D
// panel, "map" frame). Plain data, filled by the host from the mission it sails.
#include <string>
#include <vector>

#include "coxswain/record/tick_record.hpp"

namespace coxswain::record {

/// A point on both maps.
struct MapVertex {
  double lat_deg = 0.0;
  double lon_deg = 0.0;
  VizPoint nav;
};

struct MapMark {
  enum class Kind : unsigned char { kWaypoint, kSlip };
  Kind kind = Kind::kWaypoint;
  std::string label;  // e.g. "obstacles 2": the task and the point's number in it (from 1)
  MapVertex at;
};

/// A closed polygon (the last corner joins the first).
struct MapArea {
  enum class Kind : unsigned char { kBoundary, kNoGo };
  Kind kind = Kind::kBoundary;
  std::string label;
  std::vector<MapVertex> corners;
};

struct MapGeometry {
  std::vector<MapMark> marks;
  std::vector<MapArea> areas;
  [[nodiscard]] bool empty() const { return marks.empty() && areas.empty(); }
};

}  // namespace coxswain::record
