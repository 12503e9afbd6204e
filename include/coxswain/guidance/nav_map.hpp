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
#include "coxswain/guidance/turn_side.hpp"
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
  double min_range_m = 0.15;       // nearer returns are the hull: the avoidance's, not the map's
  // A beam with no return (open water reflects nothing back) clears its whole length; off, only
  // beams that end on something clear, and open water stays unseen.
  bool no_return_clears = true;
  // ...except in a scan with a return nearer than this: a wall nearer than the scanner's own
  // least range gives no return either, and a hull against a wall would clear the water behind
  // it. 0: never held back.
  double no_return_near_m = 0.6;

  static constexpr std::size_t kMaxCells = 1U << 20;
  [[nodiscard]] std::optional<std::string> validate() const;
};

/// The global planner's rules. Distances in metres.
struct MapPlannerParams {
  bool enabled = true;            // false: the tasks steer straight at the goal as before
  double replan_period_s = 0.25;  // replan at most this often (and when the goal changes)
  double clearance_m = 0.2;       // inflation = the avoidance's half beam + this
  // Beyond the inflation a band this wide where a path pays to come near an obstacle, up to
  // clearance_cost times its length at the inflation's edge (falling off as a square), so the
  // path keeps to the middle of a passage when there is room and still takes a narrow one. Off
  // by default: with it (4.0) and the line-of-sight sub-goal, dead ends went 58% -> 82% but the
  // obstacle course 99% -> 94% (docs/results.md), so it is a venue's choice.
  double soft_clearance_m = 1.5;
  double clearance_cost = 0.0;
  double unknown_cost = 0.0;  // extra cost per metre of water the lidar has never seen
  // Within this of the goal both costs fade out toward it: a goal in a gate or a slip is as near
  // its obstacles as it is, and the path must be free to reach it there.
  double goal_fade_m = 4.0;
  // Never outrun the lidar: full speed only while the path ahead runs this far through water
  // already seen; nearer the unseen, the speed falls in proportion, down to the floor. Off by
  // default: on the dead-end family it cost successes (a slow single-thruster boat is set onto
  // the walls by the current; docs/results.md).
  double sight_full_speed_m = 0.0;
  double sight_min_speed_factor = 0.4;
  // Slow for a turn: with the path's sub-goal more than turn_slow_deg off the bow, the speed
  // falls in proportion to the turn still to make, down to turn_min_speed_factor at 90 deg or
  // more, so a boat meeting a corner of its path (a gap opening beside it) turns in the room it
  // has rather than coasting on into what lies ahead. 0 deg: off.
  double turn_slow_deg = 0.0;
  double turn_min_speed_factor = 0.4;
  double lookahead_m = 3.0;  // the sub-goal's distance along the path
  // The sub-goal comes nearer, down to this along the path, until the boat can steer straight
  // at it (never round a corner); at lookahead_m or more (the default): always lookahead_m along
  // the path. Off by default with the clearance cost (docs/results.md).
  double line_of_sight_min_m = 3.0;
  std::uint32_t max_expansions = 60000;  // A* budget per plan (bounds its time)
  // A* aims this much harder at the goal than the exact search (weighted A*): a path at most
  // this many times the cheapest one's cost, found with far fewer expansions where obstacles
  // stand between. 1: the cheapest path.
  double heuristic_weight = 1.0;
  double goal_search_m = 1.5;  // a blocked goal moves to the nearest free cell this near
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
  // Astern along the path: when the path's sub-goal lies more than astern_behind_deg off the
  // bow and the swept hull cannot turn to it (a pocket narrower than the turning circle), the
  // boat backs along the path stern first at astern_thrust_frac, while astern_look_m of water
  // behind the stern stays clear, until the turn is free (then turns onto the path at
  // look_thrust_frac) or it has backed astern_max_m.
  bool astern_enabled = true;
  double astern_behind_deg = 110.0;
  double astern_thrust_frac = 1.0;  // a propeller pushes less astern than ahead
  double astern_look_m = 0.6;
  double astern_max_m = 8.0;
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
  // While a gate is the goal the planner takes its line beyond each end, this far, for a wall,
  // so a path crosses the line between the ends and nowhere else (0: off).
  double wall_m = 8.0;
  [[nodiscard]] std::optional<std::string> validate() const;
};

/// The mission file's `planning:` section.
struct PlanningConfig {
  NavMapParams map;
  MapPlannerParams planner;
  GateParams gates;
  // Tasks that only follow waypoints (the hopping tour) take a large turn the long way round
  // when the lidar sees the short way's turning circle blocked (a pool's wall beside a waypoint).
  TurnSideParams turn_side;
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
  void set_log_odds(std::size_t k, float v);
  void build_sweep();
  /// Cosine and sine of a body bearing from the table (false when it is not finite): one scan
  /// has a thousand beams or more, and the library's sine and cosine were a third of a tick.
  [[nodiscard]] bool unit_of(double bearing_deg, double& cos_out, double& sin_out) const;
  /// The shortest beam among the bins [lo, lo + span) of this scan's range table.
  [[nodiscard]] float shortest_beam(std::uint32_t lo, std::uint32_t span) const;

  NavMapParams params_;
  core::NavPoint origin_;
  std::uint32_t rows_ = 0;
  std::uint32_t cols_ = 0;
  static constexpr int kTrigStepsPerDeg = 10;
  std::vector<double> trig_;  // cos, sin pairs from -180 deg in 1 / kTrigStepsPerDeg steps
  std::vector<float> log_odds_;
  std::vector<std::uint8_t> known_;
  std::vector<std::uint32_t> hit_stamp_;  // scan number of the last hit in each cell
  std::uint32_t scan_number_ = 0;
  // Free space is cleared cell by cell rather than beam by beam: a cell is passed when every
  // beam across it reaches beyond its far corner, so a beam grazing a buoy through the gap
  // beside it never clears the buoy's cells, and a cell takes one miss per scan however many
  // beams cross it. Each cell within range is listed once per position of the boat in its own
  // cell (kSubCells x kSubCells of them): offset, the bearing bins it spans, the distance to its
  // far corner, nearest first.
  static constexpr int kSubCells = 4;
  static constexpr std::uint32_t kBins = 1024;  // bearing bins of the range table, north = 0
  struct SweepCell {
    std::int16_t dr;
    std::int16_t dc;
    std::uint16_t bin_lo;
    std::uint16_t span;  // bins, >= 1
    float far_m;         // distance from the boat to the cell's far corner
  };
  std::vector<SweepCell> sweep_cells_;
  std::vector<std::size_t> sweep_start_;  // kSubCells^2 + 1 offsets into sweep_cells_
  // This scan's shortest range per bin (no beam: 0), then levels of minima over 2^l bins for
  // O(1) spans (a sparse table), each level 2 * kBins long so spans need not wrap.
  std::vector<float> range_levels_;
  std::uint32_t levels_ = 1;
  // Occupied lidar cells as an unordered set (list + position), so inflation visits only them.
  std::vector<std::uint32_t> occupied_list_;
  std::vector<std::int32_t> occupied_pos_;
  std::size_t occupied_count_ = 0;
};

/// A line one plan may not cross (a gate's line beyond its ends), inflated as a wall is.
struct PlanWall {
  core::NavPoint from;
  core::NavPoint to;
};

/// A* on the inflated map, the path's look-ahead sub-goal. Not thread-safe; allocates only in
/// the constructor.
class MapPlanner {
 public:
  /// `half_beam_m`: half the hull's width (the avoidance's).
  MapPlanner(const NavMap& map, const MapPlannerParams& params, double half_beam_m);

  /// Inflates the map and plans from `start` to `goal` (a goal off the map is taken to where the
  /// line to it leaves the map; a blocked one moves to the nearest free cell within
  /// goal_search_m). A start on an obstacle cell (a hull on a wall, its position a little
  /// inside it) plans from the last start that was not, when that is near: the boat leaves a
  /// wall on the side it came from, never through it. `walls` stand for this plan only, as
  /// obstacles (a boat on one leaves it the way it came, as from any wall).
  PlanStatus plan(const NavMap& map, core::NavPoint start, core::NavPoint goal,
                  std::span<const PlanWall> walls = {});
  [[nodiscard]] PlanStatus status() const { return status_; }
  /// The last successful plan's path (empty after a failure).
  [[nodiscard]] const std::vector<core::NavPoint>& path() const { return path_; }
  [[nodiscard]] std::size_t expanded() const { return astar_.expanded(); }
  /// How far the path runs through water the lidar has seen, from the point of it nearest
  /// `position` (capped at `limit_m`; a path ending before that in seen water gives the cap).
  [[nodiscard]] double seen_ahead_m(const NavMap& map, core::NavPoint position,
                                    double limit_m) const;
  /// The farthest point of the path, at most `lookahead_m` along it past the point of it nearest
  /// `position`, that the boat reaches on a clear straight line (so never round a corner).
  [[nodiscard]] std::optional<core::NavPoint> subgoal(core::NavPoint position) const {
    return subgoal(position, params_.line_of_sight_min_m);
  }
  /// As above, coming nearer down to `nearest_m` along the path for a clear straight line.
  [[nodiscard]] std::optional<core::NavPoint> subgoal(core::NavPoint position,
                                                      double nearest_m) const;
  /// The point `ahead_m` along the path past the point of it nearest `position` (the path's end
  /// when that is nearer), whether or not the boat sees it on a straight line.
  [[nodiscard]] std::optional<core::NavPoint> along_path(core::NavPoint position,
                                                         double ahead_m) const;
  [[nodiscard]] GridView view() const;
  [[nodiscard]] const MapPlannerParams& params() const { return params_; }

 private:
  struct Offset {
    int dr;
    int dc;
  };
  void inflate(const NavMap& map, std::span<const PlanWall> walls);
  /// Makes the cells of `w` on the map obstacles, queued for the spread after the first
  /// `queued`; returns the new count.
  std::size_t queue_wall(const PlanWall& w, std::size_t queued);
  /// Scales the costs down toward the goal (goal_fade_m).
  void fade_near(core::NavPoint goal);
  /// Spreads each cell's nearest obstacle (site) to its neighbours from the `queued` cells at
  /// the front of queue_, as far as the soft band reaches (squared cell distances).
  void spread(std::vector<std::uint32_t>& dist2, std::vector<std::uint32_t>& site,
              std::size_t queued, bool note);
  /// A cell's state, depth and cost from its distance (and, with unknown_cost, the map).
  void derive(const NavMap& map, std::size_t k);
  /// Lists a cell whose values now differ from the known layer's (once per plan).
  void note_changed(std::uint32_t k);
  /// Whether the straight line from `a` to `b` stays where a boat at `a` may go: free cells, or
  /// inflated ones no deeper than a's own (leaving the inflation it starts in).
  [[nodiscard]] bool line_clear(core::NavPoint a, core::NavPoint b) const;
  /// The segment of path_ (index of its first point) nearest `position`, and that point.
  std::size_t nearest_on_path(core::NavPoint position, core::NavPoint& nearest) const;

  MapPlannerParams params_;
  double resolution_m_;
  core::NavPoint origin_;
  std::uint32_t rows_;
  std::uint32_t cols_;
  // Squared distance (cells) to the nearest obstacle cell and that cell, for the known layer
  // (computed once) and for the known layer plus the lidar's (each plan); kFar beyond the band.
  std::vector<std::uint32_t> known_dist2_;
  std::vector<std::uint32_t> known_site_;
  std::vector<std::uint32_t> dist2_;
  std::vector<std::uint32_t> site_;
  std::vector<std::uint32_t> queue_;  // the spread's FIFO ring
  std::vector<CellState> state_;
  std::vector<std::uint8_t> depth_;
  std::vector<std::uint8_t> cost_;
  // By squared cell distance up to the band's edge: inflation depth (0 outside the inflation)
  // and soft cost (sixteenths, see GridView::cost).
  std::vector<std::uint8_t> depth_by_dist2_;
  std::vector<std::uint8_t> cost_by_dist2_;
  std::uint8_t unknown_cost_ = 0;
  std::uint32_t band_dist2_ = 0;
  std::vector<Offset> goal_ring_;  // offsets within goal_search_m, nearest first
  // The cells that differ from the known layer after this plan and the last (see inflate), and
  // the plan that last listed each cell.
  std::vector<std::uint32_t> changed_;
  std::vector<std::uint32_t> previous_changed_;
  std::vector<std::uint32_t> changed_stamp_;
  std::uint32_t plan_stamp_ = 0;
  bool inflated_once_ = false;
  AStarPlanner astar_;
  std::vector<core::NavPoint> path_;  // capacity reserved once: assignments never allocate
  PlanStatus status_ = PlanStatus::kNoPath;
  // The last start that lay off every obstacle cell (see plan).
  std::optional<core::NavPoint> last_clear_start_;
};

}  // namespace coxswain::guidance
