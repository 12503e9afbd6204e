// SPDX-License-Identifier: Apache-2.0
#pragma once
// The mission's map in the navigation frame and the global planner on it (mission.md sections 4
// and 6). Two layers: a known layer from the mission file (outside the field boundary, inside a
// no-go polygon), fixed at construction; and lidar evidence as clamped log-odds, raised where a
// beam ends and lowered along the beam before it, so a buoy that moved or a return that was
// spray is cleared by the next beams that see through it. The planner inflates the obstacles by
// the hull's half beam plus a clearance, runs A* from the boat to the goal within an expansion
// budget, and hands the reactive avoidance a sub-goal a look-ahead distance along the path.
// Storage is allocated once at construction; updates and plans allocate nothing.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "coxswain/core/frames.hpp"
#include "coxswain/core/geodesy.hpp"
#include "coxswain/guidance/grid_planner.hpp"
#include "coxswain/msg/lidar_scan.hpp"
#include "coxswain/perception/lidar_clusterer.hpp"

namespace coxswain::guidance {

/// Map shape and the evidence rules. Log-odds are natural-log odds per beam.
struct NavMapParams {
  double resolution_m = 0.25;      // cell side
  double margin_m = 5.0;           // around the field boundary's bounding box
  double size_north_m = 100.0;     // without a boundary: this square-ish area centred on the
  double size_east_m = 100.0;      // mission origin
  float hit_log_odds = 0.85F;      // added where a beam ends on a return
  float miss_log_odds = -0.4F;     // added to each cell a beam passes through before its return
  float min_log_odds = -2.0F;      // clamp: a cell seen free many times still turns occupied
  float max_log_odds = 3.5F;       //   after a few hits, and the other way round
  float occupied_log_odds = 0.6F;  // at or above: an obstacle
  double max_range_m = 12.0;       // beams clear and mark only this far
  double min_range_m = 0.15;       // nearer returns are the hull or spray

  static constexpr std::size_t kMaxCells = 1U << 20;
  [[nodiscard]] std::optional<std::string> validate() const;
};

/// The global planner's rules. Distances in metres.
struct MapPlannerParams {
  bool enabled = true;                   // false: the tasks steer straight at the goal as before
  double replan_period_s = 0.25;         // replan at most this often (and when the goal changes)
  double clearance_m = 0.2;              // inflation = the avoidance's half beam + this
  double lookahead_m = 3.0;              // the sub-goal's distance along the path
  std::uint32_t max_expansions = 60000;  // A* budget per plan (bounds its time)
  double goal_search_m = 1.5;            // a blocked goal moves to the nearest free cell this near
  // No path: stop, back off, turn to look, replan; never drive at the goal.
  double stop_s = 1.0;
  double back_off_s = 4.0;  // astern is weak: 2 s at 0.3 moved a boat pinned on a wall 0.25 m
  double back_off_thrust_frac = 0.6;
  double look_s = 3.0;
  double look_turn_deg = 90.0;
  double look_thrust_frac = 0.3;
  // Stuck (with or without the planner): the boat moved less than stuck_distance_m in
  // stuck_s while it meant to go somewhere, as when its bow is on a wall; it stops, backs off
  // and turns toward its path (the stop/back-off/look times above). 0 s: never.
  double stuck_s = 5.0;
  double stuck_distance_m = 0.5;
  [[nodiscard]] std::optional<std::string> validate() const;
};

/// Gates judged by what the lidar sees: a waypoint of an obstacle course with two buoys about
/// `width_m` apart either side of it is a gate; it is passed when the boat's track crosses the
/// segment between the buoys as the lidar places them (relative to the boat, so a GNSS bias moves
/// both alike), with the mission's own gate (waypoint +- width / 2 across the leg) as fallback
/// when the buoys are not seen.
struct GateParams {
  bool judge_by_lidar = true;
  double width_m = 3.0;  // buoy centre to buoy centre
  double width_tolerance_m = 0.6;
  double search_radius_m = 4.0;    // the pair's midpoint this near the waypoint
  double max_angle_deg = 35.0;     // the pair's line this near square to the leg
  double max_buoy_length_m = 0.8;  // longer obstacle segments are not buoys
  double track_gate_m = 1.0;       // a new sighting this near the tracked gate updates it
  double approach_m = 2.5;         // after a miss: back to this far before the gate
  [[nodiscard]] std::optional<std::string> validate() const;
};

/// The mission file's `planning:` section.
struct PlanningConfig {
  NavMapParams map;
  MapPlannerParams planner;
  GateParams gates;
  std::vector<core::GeoPoint> boundary;            // field corners, in order (>= 3 or none)
  std::vector<std::vector<core::GeoPoint>> no_go;  // polygons, each >= 3 corners
  [[nodiscard]] std::optional<std::string> validate() const;
};

/// True when `p` lies inside the polygon (even-odd rule).
[[nodiscard]] bool inside_polygon(std::span<const core::NavPoint> polygon, core::NavPoint p);

/// The map. Not thread-safe.
class NavMap {
 public:
  /// Sized from the boundary (its bounding box plus the margin) or, without one, the explicit
  /// size centred on the navigation origin grown to hold every point of `extent` (the mission's
  /// waypoints) with the margin. Throws std::invalid_argument when invalid or too large.
  NavMap(const NavMapParams& params, std::span<const core::NavPoint> boundary,
         std::span<const std::vector<core::NavPoint>> no_go,
         std::span<const core::NavPoint> extent = {});

  /// One revolution (body frame, see msg::LidarScan) taken at `pose`; returns inside `hull` are
  /// the boat itself. Cells a beam ends in this scan are not cleared by other beams of it.
  void add_scan(const msg::LidarScan& scan, const core::NavPose& pose,
                const perception::HullBox& hull);
  /// Forgets the lidar evidence (the known layer stays).
  void clear_evidence();

  [[nodiscard]] bool occupied(std::size_t k) const {
    return known_[k] != 0 || log_odds_[k] >= params_.occupied_log_odds;
  }
  [[nodiscard]] bool known(std::size_t k) const { return known_[k] != 0; }
  [[nodiscard]] float log_odds(std::size_t k) const { return log_odds_[k]; }
  [[nodiscard]] std::optional<GridCell> cell_of(core::NavPoint p) const;
  [[nodiscard]] core::NavPoint center_of(GridCell c) const;
  [[nodiscard]] std::size_t index(GridCell c) const {
    return static_cast<std::size_t>(c.row) * cols_ + c.col;
  }
  [[nodiscard]] std::uint32_t rows() const { return rows_; }
  [[nodiscard]] std::uint32_t cols() const { return cols_; }
  [[nodiscard]] core::NavPoint origin() const { return origin_; }
  [[nodiscard]] const NavMapParams& params() const { return params_; }
  /// Occupied cells of the lidar layer (kept current by add_scan).
  [[nodiscard]] std::span<const std::uint32_t> lidar_occupied() const {
    return {occupied_list_.data(), occupied_count_};
  }

 private:
  void trace(int r0, int c0, int r1, int c1, bool hit);
  void set_log_odds(std::size_t k, float v);

  NavMapParams params_;
  core::NavPoint origin_;
  std::uint32_t rows_ = 0;
  std::uint32_t cols_ = 0;
  std::vector<float> log_odds_;
  std::vector<std::uint8_t> known_;
  std::vector<std::uint32_t> hit_stamp_;  // scan number of the last hit in each cell
  std::uint32_t scan_number_ = 0;
  struct CellIndex {
    int r;
    int c;
  };
  std::vector<CellIndex> beam_ends_;  // this scan's beam ends (scratch, one per return)
  // Occupied lidar cells as an unordered set (list + position), so inflation visits only them.
  std::vector<std::uint32_t> occupied_list_;
  std::vector<std::int32_t> occupied_pos_;
  std::size_t occupied_count_ = 0;
};

/// A* on the inflated map, the path's look-ahead sub-goal. Not thread-safe; allocates only in
/// the constructor.
class MapPlanner {
 public:
  /// `half_beam_m`: half the hull's width (the avoidance's).
  MapPlanner(const NavMap& map, const MapPlannerParams& params, double half_beam_m);

  /// Inflates the map and plans from `start` to `goal` (a goal off the map is taken to where the
  /// line to it leaves the map; a blocked one moves to the nearest free cell within
  /// goal_search_m).
  PlanStatus plan(const NavMap& map, core::NavPoint start, core::NavPoint goal);
  [[nodiscard]] PlanStatus status() const { return status_; }
  [[nodiscard]] const std::vector<core::NavPoint>& path() const { return astar_.path(); }
  [[nodiscard]] std::size_t expanded() const { return astar_.expanded(); }
  /// The point `lookahead_m` along the path past the point of it nearest `position`.
  [[nodiscard]] std::optional<core::NavPoint> subgoal(core::NavPoint position) const;
  [[nodiscard]] GridView view() const;
  [[nodiscard]] const MapPlannerParams& params() const { return params_; }

 private:
  struct Offset {
    int dr;
    int dc;
    std::uint8_t depth;  // how far inside the inflation radius, 1..254 (see GridView::depth)
  };
  void inflate(const NavMap& map);

  MapPlannerParams params_;
  double resolution_m_;
  core::NavPoint origin_;
  std::uint32_t rows_;
  std::uint32_t cols_;
  std::vector<CellState> known_state_;  // the known layer inflated once
  std::vector<CellState> state_;
  std::vector<std::uint8_t> known_depth_;
  std::vector<std::uint8_t> depth_;
  std::vector<Offset> stencil_;
  std::vector<Offset> goal_ring_;  // offsets within goal_search_m, nearest first
  AStarPlanner astar_;
  PlanStatus status_ = PlanStatus::kNoPath;
};

}  // namespace coxswain::guidance
