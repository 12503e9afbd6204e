// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/grid_planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace coxswain::guidance {
namespace {

constexpr float kInfF = std::numeric_limits<float>::infinity();
constexpr float kSqrt2 = 1.41421356F;
constexpr std::int32_t kNotInHeap = -1;
constexpr std::int32_t kClosed = -2;
constexpr float kCostUnit = 1.0F / 16.0F;  // GridView::cost is in sixteenths

// Octile distance in cells: exact for 8-connected moves on a free grid, so admissible.
float octile(std::uint32_t r0, std::uint32_t c0, std::uint32_t r1, std::uint32_t c1) {
  const auto dr = static_cast<float>(r0 > r1 ? r0 - r1 : r1 - r0);
  const auto dc = static_cast<float>(c0 > c1 ? c0 - c1 : c1 - c0);
  return std::max(dr, dc) + (kSqrt2 - 1.0F) * std::min(dr, dc);
}

}  // namespace

std::optional<std::string> GridParams::validate() const {
  if (rows == 0 || cols == 0) return "grid: rows and cols must be > 0";
  if (static_cast<std::uint64_t>(rows) * cols > kMaxCells) return "grid: too many cells";
  if (!std::isfinite(resolution_m) || !(resolution_m > 0.0)) return "grid: resolution_m > 0";
  if (!std::isfinite(origin.north_m) || !std::isfinite(origin.east_m)) return "grid: origin";
  if (!(decay_per_update >= 0.0F && decay_per_update < 1.0F)) return "grid: decay in [0, 1)";
  if (!(hit_evidence > 0.0F && hit_evidence <= 1.0F)) return "grid: hit_evidence in (0, 1]";
  if (!(occupied_threshold > 0.0F && occupied_threshold <= 1.0F)) {
    return "grid: occupied_threshold in (0, 1]";
  }
  if (!std::isfinite(inflate_radius_m) || inflate_radius_m < 0.0) return "grid: inflate >= 0";
  if (inflate_radius_m / resolution_m > 50.0) return "grid: inflation too wide for the cells";
  if (!std::isfinite(max_range_m) || !(max_range_m > 0.0)) return "grid: max_range_m > 0";
  return {};
}

std::optional<OccupancyGrid> OccupancyGrid::create(const GridParams& params, std::string* error) {
  if (auto e = params.validate()) {
    if (error != nullptr) *error = std::move(*e);
    return std::nullopt;
  }
  return OccupancyGrid(params);
}

OccupancyGrid::OccupancyGrid(const GridParams& params)
    : params_(params),
      evidence_(static_cast<std::size_t>(params.rows) * params.cols, 0.0F),
      state_(evidence_.size(), State::kFree) {
  // An obstacle may sit anywhere in its cell, so reach half a cell further than the radius.
  const double reach = params.inflate_radius_m / params.resolution_m + 0.5;
  const int n = static_cast<int>(std::ceil(reach));
  for (int dr = -n; dr <= n; ++dr) {
    for (int dc = -n; dc <= n; ++dc) {
      if ((dr != 0 || dc != 0) && std::hypot(dr, dc) <= reach) stencil_.push_back({dr, dc});
    }
  }
}

void OccupancyGrid::clear() {
  std::fill(evidence_.begin(), evidence_.end(), 0.0F);
  std::fill(state_.begin(), state_.end(), State::kFree);
}

void OccupancyGrid::decay() {
  for (float& e : evidence_) e *= params_.decay_per_update;
}

std::optional<GridCell> GridView::cell_of(core::NavPoint p) const {
  const double r = std::floor((p.north_m - origin.north_m) / resolution_m);
  const double c = std::floor((p.east_m - origin.east_m) / resolution_m);
  if (!(r >= 0.0 && c >= 0.0 && r < rows && c < cols)) return std::nullopt;
  return GridCell{static_cast<std::uint32_t>(r), static_cast<std::uint32_t>(c)};
}

core::NavPoint GridView::center_of(GridCell c) const {
  return {origin.north_m + (c.row + 0.5) * resolution_m,
          origin.east_m + (c.col + 0.5) * resolution_m};
}

std::optional<GridCell> OccupancyGrid::cell_of(core::NavPoint p) const { return view().cell_of(p); }

core::NavPoint OccupancyGrid::center_of(GridCell c) const { return view().center_of(c); }

void OccupancyGrid::mark_segment(core::NavPoint a, core::NavPoint b) {
  const double len = core::distance_m(a, b);
  const double step = 0.5 * params_.resolution_m;
  const auto samples = static_cast<std::size_t>(std::ceil(len / step));
  std::size_t last = evidence_.size();  // don't add twice to one cell for one segment
  for (std::size_t i = 0; i <= samples; ++i) {
    const double t = samples == 0 ? 0.0 : static_cast<double>(i) / static_cast<double>(samples);
    const core::NavPoint p{a.north_m + t * (b.north_m - a.north_m),
                           a.east_m + t * (b.east_m - a.east_m)};
    const auto cell = cell_of(p);
    if (!cell) continue;
    const std::size_t k = index(*cell);
    if (k == last) continue;
    last = k;
    evidence_[k] = std::min(1.0F, evidence_[k] + params_.hit_evidence);
  }
}

void OccupancyGrid::rebuild_inflation() {
  std::fill(state_.begin(), state_.end(), State::kFree);
  const auto rows = static_cast<int>(params_.rows);
  const auto cols = static_cast<int>(params_.cols);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const auto k = static_cast<std::size_t>(r) * params_.cols + static_cast<std::size_t>(c);
      if (evidence_[k] < params_.occupied_threshold) continue;
      state_[k] = State::kOccupied;
      for (const Offset& o : stencil_) {
        const int rr = r + o.dr;
        const int cc = c + o.dc;
        if (rr < 0 || cc < 0 || rr >= rows || cc >= cols) continue;
        const auto kk = static_cast<std::size_t>(rr) * params_.cols + static_cast<std::size_t>(cc);
        if (state_[kk] == State::kFree) state_[kk] = State::kInflated;
      }
    }
  }
}

void OccupancyGrid::update(const perception::ObstacleList& obstacles, const core::NavPose& pose) {
  decay();
  const std::uint32_t n =
      std::min<std::uint32_t>(obstacles.count, perception::ObstacleList::kMaxSegments);
  for (std::uint32_t k = 0; k < n; ++k) {
    const auto& s = obstacles.segments[k];
    const double near_m = std::min(std::hypot(s.begin.forward_m, s.begin.starboard_m),
                                   std::hypot(s.end.forward_m, s.end.starboard_m));
    if (!(std::min(near_m, static_cast<double>(s.closest_range_m)) <= params_.max_range_m))
      continue;
    mark_segment(core::body_to_nav(pose, s.begin), core::body_to_nav(pose, s.end));
  }
  rebuild_inflation();
}

const char* to_string(PlanStatus s) {
  switch (s) {
    case PlanStatus::kOk:
      return "ok";
    case PlanStatus::kStartOutside:
      return "start_outside";
    case PlanStatus::kGoalOutside:
      return "goal_outside";
    case PlanStatus::kGoalBlocked:
      return "goal_blocked";
    case PlanStatus::kNoPath:
      return "no_path";
    case PlanStatus::kBudget:
      return "budget";
  }
  return "unknown";
}

AStarPlanner::AStarPlanner(std::uint32_t rows, std::uint32_t cols)
    : rows_(rows),
      cols_(cols),
      g_(static_cast<std::size_t>(rows) * cols),
      h_(g_.size()),
      parent_(g_.size()),
      heap_pos_(g_.size()),
      escaping_(g_.size()),
      visit_(g_.size(), 0U),
      heap_(g_.size()),
      cells_(g_.size()) {
  path_.reserve(g_.size() + 2);
}

bool AStarPlanner::less(const HeapEntry& a, const HeapEntry& b) {
  // Lower f, then lower h (deeper toward the goal), then lower index: fully deterministic. The
  // keys travel with the heap's entries, so a comparison reads no other array.
  if (a.f != b.f) return a.f < b.f;
  if (a.h != b.h) return a.h < b.h;
  return a.cell < b.cell;
}

void AStarPlanner::sift_up(std::size_t i) {
  const HeapEntry e = heap_[i];
  while (i > 0) {
    const std::size_t parent = (i - 1) / 2;
    if (!less(e, heap_[parent])) break;
    heap_[i] = heap_[parent];
    heap_pos_[heap_[i].cell] = static_cast<std::int32_t>(i);
    i = parent;
  }
  heap_[i] = e;
  heap_pos_[e.cell] = static_cast<std::int32_t>(i);
}

void AStarPlanner::sift_down(std::size_t i) {
  const HeapEntry e = heap_[i];
  for (;;) {
    std::size_t child = 2 * i + 1;
    if (child >= heap_size_) break;
    if (child + 1 < heap_size_ && less(heap_[child + 1], heap_[child])) ++child;
    if (!less(heap_[child], e)) break;
    heap_[i] = heap_[child];
    heap_pos_[heap_[i].cell] = static_cast<std::int32_t>(i);
    i = child;
  }
  heap_[i] = e;
  heap_pos_[e.cell] = static_cast<std::int32_t>(i);
}

void AStarPlanner::heap_push(std::uint32_t cell, float f) {
  heap_[heap_size_] = {f, h_[cell], cell};
  ++heap_size_;
  sift_up(heap_size_ - 1);
}

void AStarPlanner::heap_decrease(std::uint32_t cell, float f) {
  const auto at = static_cast<std::size_t>(heap_pos_[cell]);
  heap_[at].f = f;
  sift_up(at);
}

std::uint32_t AStarPlanner::heap_pop() {
  const std::uint32_t top = heap_[0].cell;
  --heap_size_;
  if (heap_size_ > 0) {
    heap_[0] = heap_[heap_size_];
    sift_down(0);
  }
  heap_pos_[top] = kClosed;
  return top;
}

PlanStatus AStarPlanner::plan(const GridView& grid, core::NavPoint start, core::NavPoint goal,
                              std::size_t max_expanded, float heuristic_weight) {
  path_.clear();
  expanded_ = 0;
  if (grid.rows != rows_ || grid.cols != cols_ || grid.state == nullptr) return PlanStatus::kNoPath;
  const auto s_cell = grid.cell_of(start);
  if (!s_cell) return PlanStatus::kStartOutside;
  const auto g_cell = grid.cell_of(goal);
  if (!g_cell) return PlanStatus::kGoalOutside;
  if (grid.at(*g_cell) != CellState::kFree) return PlanStatus::kGoalBlocked;

  // A cell's g, heap place and escape flag count only when it was touched in this plan: no pass
  // over the whole grid per plan.
  if (++generation_ == 0) {
    std::fill(visit_.begin(), visit_.end(), 0U);
    generation_ = 1;
  }
  const auto touch = [&](std::uint32_t k) {
    if (visit_[k] == generation_) return;
    visit_[k] = generation_;
    g_[k] = kInfF;
    heap_pos_[k] = kNotInHeap;
    escaping_[k] = 0;
  };
  heap_size_ = 0;

  const auto s = static_cast<std::uint32_t>(grid.index(*s_cell));
  const auto t = static_cast<std::uint32_t>(grid.index(*g_cell));
  touch(s);
  g_[s] = 0.0F;
  // A weight below 1 or not finite would only slow the search: taken as 1.
  const float weight =
      heuristic_weight > 1.0F && std::isfinite(heuristic_weight) ? heuristic_weight : 1.0F;
  const auto heuristic = [&](std::uint32_t r, std::uint32_t c) {
    return weight * octile(r, c, g_cell->row, g_cell->col);
  };
  h_[s] = heuristic(s_cell->row, s_cell->col);
  parent_[s] = s;
  escaping_[s] = grid.at(*s_cell) != CellState::kFree ? 1 : 0;
  heap_push(s, h_[s]);

  const auto passable = [&](std::uint32_t from, std::int64_t r, std::int64_t c) {
    if (r < 0 || c < 0 || r >= rows_ || c >= cols_) return false;
    const auto st = grid.at({static_cast<std::uint32_t>(r), static_cast<std::uint32_t>(c)});
    if (st == CellState::kFree) return true;
    if (st != CellState::kInflated || escaping_[from] == 0) return false;
    return grid.depth == nullptr ||
           grid.depth[static_cast<std::size_t>(r) * cols_ + static_cast<std::size_t>(c)] <=
               grid.depth[from];
  };

  const auto nb_index = [&](std::int64_t r, std::int64_t c) {
    return static_cast<std::uint32_t>(r * cols_ + c);
  };
  bool found = false;
  while (heap_size_ > 0) {
    if (expanded_ >= max_expanded) return PlanStatus::kBudget;
    const std::uint32_t cur = heap_pop();
    ++expanded_;
    if (cur == t) {
      found = true;
      break;
    }
    const std::int64_t r = cur / cols_;
    const std::int64_t c = cur % cols_;
    for (int dr = -1; dr <= 1; ++dr) {
      for (int dc = -1; dc <= 1; ++dc) {
        if (dr == 0 && dc == 0) continue;
        const std::int64_t nr = r + dr;
        const std::int64_t nc = c + dc;
        if (!passable(cur, nr, nc)) continue;
        // No corner cutting: both cells beside a diagonal move must be passable too.
        if (dr != 0 && dc != 0 && (!passable(cur, r + dr, c) || !passable(cur, r, c + dc))) {
          continue;
        }
        const auto nb = nb_index(nr, nc);
        touch(nb);
        if (heap_pos_[nb] == kClosed) continue;
        float step = dr != 0 && dc != 0 ? kSqrt2 : 1.0F;
        if (grid.cost != nullptr) {
          step *= 1.0F + static_cast<float>(grid.cost[nb]) * kCostUnit;
        }
        const float cand = g_[cur] + step;
        if (!(cand < g_[nb])) continue;
        g_[nb] = cand;
        parent_[nb] = cur;
        const bool nb_free = grid.at({static_cast<std::uint32_t>(nr),
                                      static_cast<std::uint32_t>(nc)}) == CellState::kFree;
        escaping_[nb] = nb_free ? 0 : 1;
        if (heap_pos_[nb] == kNotInHeap) {
          h_[nb] = heuristic(static_cast<std::uint32_t>(nr), static_cast<std::uint32_t>(nc));
          heap_push(nb, cand + h_[nb]);
        } else {
          heap_decrease(nb, cand + h_[nb]);
        }
      }
    }
  }
  if (!found) return PlanStatus::kNoPath;

  // Walk back from the goal, then emit start, the turning cells, goal.
  std::size_t n = 0;
  for (std::uint32_t k = t;; k = parent_[k]) {
    cells_[n++] = k;
    if (k == s) break;
  }
  path_.push_back(start);
  for (std::size_t i = n - 1; i-- > 1;) {  // interior cells, start side first
    const std::uint32_t prev = cells_[i + 1];
    const std::uint32_t here = cells_[i];
    const std::uint32_t next = cells_[i - 1];
    const auto dir = [&](std::uint32_t a, std::uint32_t b) {
      return std::pair<std::int64_t, std::int64_t>{
          static_cast<std::int64_t>(b / cols_) - static_cast<std::int64_t>(a / cols_),
          static_cast<std::int64_t>(b % cols_) - static_cast<std::int64_t>(a % cols_)};
    };
    if (dir(prev, here) == dir(here, next)) continue;  // collinear: not a turning point
    path_.push_back(grid.center_of({here / cols_, here % cols_}));
  }
  path_.push_back(goal);
  return PlanStatus::kOk;
}

}  // namespace coxswain::guidance
