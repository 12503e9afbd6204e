// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/nav_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include "coxswain/core/angles.hpp"

namespace coxswain::guidance {
namespace {
constexpr std::uint8_t kDeepest = 255;  // an occupied cell's inflation depth

bool finite_pos(double v) { return std::isfinite(v) && v > 0.0; }
bool finite_nonneg(double v) { return std::isfinite(v) && v >= 0.0; }

}  // namespace

std::optional<std::string> NavMapParams::validate() const {
  if (!finite_pos(resolution_m) || resolution_m < 0.05) return "map: resolution_m >= 0.05";
  if (!finite_nonneg(margin_m)) return "map: margin_m >= 0";
  if (!finite_pos(size_north_m) || !finite_pos(size_east_m)) return "map: size must be > 0";
  if (!(hit_log_odds > 0.0F) || !std::isfinite(hit_log_odds)) return "map: hit_log_odds > 0";
  if (!(miss_log_odds < 0.0F) || !std::isfinite(miss_log_odds)) return "map: miss_log_odds < 0";
  if (!(min_log_odds < 0.0F && max_log_odds > 0.0F) || !std::isfinite(min_log_odds) ||
      !std::isfinite(max_log_odds)) {
    return "map: min_log_odds < 0 < max_log_odds";
  }
  if (!(occupied_log_odds > min_log_odds && occupied_log_odds <= max_log_odds)) {
    return "map: occupied_log_odds in (min_log_odds, max_log_odds]";
  }
  if (!finite_pos(max_range_m) || !finite_nonneg(min_range_m) || min_range_m >= max_range_m) {
    return "map: 0 <= min_range_m < max_range_m";
  }
  return {};
}

std::optional<std::string> MapPlannerParams::validate() const {
  if (!finite_pos(replan_period_s)) return "planner: replan_period_s > 0";
  if (!finite_nonneg(clearance_m) || clearance_m > 3.0) return "planner: clearance_m in [0, 3]";
  if (!finite_pos(lookahead_m)) return "planner: lookahead_m > 0";
  if (max_expansions == 0) return "planner: max_expansions > 0";
  if (!finite_nonneg(goal_search_m) || goal_search_m > 5.0) {
    return "planner: goal_search_m in [0, 5]";
  }
  if (!finite_nonneg(stop_s) || !finite_nonneg(back_off_s) || !finite_nonneg(look_s)) {
    return "planner: stop_s, back_off_s and look_s >= 0";
  }
  if (!(back_off_thrust_frac >= 0.0 && back_off_thrust_frac <= 1.0) ||
      !(look_thrust_frac >= 0.0 && look_thrust_frac <= 1.0)) {
    return "planner: thrust fractions in [0, 1]";
  }
  if (!std::isfinite(look_turn_deg) || std::abs(look_turn_deg) > 180.0) {
    return "planner: look_turn_deg in [-180, 180]";
  }
  if (!finite_nonneg(stuck_s) || !finite_pos(stuck_distance_m)) {
    return "planner: stuck_s >= 0 and stuck_distance_m > 0";
  }
  return {};
}

std::optional<std::string> GateParams::validate() const {
  if (!finite_pos(width_m)) return "gates: width_m > 0";
  if (!finite_nonneg(width_tolerance_m) || width_tolerance_m >= width_m) {
    return "gates: 0 <= width_tolerance_m < width_m";
  }
  if (!finite_pos(search_radius_m)) return "gates: search_radius_m > 0";
  if (!std::isfinite(max_angle_deg) || max_angle_deg < 0.0 || max_angle_deg > 90.0) {
    return "gates: max_angle_deg in [0, 90]";
  }
  if (!finite_pos(max_buoy_length_m)) return "gates: max_buoy_length_m > 0";
  if (!finite_pos(track_gate_m)) return "gates: track_gate_m > 0";
  if (!finite_pos(approach_m)) return "gates: approach_m > 0";
  return {};
}

std::optional<std::string> PlanningConfig::validate() const {
  if (auto e = map.validate()) return e;
  if (auto e = planner.validate()) return e;
  if (auto e = gates.validate()) return e;
  if (!boundary.empty() && boundary.size() < 3) return "boundary: needs at least 3 corners";
  for (const auto& p : no_go) {
    if (p.size() < 3) return "no_go: each polygon needs at least 3 corners";
  }
  return {};
}

bool inside_polygon(std::span<const core::NavPoint> polygon, core::NavPoint p) {
  bool in = false;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const core::NavPoint a = polygon[i];
    const core::NavPoint b = polygon[j];
    if ((a.east_m > p.east_m) != (b.east_m > p.east_m)) {
      const double n_at =
          a.north_m + (p.east_m - a.east_m) * (b.north_m - a.north_m) / (b.east_m - a.east_m);
      if (p.north_m < n_at) in = !in;
    }
  }
  return in;
}

NavMap::NavMap(const NavMapParams& params, std::span<const core::NavPoint> boundary,
               std::span<const std::vector<core::NavPoint>> no_go,
               std::span<const core::NavPoint> extent)
    : params_(params) {
  if (auto e = params.validate()) throw std::invalid_argument(*e);
  if (!boundary.empty() && boundary.size() < 3) {
    throw std::invalid_argument("map: the boundary needs at least 3 corners");
  }
  double n0 = -0.5 * params.size_north_m;
  double n1 = 0.5 * params.size_north_m;
  double e0 = -0.5 * params.size_east_m;
  double e1 = 0.5 * params.size_east_m;
  if (boundary.empty()) {
    for (const core::NavPoint& p : extent) {
      n0 = std::min(n0, p.north_m - params.margin_m);
      n1 = std::max(n1, p.north_m + params.margin_m);
      e0 = std::min(e0, p.east_m - params.margin_m);
      e1 = std::max(e1, p.east_m + params.margin_m);
    }
  } else {
    n0 = e0 = std::numeric_limits<double>::infinity();
    n1 = e1 = -std::numeric_limits<double>::infinity();
    for (const core::NavPoint& p : boundary) {
      n0 = std::min(n0, p.north_m);
      n1 = std::max(n1, p.north_m);
      e0 = std::min(e0, p.east_m);
      e1 = std::max(e1, p.east_m);
    }
    n0 -= params.margin_m;
    n1 += params.margin_m;
    e0 -= params.margin_m;
    e1 += params.margin_m;
  }
  if (!std::isfinite(n0) || !std::isfinite(n1) || !std::isfinite(e0) || !std::isfinite(e1)) {
    throw std::invalid_argument("map: boundary corners must be finite");
  }
  const double rows = std::ceil((n1 - n0) / params.resolution_m);
  const double cols = std::ceil((e1 - e0) / params.resolution_m);
  if (!(rows >= 1.0 && cols >= 1.0 &&
        rows * cols <= static_cast<double>(NavMapParams::kMaxCells))) {
    throw std::invalid_argument("map: too many cells (area / resolution)");
  }
  rows_ = static_cast<std::uint32_t>(rows);
  cols_ = static_cast<std::uint32_t>(cols);
  origin_ = {n0, e0};
  const std::size_t n = static_cast<std::size_t>(rows_) * cols_;
  log_odds_.assign(n, 0.0F);
  known_.assign(n, 0);
  hit_stamp_.assign(n, 0);
  beam_ends_.assign(msg::LidarScan::kMaxPoints, {0, 0});
  occupied_list_.assign(n, 0);
  occupied_pos_.assign(n, -1);
  for (std::uint32_t r = 0; r < rows_; ++r) {
    for (std::uint32_t c = 0; c < cols_; ++c) {
      const core::NavPoint p = center_of({r, c});
      bool k = !boundary.empty() && !inside_polygon(boundary, p);
      for (const auto& poly : no_go) {
        if (k) break;
        if (poly.size() >= 3) k = inside_polygon(poly, p);
      }
      known_[index({r, c})] = k ? 1 : 0;
    }
  }
}

std::optional<GridCell> NavMap::cell_of(core::NavPoint p) const {
  const double r = std::floor((p.north_m - origin_.north_m) / params_.resolution_m);
  const double c = std::floor((p.east_m - origin_.east_m) / params_.resolution_m);
  if (!(r >= 0.0 && c >= 0.0 && r < rows_ && c < cols_)) return std::nullopt;
  return GridCell{static_cast<std::uint32_t>(r), static_cast<std::uint32_t>(c)};
}

core::NavPoint NavMap::center_of(GridCell c) const {
  return {origin_.north_m + (c.row + 0.5) * params_.resolution_m,
          origin_.east_m + (c.col + 0.5) * params_.resolution_m};
}

void NavMap::clear_evidence() {
  std::fill(log_odds_.begin(), log_odds_.end(), 0.0F);
  for (std::size_t i = 0; i < occupied_count_; ++i) occupied_pos_[occupied_list_[i]] = -1;
  occupied_count_ = 0;
}

void NavMap::set_log_odds(std::size_t k, float v) {
  const bool was = log_odds_[k] >= params_.occupied_log_odds;
  log_odds_[k] = std::clamp(v, params_.min_log_odds, params_.max_log_odds);
  const bool now = log_odds_[k] >= params_.occupied_log_odds;
  if (was == now) return;
  if (now) {
    occupied_pos_[k] = static_cast<std::int32_t>(occupied_count_);
    occupied_list_[occupied_count_++] = static_cast<std::uint32_t>(k);
  } else {
    const auto pos = static_cast<std::size_t>(occupied_pos_[k]);
    const std::uint32_t last = occupied_list_[--occupied_count_];
    occupied_list_[pos] = last;
    occupied_pos_[last] = static_cast<std::int32_t>(pos);
    occupied_pos_[k] = -1;
  }
}

// Bresenham from (r0, c0) to (r1, c1) in cell coordinates, which may lie outside the grid (those
// cells are skipped). Every cell before the last is passed through (a miss unless a beam ended in
// it this scan); the last is a hit when `hit`, else passed through as well.
void NavMap::trace(int r0, int c0, int r1, int c1, bool hit) {
  const int dr = std::abs(r1 - r0);
  const int dc = std::abs(c1 - c0);
  const int sr = r0 < r1 ? 1 : -1;
  const int sc = c0 < c1 ? 1 : -1;
  int err = dc - dr;
  int r = r0;
  int c = c0;
  const auto rows = static_cast<int>(rows_);
  const auto cols = static_cast<int>(cols_);
  for (;;) {
    const bool last = r == r1 && c == c1;
    if (r >= 0 && c >= 0 && r < rows && c < cols) {
      const auto k = static_cast<std::size_t>(r) * cols_ + static_cast<std::size_t>(c);
      if (last && hit) {
        set_log_odds(k, log_odds_[k] + params_.hit_log_odds);
      } else if (log_odds_[k] > params_.min_log_odds && hit_stamp_[k] != scan_number_) {
        // Cells near the boat are passed by most beams: those already clamped free cost nothing.
        set_log_odds(k, log_odds_[k] + params_.miss_log_odds);
      }
    }
    if (last) break;
    const int e2 = 2 * err;
    if (e2 > -dr) {
      err -= dr;
      c += sc;
    }
    if (e2 < dc) {
      err += dc;
      r += sr;
    }
  }
}

void NavMap::add_scan(const msg::LidarScan& scan, const core::NavPose& pose,
                      const perception::HullBox& hull) {
  ++scan_number_;
  if (scan_number_ == 0) {  // wrapped: old stamps could alias the new number
    std::fill(hit_stamp_.begin(), hit_stamp_.end(), 0U);
    scan_number_ = 1;
  }
  const std::uint32_t n = std::min<std::uint32_t>(scan.point_count, msg::LidarScan::kMaxPoints);
  const double res = params_.resolution_m;
  const double fr0 = (pose.position.north_m - origin_.north_m) / res;
  const double fc0 = (pose.position.east_m - origin_.east_m) / res;
  if (!std::isfinite(fr0) || !std::isfinite(fc0) || std::abs(fr0) > 1e6 || std::abs(fc0) > 1e6) {
    return;
  }
  const auto r0 = static_cast<int>(std::floor(fr0));
  const auto c0 = static_cast<int>(std::floor(fc0));
  const double h = core::deg_to_rad(pose.heading_deg);
  const double max_range =
      scan.max_range_m > 0.0F ? std::min(params_.max_range_m, static_cast<double>(scan.max_range_m))
                              : params_.max_range_m;
  // Where a beam ends, or nothing when it is to be skipped.
  const auto end_of = [&](const msg::LidarPoint& p, bool& hit, int& r1, int& c1) {
    const double range = static_cast<double>(p.range_m);
    if (!(range > params_.min_range_m) || !std::isfinite(range)) return false;
    const double b = core::deg_to_rad(static_cast<double>(p.bearing_deg));
    const double fwd = range * std::cos(b);
    const double stb = range * std::sin(b);
    if (hull.contains(fwd, stb)) return false;
    hit = range <= max_range;
    const double reach = hit ? range : max_range;
    const double a = h + b;
    r1 = static_cast<int>(std::floor(fr0 + reach * std::cos(a) / res));
    c1 = static_cast<int>(std::floor(fc0 + reach * std::sin(a) / res));
    return true;
  };
  // Hits first, so a beam grazing a buoy does not clear the cell another beam ended in. The ends
  // are worked out once (trigonometry is most of the cost) and kept for the second pass.
  std::size_t beams = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    bool hit = false;
    int r1 = 0;
    int c1 = 0;
    if (!end_of(scan.points[i], hit, r1, c1)) continue;
    if (r1 != r0 || c1 != c0) beam_ends_[beams++] = {r1, c1};
    if (!hit) continue;
    if (r1 < 0 || c1 < 0 || r1 >= static_cast<int>(rows_) || c1 >= static_cast<int>(cols_)) {
      continue;
    }
    const auto k = static_cast<std::size_t>(r1) * cols_ + static_cast<std::size_t>(c1);
    if (hit_stamp_[k] == scan_number_) continue;  // one hit per cell per scan
    hit_stamp_[k] = scan_number_;
    set_log_odds(k, log_odds_[k] + params_.hit_log_odds);
  }
  // The hit cells were raised above; trace the cells before them as misses.
  for (std::size_t i = 0; i < beams; ++i) trace(r0, c0, beam_ends_[i].r, beam_ends_[i].c, false);
}

MapPlanner::MapPlanner(const NavMap& map, const MapPlannerParams& params, double half_beam_m)
    : params_(params),
      resolution_m_(map.params().resolution_m),
      origin_(map.origin()),
      rows_(map.rows()),
      cols_(map.cols()),
      known_state_(static_cast<std::size_t>(rows_) * cols_, CellState::kFree),
      state_(known_state_.size(), CellState::kFree),
      known_depth_(known_state_.size(), 0),
      depth_(known_state_.size(), 0),
      astar_(rows_, cols_) {
  if (auto e = params.validate()) throw std::invalid_argument(*e);
  if (!std::isfinite(half_beam_m) || half_beam_m < 0.0) {
    throw std::invalid_argument("planner: half beam must be >= 0");
  }
  // An obstacle may sit anywhere in its cell, so reach half a cell further than the radius.
  const double reach = (half_beam_m + params.clearance_m) / resolution_m_ + 0.5;
  const int n = static_cast<int>(std::ceil(reach));
  for (int dr = -n; dr <= n; ++dr) {
    for (int dc = -n; dc <= n; ++dc) {
      const double d = std::hypot(dr, dc);
      if ((dr != 0 || dc != 0) && d <= reach) {
        const double deep = std::clamp(1.0 + (reach - d) * 16.0, 1.0, 254.0);
        stencil_.push_back({dr, dc, static_cast<std::uint8_t>(deep)});
      }
    }
  }
  const int g = static_cast<int>(std::ceil(params.goal_search_m / resolution_m_));
  for (int dr = -g; dr <= g; ++dr) {
    for (int dc = -g; dc <= g; ++dc) {
      if (std::hypot(dr, dc) <= params.goal_search_m / resolution_m_)
        goal_ring_.push_back({dr, dc, 0});
    }
  }
  std::stable_sort(goal_ring_.begin(), goal_ring_.end(), [](Offset a, Offset b) {
    return a.dr * a.dr + a.dc * a.dc < b.dr * b.dr + b.dc * b.dc;
  });
  // The known layer never changes: inflate it once. Cells whose four neighbours are all known
  // are interior and cannot inflate anything their neighbours do not.
  const auto rows = static_cast<int>(rows_);
  const auto cols = static_cast<int>(cols_);
  const auto known = [&](int r, int c) {
    return r < 0 || c < 0 || r >= rows || c >= cols ||
           map.known(static_cast<std::size_t>(r) * cols_ + static_cast<std::size_t>(c));
  };
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (!known(r, c)) continue;
      known_state_[static_cast<std::size_t>(r) * cols_ + static_cast<std::size_t>(c)] =
          CellState::kOccupied;
      known_depth_[static_cast<std::size_t>(r) * cols_ + static_cast<std::size_t>(c)] = kDeepest;
      if (known(r - 1, c) && known(r + 1, c) && known(r, c - 1) && known(r, c + 1)) continue;
      for (const Offset& o : stencil_) {
        const int rr = r + o.dr;
        const int cc = c + o.dc;
        if (rr < 0 || cc < 0 || rr >= rows || cc >= cols) continue;
        const std::size_t kk = static_cast<std::size_t>(rr) * cols_ + static_cast<std::size_t>(cc);
        if (known_state_[kk] == CellState::kFree) known_state_[kk] = CellState::kInflated;
        known_depth_[kk] = std::max(known_depth_[kk], o.depth);
      }
    }
  }
}

GridView MapPlanner::view() const {
  return {rows_, cols_, resolution_m_, origin_, state_.data(), depth_.data()};
}

void MapPlanner::inflate(const NavMap& map) {
  std::copy(known_state_.begin(), known_state_.end(), state_.begin());
  std::copy(known_depth_.begin(), known_depth_.end(), depth_.begin());
  const auto rows = static_cast<int>(rows_);
  const auto cols = static_cast<int>(cols_);
  for (const std::uint32_t k : map.lidar_occupied()) {
    state_[k] = CellState::kOccupied;
    depth_[k] = kDeepest;
    const auto r = static_cast<int>(k / cols_);
    const auto c = static_cast<int>(k % cols_);
    for (const Offset& o : stencil_) {
      const int rr = r + o.dr;
      const int cc = c + o.dc;
      if (rr < 0 || cc < 0 || rr >= rows || cc >= cols) continue;
      const std::size_t kk = static_cast<std::size_t>(rr) * cols_ + static_cast<std::size_t>(cc);
      if (state_[kk] == CellState::kFree) state_[kk] = CellState::kInflated;
      depth_[kk] = std::max(depth_[kk], o.depth);
    }
  }
}

PlanStatus MapPlanner::plan(const NavMap& map, core::NavPoint start, core::NavPoint goal) {
  inflate(map);
  const GridView v = view();
  core::NavPoint g = goal;
  if (!v.cell_of(g) && v.cell_of(start)) {
    // Off the map: aim where the straight line to it leaves the map (bisection, 1 cm).
    double lo = 0.0;
    double hi = 1.0;
    for (int i = 0; i < 24; ++i) {
      const double mid = 0.5 * (lo + hi);
      const core::NavPoint q{start.north_m + mid * (goal.north_m - start.north_m),
                             start.east_m + mid * (goal.east_m - start.east_m)};
      (v.cell_of(q) ? lo : hi) = mid;
    }
    g = {start.north_m + lo * (goal.north_m - start.north_m),
         start.east_m + lo * (goal.east_m - start.east_m)};
  }
  if (const auto gc = v.cell_of(goal); gc && v.at(*gc) != CellState::kFree) {
    bool moved = false;
    for (const Offset& o : goal_ring_) {
      const auto r = static_cast<std::int64_t>(gc->row) + o.dr;
      const auto c = static_cast<std::int64_t>(gc->col) + o.dc;
      if (r < 0 || c < 0 || r >= rows_ || c >= cols_) continue;
      const GridCell cell{static_cast<std::uint32_t>(r), static_cast<std::uint32_t>(c)};
      if (v.at(cell) != CellState::kFree) continue;
      g = v.center_of(cell);
      moved = true;
      break;
    }
    if (!moved) {
      status_ = PlanStatus::kGoalBlocked;
      return status_;
    }
  }
  status_ = astar_.plan(v, start, g, params_.max_expansions);
  return status_;
}

std::optional<core::NavPoint> MapPlanner::subgoal(core::NavPoint position) const {
  const std::vector<core::NavPoint>& p = astar_.path();
  if (status_ != PlanStatus::kOk || p.empty()) return std::nullopt;
  if (p.size() == 1) return p.front();
  // The nearest point of the path.
  std::size_t best_i = 0;
  double best_t = 0.0;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < p.size(); ++i) {
    const double dn = p[i + 1].north_m - p[i].north_m;
    const double de = p[i + 1].east_m - p[i].east_m;
    const double len2 = dn * dn + de * de;
    double t = 0.0;
    if (len2 > 0.0) {
      t = std::clamp(
          ((position.north_m - p[i].north_m) * dn + (position.east_m - p[i].east_m) * de) / len2,
          0.0, 1.0);
    }
    const double d = std::hypot(p[i].north_m + t * dn - position.north_m,
                                p[i].east_m + t * de - position.east_m);
    if (d < best_d) {
      best_d = d;
      best_i = i;
      best_t = t;
    }
  }
  // Walk the look-ahead along the path from there.
  double left = params_.lookahead_m;
  core::NavPoint at{p[best_i].north_m + best_t * (p[best_i + 1].north_m - p[best_i].north_m),
                    p[best_i].east_m + best_t * (p[best_i + 1].east_m - p[best_i].east_m)};
  for (std::size_t i = best_i; i + 1 < p.size(); ++i) {
    const double seg = core::distance_m(at, p[i + 1]);
    if (seg >= left && seg > 0.0) {
      const double f = left / seg;
      return core::NavPoint{at.north_m + f * (p[i + 1].north_m - at.north_m),
                            at.east_m + f * (p[i + 1].east_m - at.east_m)};
    }
    left -= seg;
    at = p[i + 1];
  }
  return p.back();
}

}  // namespace coxswain::guidance
