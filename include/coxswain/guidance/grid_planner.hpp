// SPDX-License-Identifier: Apache-2.0
#pragma once
// Global planning over an occupancy grid (docs/missions.md; the capstone report: A* on a
// down-sampled cost map, its path followed by pure pursuit). The grid lives in the navigation
// frame so obstacles persist while the boat turns; evidence decays so moved or spurious returns
// fade; obstacles are inflated by the hull so a path is a path for the whole boat.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "coxswain/core/frames.hpp"
#include "coxswain/perception/obstacles.hpp"

namespace coxswain::guidance {

/// Grid shape and update rules. Distances in metres.
struct GridParams {
  std::uint32_t rows = 100;         // along north
  std::uint32_t cols = 100;         // along east
  double resolution_m = 0.5;        // cell side; coarse enough to plan in well under a tick
  core::NavPoint origin{};          // navigation-frame position of the south-west corner of (0, 0)
  float decay_per_update = 0.85F;   // evidence multiplier applied at every update, in [0, 1)
  float hit_evidence = 0.6F;        // evidence added by one lidar segment sample, in (0, 1]
  float occupied_threshold = 0.5F;  // evidence at or above which a cell is an obstacle
  double inflate_radius_m = 0.8;    // half beam + clearance
  double max_range_m = 20.0;        // segments farther than this from the boat are not marked

  static constexpr std::uint32_t kMaxCells = 1U << 20;
  /// Empty when valid, else the first problem found.
  [[nodiscard]] std::optional<std::string> validate() const;
};

struct GridCell {
  std::uint32_t row = 0;
  std::uint32_t col = 0;
};

enum class CellState : std::uint8_t { kFree = 0, kInflated = 1, kOccupied = 2 };

/// What the planner reads: the shape of a grid and its blocked layer (not owned). Both
/// OccupancyGrid and the mission's NavMap planner hand one out.
struct GridView {
  std::uint32_t rows = 0;
  std::uint32_t cols = 0;
  double resolution_m = 1.0;
  core::NavPoint origin{};  // south-west corner of cell (0, 0)
  const CellState* state = nullptr;
  // How deep each cell lies in the inflation (0 free, larger nearer an obstacle), or none. With
  // it, a boat starting inside the inflation escapes only by moving no deeper, so it backs away
  // from a wall but never threads the gap between two buoys it lies beside.
  const std::uint8_t* depth = nullptr;
  // Extra cost of entering each cell, in sixteenths of its length (0 none), or none: a step into
  // cell k costs its length times (1 + cost[k] / 16), so paths keep off obstacles where there
  // is room and prefer water they have seen.
  const std::uint8_t* cost = nullptr;

  [[nodiscard]] std::optional<GridCell> cell_of(core::NavPoint p) const;
  [[nodiscard]] core::NavPoint center_of(GridCell c) const;
  [[nodiscard]] std::size_t index(GridCell c) const {
    return static_cast<std::size_t>(c.row) * cols + c.col;
  }
  [[nodiscard]] CellState at(GridCell c) const { return state[index(c)]; }
};

/// Occupancy evidence per cell plus the hull-inflated blocked layer. Storage is allocated once
/// in `create`; `update` allocates nothing. Not thread-safe.
class OccupancyGrid {
 public:
  using State = CellState;

  [[nodiscard]] static std::optional<OccupancyGrid> create(const GridParams& params,
                                                           std::string* error = nullptr);

  /// One scan: decay every cell, mark the segments (body frame, turned into the navigation frame
  /// with `pose`), rebuild the inflated layer.
  void update(const perception::ObstacleList& obstacles, const core::NavPose& pose);
  void decay();
  /// Adds evidence along a navigation-frame segment (sampled at half a cell).
  void mark_segment(core::NavPoint a, core::NavPoint b);
  /// Recomputes the occupied/inflated layer from the evidence.
  void rebuild_inflation();
  void clear();

  [[nodiscard]] std::optional<GridCell> cell_of(core::NavPoint p) const;
  [[nodiscard]] core::NavPoint center_of(GridCell c) const;
  [[nodiscard]] State state(GridCell c) const { return state_[index(c)]; }
  [[nodiscard]] float evidence(GridCell c) const { return evidence_[index(c)]; }
  [[nodiscard]] std::uint32_t rows() const { return params_.rows; }
  [[nodiscard]] std::uint32_t cols() const { return params_.cols; }
  [[nodiscard]] const GridParams& params() const { return params_; }
  [[nodiscard]] std::size_t index(GridCell c) const {
    return static_cast<std::size_t>(c.row) * params_.cols + c.col;
  }
  [[nodiscard]] GridView view() const {
    return {params_.rows, params_.cols, params_.resolution_m, params_.origin, state_.data()};
  }

 private:
  explicit OccupancyGrid(const GridParams& params);
  struct Offset {
    int dr;
    int dc;
  };
  GridParams params_;
  std::vector<float> evidence_;
  std::vector<State> state_;
  std::vector<Offset> stencil_;  // cells within the inflation radius of a cell
};

enum class PlanStatus : std::uint8_t {
  kOk = 0,
  kStartOutside = 1,
  kGoalOutside = 2,
  kGoalBlocked = 3,  // the goal cell is an obstacle or within the hull inflation
  kNoPath = 4,       // enclosed
  kBudget = 5,       // the expansion budget ran out before the goal was reached
};
[[nodiscard]] const char* to_string(PlanStatus s);

/// 8-connected A* with an octile-distance heuristic; diagonal moves may not cut an obstacle's
/// corner. Occupied and inflated cells are impassable, except that a boat starting inside the
/// inflation may leave it through inflated (never occupied) cells, never deeper ones when the
/// grid gives the inflation's depth. The path runs from the start
/// position to the goal position through cell centres, with collinear points removed.
/// All arrays are sized in the constructor for a grid of rows x cols; `plan` does not allocate.
/// Not thread-safe.
class AStarPlanner {
 public:
  AStarPlanner(std::uint32_t rows, std::uint32_t cols);

  [[nodiscard]] PlanStatus plan(const OccupancyGrid& grid, core::NavPoint start,
                                core::NavPoint goal) {
    return plan(grid.view(), start, goal);
  }
  /// As above on any grid of this planner's shape; gives up with kBudget after `max_expanded`
  /// expansions (a bound on the time one plan may take). `heuristic_weight` > 1 trades length
  /// for time: the path found is at most that many times the shortest one's cost, and far fewer
  /// cells are expanded where obstacles stand between start and goal (weighted A*).
  [[nodiscard]] PlanStatus plan(const GridView& grid, core::NavPoint start, core::NavPoint goal,
                                std::size_t max_expanded = SIZE_MAX, float heuristic_weight = 1.0F);
  /// The last successful path (empty after a failure).
  [[nodiscard]] const std::vector<core::NavPoint>& path() const { return path_; }
  /// Cells expanded by the last call (for benchmarks and tests).
  [[nodiscard]] std::size_t expanded() const { return expanded_; }

 private:
  void heap_push(std::uint32_t cell, float f);
  void heap_decrease(std::uint32_t cell, float f);
  std::uint32_t heap_pop();
  void sift_up(std::size_t i);
  void sift_down(std::size_t i);
  struct HeapEntry {
    float f;
    float h;
    std::uint32_t cell;
  };
  [[nodiscard]] static bool less(const HeapEntry& a, const HeapEntry& b);

  std::uint32_t rows_;
  std::uint32_t cols_;
  std::vector<float> g_;
  std::vector<float> h_;
  std::vector<std::uint32_t> parent_;
  std::vector<std::int32_t> heap_pos_;  // -1 not in heap, -2 closed
  std::vector<std::uint8_t> escaping_;  // reached from an inflated start through inflation only
  std::vector<std::uint32_t> visit_;    // the plan that last touched each cell (see plan)
  std::uint32_t generation_ = 0;
  std::vector<HeapEntry> heap_;
  std::size_t heap_size_ = 0;
  std::vector<std::uint32_t> cells_;  // scratch: the path as cells, goal first
  std::vector<core::NavPoint> path_;
  std::size_t expanded_ = 0;
};

}  // namespace coxswain::guidance
