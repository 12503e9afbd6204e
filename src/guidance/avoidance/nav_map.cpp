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
constexpr std::uint32_t kFar = std::numeric_limits<std::uint32_t>::max();  // beyond the band

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
  if (!finite_nonneg(no_return_near_m) || no_return_near_m > 5.0) {
    return "map: no_return_near_m in [0, 5]";
  }
  return {};
}

std::optional<std::string> MapPlannerParams::validate() const {
  if (!finite_pos(replan_period_s)) return "planner: replan_period_s > 0";
  if (!finite_nonneg(clearance_m) || clearance_m > 3.0) return "planner: clearance_m in [0, 3]";
  if (!finite_nonneg(soft_clearance_m) || soft_clearance_m > 10.0) {
    return "planner: soft_clearance_m in [0, 10]";
  }
  if (!finite_nonneg(goal_fade_m) || goal_fade_m > 50.0) return "planner: goal_fade_m in [0, 50]";
  if (!finite_nonneg(sight_full_speed_m) || sight_full_speed_m > 100.0) {
    return "planner: sight_full_speed_m in [0, 100]";
  }
  if (!(heuristic_weight >= 1.0 && heuristic_weight <= 5.0)) {
    return "planner: heuristic_weight in [1, 5]";
  }
  if (!std::isfinite(turn_slow_deg) || turn_slow_deg < 0.0 || turn_slow_deg >= 90.0) {
    return "planner: turn_slow_deg in [0, 90)";
  }
  if (!(turn_min_speed_factor > 0.0 && turn_min_speed_factor <= 1.0)) {
    return "planner: turn_min_speed_factor in (0, 1]";
  }
  if (!(sight_min_speed_factor > 0.0 && sight_min_speed_factor <= 1.0)) {
    return "planner: sight_min_speed_factor in (0, 1]";
  }
  if (!finite_nonneg(clearance_cost) || clearance_cost > 15.0 || !finite_nonneg(unknown_cost) ||
      unknown_cost > 15.0) {
    return "planner: clearance_cost and unknown_cost in [0, 15]";
  }
  if (!finite_pos(lookahead_m)) return "planner: lookahead_m > 0";
  if (!finite_nonneg(line_of_sight_min_m)) return "planner: line_of_sight_min_m >= 0";
  if (max_expansions == 0) return "planner: max_expansions > 0";
  if (!finite_nonneg(goal_search_m) || goal_search_m > 5.0) {
    return "planner: goal_search_m in [0, 5]";
  }
  if (!finite_nonneg(stop_s) || !finite_nonneg(back_off_s) || !finite_nonneg(look_s)) {
    return "planner: stop_s, back_off_s and look_s >= 0";
  }
  if (!(back_off_thrust_frac >= 0.0 && back_off_thrust_frac <= 1.0) ||
      !(look_thrust_frac >= 0.0 && look_thrust_frac <= 1.0) ||
      !(astern_thrust_frac >= 0.0 && astern_thrust_frac <= 1.0)) {
    return "planner: thrust fractions in [0, 1]";
  }
  if (!std::isfinite(look_turn_deg) || std::abs(look_turn_deg) > 180.0) {
    return "planner: look_turn_deg in [-180, 180]";
  }
  if (!finite_nonneg(stuck_s) || !finite_pos(stuck_distance_m)) {
    return "planner: stuck_s >= 0 and stuck_distance_m > 0";
  }
  if (!std::isfinite(astern_behind_deg) || astern_behind_deg < 90.0 || astern_behind_deg > 180.0) {
    return "planner: astern_behind_deg in [90, 180]";
  }
  if (!finite_nonneg(astern_look_m) || !finite_nonneg(astern_max_m)) {
    return "planner: astern_look_m and astern_max_m >= 0";
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
  if (!finite_nonneg(wall_m)) return "gates: wall_m >= 0";
  return {};
}

std::optional<std::string> PlanningConfig::validate() const {
  if (auto e = map.validate()) return e;
  if (auto e = planner.validate()) return e;
  if (auto e = gates.validate()) return e;
  if (auto e = turn_side.validate()) return "turn_side: " + *e;
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
  build_sweep();
  trig_.resize(2 * (360 * static_cast<std::size_t>(kTrigStepsPerDeg) + 1));
  for (std::size_t i = 0; i < trig_.size() / 2; ++i) {
    const double a = core::deg_to_rad(-180.0 + static_cast<double>(i) / kTrigStepsPerDeg);
    trig_[2 * i] = std::cos(a);
    trig_[2 * i + 1] = std::sin(a);
  }
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

void NavMap::build_sweep() {
  const double res = params_.resolution_m;
  const double half_diag = res * std::sqrt(0.5);
  const double bin_rad = 2.0 * core::kPi / kBins;
  // Cells nearer than min_range_m (or a cell and a half) are left to the avoidance: their beams
  // are dropped, and they span too many bins to say anything.
  const double nearest = std::max(params_.min_range_m, 1.5 * res);
  const int n = static_cast<int>(std::ceil(params_.max_range_m / res)) + 1;
  std::uint32_t widest = 1;
  sweep_start_.assign(kSubCells * kSubCells + 1, 0);
  for (int si = 0; si < kSubCells; ++si) {
    for (int sj = 0; sj < kSubCells; ++sj) {
      const double bn = (si + 0.5) / kSubCells;  // the boat within its cell, in cells
      const double be = (sj + 0.5) / kSubCells;
      const std::size_t first = sweep_cells_.size();
      for (int dr = -n; dr <= n; ++dr) {
        for (int dc = -n; dc <= n; ++dc) {
          const double north = (dr + 0.5 - bn) * res;
          const double east = (dc + 0.5 - be) * res;
          const double d = std::hypot(north, east);
          if (d < nearest || d + half_diag > params_.max_range_m) continue;
          double bearing = std::atan2(east, north);
          if (bearing < 0.0) bearing += 2.0 * core::kPi;
          const double half = std::asin(std::min(1.0, half_diag / d));
          const auto lo = static_cast<std::int64_t>(std::floor((bearing - half) / bin_rad));
          const auto hi = static_cast<std::int64_t>(std::floor((bearing + half) / bin_rad));
          const auto span = static_cast<std::uint32_t>(hi - lo + 1);
          widest = std::max(widest, span);
          const auto wrapped = static_cast<std::uint32_t>((lo % kBins + kBins) % kBins);
          sweep_cells_.push_back({static_cast<std::int16_t>(dr), static_cast<std::int16_t>(dc),
                                  static_cast<std::uint16_t>(wrapped),
                                  static_cast<std::uint16_t>(span),
                                  static_cast<float>(d + half_diag)});
        }
      }
      std::stable_sort(sweep_cells_.begin() + static_cast<std::ptrdiff_t>(first),
                       sweep_cells_.end(),
                       [](const SweepCell& a, const SweepCell& b) { return a.far_m < b.far_m; });
      sweep_start_[static_cast<std::size_t>(si * kSubCells + sj) + 1] = sweep_cells_.size();
    }
  }
  levels_ = 1;
  while ((2U << (levels_ - 1)) <= widest) ++levels_;
  range_levels_.assign(static_cast<std::size_t>(levels_) * 2 * kBins, 0.0F);
}

bool NavMap::unit_of(double bearing_deg, double& cos_out, double& sin_out) const {
  if (!std::isfinite(bearing_deg)) return false;
  if (!(bearing_deg >= -180.0 && bearing_deg < 180.0)) bearing_deg = core::wrap_deg(bearing_deg);
  // The entry at or below the bearing, then the turn by the remainder d (< 1.8e-3 rad): to
  // second order in cos and third in sin, the terms left out are below 4e-13.
  auto i = static_cast<std::size_t>((bearing_deg + 180.0) * kTrigStepsPerDeg);
  i = std::min(i, trig_.size() / 2 - 2);
  const double d =
      core::deg_to_rad(bearing_deg - (static_cast<double>(i) / kTrigStepsPerDeg - 180.0));
  const double c0 = trig_[2 * i];
  const double s0 = trig_[2 * i + 1];
  const double cd = 1.0 - 0.5 * d * d;
  const double sd = d - d * d * d / 6.0;
  cos_out = c0 * cd - s0 * sd;
  sin_out = s0 * cd + c0 * sd;
  return true;
}

float NavMap::shortest_beam(std::uint32_t lo, std::uint32_t span) const {
  std::uint32_t level = 0;
  while ((2U << level) <= span) ++level;
  const float* row = range_levels_.data() + static_cast<std::size_t>(level) * 2 * kBins;
  return std::min(row[lo], row[lo + span - (1U << level)]);
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
  if (!std::isfinite(fr0) || !std::isfinite(fc0) || std::abs(fr0) > 1e6 || std::abs(fc0) > 1e6 ||
      !std::isfinite(pose.heading_deg)) {
    return;
  }
  const auto r0 = static_cast<int>(std::floor(fr0));
  const auto c0 = static_cast<int>(std::floor(fc0));
  const double h = core::deg_to_rad(pose.heading_deg);
  const double max_range =
      scan.max_range_m > 0.0F ? std::min(params_.max_range_m, static_cast<double>(scan.max_range_m))
                              : params_.max_range_m;
  const double bins_per_rad = kBins / (2.0 * core::kPi);
  float* ranges = range_levels_.data();
  std::fill(ranges, ranges + kBins, -1.0F);  // -1: no beam in this bin
  bool any = false;
  // Whether this scan's beams without a return may clear: not when anything outside the hull
  // is so near that a wall may stand within the scanner's least range.
  bool no_return_clears = params_.no_return_clears;
  for (std::uint32_t i = 0; i < n && no_return_clears; ++i) {
    const msg::LidarPoint& p = scan.points[i];
    const auto range = static_cast<double>(p.range_m);
    if (!(range > 0.0) || !(range < params_.no_return_near_m)) continue;
    double cb = 0.0;
    double sb = 0.0;
    if (!unit_of(static_cast<double>(p.bearing_deg), cb, sb)) continue;
    no_return_clears = hull.contains(range * cb, range * sb);
  }
  const double ch = std::cos(h);
  const double sh = std::sin(h);
  for (std::uint32_t i = 0; i < n; ++i) {
    const msg::LidarPoint& p = scan.points[i];
    const bool no_return = p.range_m == 0.0F;
    const double range = no_return ? max_range + 1.0 : static_cast<double>(p.range_m);
    if (no_return && !no_return_clears) continue;
    if (!(range > params_.min_range_m) || !std::isfinite(range)) continue;
    double cb = 0.0;
    double sb = 0.0;
    if (!unit_of(static_cast<double>(p.bearing_deg), cb, sb)) continue;
    const double a = h + core::deg_to_rad(static_cast<double>(p.bearing_deg));
    const bool hit = range <= max_range;
    const auto reach = static_cast<float>(hit ? range : max_range);
    auto bin = static_cast<std::int64_t>(std::floor(a * bins_per_rad)) % kBins;
    if (bin < 0) bin += kBins;
    float& slot = ranges[bin];
    slot = slot < 0.0F ? reach : std::min(slot, reach);
    any = true;
    // A return inside the hull box marks nothing (it is the boat, or something so near astern
    // the two cannot be told apart), but the beam saw no farther: were it dropped, its bin
    // would take the beams either side, and they would clear a buoy lying astern.
    if (!hit || hull.contains(range * cb, range * sb)) continue;
    // The beam's direction in the navigation frame: its body bearing turned by the heading.
    const double ca = cb * ch - sb * sh;
    const double sa = sb * ch + cb * sh;
    const auto r1 = static_cast<int>(std::floor(fr0 + range * ca / res));
    const auto c1 = static_cast<int>(std::floor(fc0 + range * sa / res));
    if (r1 < 0 || c1 < 0 || r1 >= static_cast<int>(rows_) || c1 >= static_cast<int>(cols_)) {
      continue;
    }
    const auto k = static_cast<std::size_t>(r1) * cols_ + static_cast<std::size_t>(c1);
    if (hit_stamp_[k] == scan_number_) continue;  // one hit per cell per scan
    hit_stamp_[k] = scan_number_;
    set_log_odds(k, log_odds_[k] + params_.hit_log_odds);
  }
  if (!any) return;
  // A bin between beams takes the shorter of the beams either side (the scanner's step may be
  // coarser than the bins); then the table is doubled so a span never wraps.
  std::uint32_t first = 0;
  while (ranges[first] < 0.0F) ++first;
  float last = ranges[first];
  for (std::uint32_t i = 1; i <= kBins; ++i) {
    const std::uint32_t b = (first + i) % kBins;
    if (ranges[b] < 0.0F) {
      ranges[b] = -2.0F - last;  // remembered, made whole on the way back
    } else {
      last = ranges[b];
    }
  }
  last = ranges[first];
  for (std::uint32_t i = 1; i <= kBins; ++i) {
    const std::uint32_t b = (first + kBins - i) % kBins;
    if (ranges[b] <= -2.0F) {
      ranges[b] = std::min(-2.0F - ranges[b], last);
    } else {
      last = ranges[b];
    }
  }
  std::copy(ranges, ranges + kBins, ranges + kBins);
  for (std::uint32_t l = 1; l < levels_; ++l) {
    const float* below = range_levels_.data() + static_cast<std::size_t>(l - 1) * 2 * kBins;
    float* row = range_levels_.data() + static_cast<std::size_t>(l) * 2 * kBins;
    const std::uint32_t half = 1U << (l - 1);
    for (std::uint32_t i = 0; i + half < 2 * kBins; ++i)
      row[i] = std::min(below[i], below[i + half]);
  }
  // Every cell within range whose beams all reach past it is passed.
  const auto si = std::clamp(static_cast<int>((fr0 - r0) * kSubCells), 0, kSubCells - 1);
  const auto sj = std::clamp(static_cast<int>((fc0 - c0) * kSubCells), 0, kSubCells - 1);
  const std::size_t sub = static_cast<std::size_t>(si) * kSubCells + static_cast<std::size_t>(sj);
  const auto rows = static_cast<int>(rows_);
  const auto cols = static_cast<int>(cols_);
  const auto limit = static_cast<float>(max_range);
  for (std::size_t e = sweep_start_[sub]; e < sweep_start_[sub + 1]; ++e) {
    const SweepCell& cell = sweep_cells_[e];
    if (cell.far_m > limit) break;
    const int r = r0 + cell.dr;
    const int c = c0 + cell.dc;
    if (r < 0 || c < 0 || r >= rows || c >= cols) continue;
    const auto k = static_cast<std::size_t>(r) * cols_ + static_cast<std::size_t>(c);
    if (!(log_odds_[k] > params_.min_log_odds) || hit_stamp_[k] == scan_number_) continue;
    if (shortest_beam(cell.bin_lo, cell.span) > cell.far_m) {
      set_log_odds(k, log_odds_[k] + params_.miss_log_odds);
    }
  }
}

MapPlanner::MapPlanner(const NavMap& map, const MapPlannerParams& params, double half_beam_m)
    : params_(params),
      resolution_m_(map.params().resolution_m),
      origin_(map.origin()),
      rows_(map.rows()),
      cols_(map.cols()),
      known_dist2_(static_cast<std::size_t>(rows_) * cols_, kFar),
      known_site_(known_dist2_.size(), 0),
      dist2_(known_dist2_.size(), kFar),
      site_(known_dist2_.size(), 0),
      queue_(2 * known_dist2_.size() + 16, 0),
      state_(known_dist2_.size(), CellState::kFree),
      depth_(known_dist2_.size(), 0),
      cost_(known_dist2_.size(), 0),
      changed_stamp_(known_dist2_.size(), 0U),
      astar_(rows_, cols_) {
  path_.reserve(known_dist2_.size() + 2);
  changed_.reserve(known_dist2_.size());
  previous_changed_.reserve(known_dist2_.size());
  if (auto e = params.validate()) throw std::invalid_argument(*e);
  if (!std::isfinite(half_beam_m) || half_beam_m < 0.0) {
    throw std::invalid_argument("planner: half beam must be >= 0");
  }
  // An obstacle may sit anywhere in its cell, so reach half a cell further than the radius.
  const double reach = (half_beam_m + params.clearance_m) / resolution_m_ + 0.5;
  // Without a soft cost the band beyond the inflation says nothing: distances stop at it.
  const double band =
      reach + (params.clearance_cost > 0.0 ? params.soft_clearance_m / resolution_m_ : 0.0);
  band_dist2_ = static_cast<std::uint32_t>(std::floor(band * band));
  depth_by_dist2_.assign(band_dist2_ + 1, 0);
  cost_by_dist2_.assign(band_dist2_ + 1, 0);
  for (std::uint32_t d2 = 1; d2 <= band_dist2_; ++d2) {
    const double d = std::sqrt(static_cast<double>(d2));
    if (d <= reach) {
      depth_by_dist2_[d2] =
          static_cast<std::uint8_t>(std::clamp(1.0 + (reach - d) * 16.0, 1.0, 254.0));
    } else if (params.soft_clearance_m > 0.0) {
      const double f = (band - d) / (band - reach);
      cost_by_dist2_[d2] = static_cast<std::uint8_t>(
          std::clamp(std::lround(params.clearance_cost * 16.0 * f * f), 0L, 255L));
    }
  }
  unknown_cost_ =
      static_cast<std::uint8_t>(std::clamp(std::lround(params.unknown_cost * 16.0), 0L, 255L));
  const int g = static_cast<int>(std::ceil(params.goal_search_m / resolution_m_));
  for (int dr = -g; dr <= g; ++dr) {
    for (int dc = -g; dc <= g; ++dc) {
      if (std::hypot(dr, dc) <= params.goal_search_m / resolution_m_)
        goal_ring_.push_back({dr, dc});
    }
  }
  std::stable_sort(goal_ring_.begin(), goal_ring_.end(), [](Offset a, Offset b) {
    return a.dr * a.dr + a.dc * a.dc < b.dr * b.dr + b.dc * b.dc;
  });
  // The known layer never changes: its distances are worked out once. Cells whose four
  // neighbours are all known are interior: nothing outside is nearer to them than to an edge.
  const auto rows = static_cast<int>(rows_);
  const auto cols = static_cast<int>(cols_);
  const auto known = [&](int r, int c) {
    return r < 0 || c < 0 || r >= rows || c >= cols ||
           map.known(static_cast<std::size_t>(r) * cols_ + static_cast<std::size_t>(c));
  };
  std::size_t queued = 0;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (!known(r, c)) continue;
      const std::size_t k = static_cast<std::size_t>(r) * cols_ + static_cast<std::size_t>(c);
      known_dist2_[k] = 0;
      known_site_[k] = static_cast<std::uint32_t>(k);
      if (known(r - 1, c) && known(r + 1, c) && known(r, c - 1) && known(r, c + 1)) continue;
      queue_[queued++] = static_cast<std::uint32_t>(k);
    }
  }
  spread(known_dist2_, known_site_, queued, false);
}

void MapPlanner::fade_near(core::NavPoint goal) {
  const GridView v = view();
  const auto gc = v.cell_of(goal);
  if (!gc || !(params_.goal_fade_m > 0.0)) return;
  const double radius = params_.goal_fade_m / resolution_m_;
  const int n = static_cast<int>(std::ceil(radius));
  const auto rows = static_cast<int>(rows_);
  const auto cols = static_cast<int>(cols_);
  for (int dr = -n; dr <= n; ++dr) {
    const int r = static_cast<int>(gc->row) + dr;
    if (r < 0 || r >= rows) continue;
    for (int dc = -n; dc <= n; ++dc) {
      const int c = static_cast<int>(gc->col) + dc;
      if (c < 0 || c >= cols) continue;
      const double f = std::hypot(dr, dc) / radius;
      if (f >= 1.0) continue;
      const std::size_t k = static_cast<std::size_t>(r) * cols_ + static_cast<std::size_t>(c);
      note_changed(static_cast<std::uint32_t>(k));  // worked out afresh at the next plan
      cost_[k] = static_cast<std::uint8_t>(std::lround(cost_[k] * f));
    }
  }
}

GridView MapPlanner::view() const {
  return {rows_, cols_, resolution_m_, origin_, state_.data(), depth_.data(), cost_.data()};
}

void MapPlanner::spread(std::vector<std::uint32_t>& dist2, std::vector<std::uint32_t>& site,
                        std::size_t queued, bool note) {
  const std::size_t cap = queue_.size();
  std::size_t head = 0;
  std::size_t tail = queued % cap;
  std::size_t count = queued;
  const auto rows = static_cast<int>(rows_);
  const auto cols = static_cast<int>(cols_);
  while (count > 0) {
    const std::uint32_t cur = queue_[head];
    head = head + 1 == cap ? 0 : head + 1;
    --count;
    const std::uint32_t s = site[cur];
    const int sr = static_cast<int>(s / cols_);
    const int sc = static_cast<int>(s % cols_);
    const int r = static_cast<int>(cur / cols_);
    const int c = static_cast<int>(cur % cols_);
    for (int dr = -1; dr <= 1; ++dr) {
      const int rr = r + dr;
      if (rr < 0 || rr >= rows) continue;
      for (int dc = -1; dc <= 1; ++dc) {
        const int cc = c + dc;
        if ((dr == 0 && dc == 0) || cc < 0 || cc >= cols) continue;
        const auto d2 = static_cast<std::uint32_t>((rr - sr) * (rr - sr) + (cc - sc) * (cc - sc));
        if (d2 > band_dist2_) continue;
        const std::size_t k = static_cast<std::size_t>(rr) * cols_ + static_cast<std::size_t>(cc);
        if (d2 >= dist2[k]) continue;
        dist2[k] = d2;
        site[k] = s;
        if (note) note_changed(static_cast<std::uint32_t>(k));
        if (count == cap) continue;  // cannot happen with the ring's size; never overrun it
        queue_[tail] = static_cast<std::uint32_t>(k);
        tail = tail + 1 == cap ? 0 : tail + 1;
        ++count;
      }
    }
  }
}

void MapPlanner::derive(const NavMap& map, std::size_t k) {
  const std::uint32_t d2 = dist2_[k];
  std::uint8_t extra = 0;
  if (d2 == 0) {
    state_[k] = CellState::kOccupied;
    depth_[k] = kDeepest;
  } else if (d2 <= band_dist2_ && depth_by_dist2_[d2] != 0) {
    state_[k] = CellState::kInflated;
    depth_[k] = depth_by_dist2_[d2];
  } else {
    state_[k] = CellState::kFree;
    depth_[k] = 0;
    if (d2 <= band_dist2_) extra = cost_by_dist2_[d2];
    if (map.log_odds(k) == 0.0F)
      extra = static_cast<std::uint8_t>(std::min(255, extra + unknown_cost_));
  }
  cost_[k] = extra;
}

void MapPlanner::note_changed(std::uint32_t k) {
  if (changed_stamp_[k] == plan_stamp_) return;
  changed_stamp_[k] = plan_stamp_;
  changed_.push_back(k);  // at most one entry per cell: within the capacity reserved
}

std::size_t MapPlanner::queue_wall(const PlanWall& w, std::size_t queued) {
  const GridView v = view();
  const double dn = w.to.north_m - w.from.north_m;
  const double de = w.to.east_m - w.from.east_m;
  if (!std::isfinite(dn) || !std::isfinite(de) || !std::isfinite(w.from.north_m) ||
      !std::isfinite(w.from.east_m)) {
    return queued;
  }
  // Only the part on the map (Liang-Barsky), so the steps are bounded by the map's size however
  // long the wall.
  double t0 = 0.0;
  double t1 = 1.0;
  const auto clip = [&](double p, double q) {  // keep where p t <= q
    if (p == 0.0) return q >= 0.0;
    const double r = q / p;
    if (p < 0.0) {
      t0 = std::max(t0, r);
    } else {
      t1 = std::min(t1, r);
    }
    return t0 <= t1;
  };
  const double rel_n = w.from.north_m - origin_.north_m;
  const double rel_e = w.from.east_m - origin_.east_m;
  const double size_n = rows_ * resolution_m_;
  const double size_e = cols_ * resolution_m_;
  if (!clip(-dn, rel_n) || !clip(dn, size_n - rel_n) || !clip(-de, rel_e) ||
      !clip(de, size_e - rel_e)) {
    return queued;
  }
  // Steps of half a cell: consecutive cells touch at least at a corner, and the inflation round
  // each closes the diagonal gaps.
  const double len = (t1 - t0) * std::hypot(dn, de);
  const auto steps = static_cast<std::size_t>(std::ceil(len / (0.5 * resolution_m_)));
  for (std::size_t i = 0; i <= steps; ++i) {
    const double f =
        t0 + (steps == 0 ? 0.0 : (t1 - t0) * static_cast<double>(i) / static_cast<double>(steps));
    const auto c = v.cell_of({w.from.north_m + f * dn, w.from.east_m + f * de});
    if (!c) continue;
    const auto k = static_cast<std::uint32_t>(v.index(*c));
    if (dist2_[k] == 0) continue;
    dist2_[k] = 0;
    site_[k] = k;
    if (queued < queue_.size()) queue_[queued++] = k;
    note_changed(k);
  }
  return queued;
}

void MapPlanner::inflate(const NavMap& map, std::span<const PlanWall> walls) {
  // Only the cells the lidar's obstacles reached (this plan's and the last's) and the last
  // goal's faded costs differ from the known layer's values, so those alone are put back and
  // worked out again: the same arrays as a copy of the whole known layer would give, without a
  // pass over every cell. With a cost on unseen water every cell may change with each scan:
  // then the whole grid, as on the first plan.
  const bool whole = !inflated_once_ || unknown_cost_ != 0;
  std::swap(changed_, previous_changed_);
  changed_.clear();
  if (++plan_stamp_ == 0) {
    std::fill(changed_stamp_.begin(), changed_stamp_.end(), 0U);
    plan_stamp_ = 1;
  }
  if (whole) {
    std::copy(known_dist2_.begin(), known_dist2_.end(), dist2_.begin());
    std::copy(known_site_.begin(), known_site_.end(), site_.begin());
  } else {
    for (const std::uint32_t k : previous_changed_) {
      dist2_[k] = known_dist2_[k];
      site_[k] = known_site_[k];
    }
  }
  std::size_t queued = 0;
  for (const std::uint32_t k : map.lidar_occupied()) {
    if (dist2_[k] == 0) continue;
    dist2_[k] = 0;
    site_[k] = k;
    queue_[queued++] = k;
    note_changed(k);
  }
  for (const PlanWall& w : walls) queued = queue_wall(w, queued);
  spread(dist2_, site_, queued, true);
  if (whole) {
    for (std::size_t k = 0; k < dist2_.size(); ++k) derive(map, k);
  } else {
    for (const std::uint32_t k : previous_changed_) derive(map, k);
    for (const std::uint32_t k : changed_) derive(map, k);
  }
  inflated_once_ = true;
}

PlanStatus MapPlanner::plan(const NavMap& map, core::NavPoint start, core::NavPoint goal,
                            std::span<const PlanWall> walls) {
  inflate(map, walls);
  const GridView v = view();
  // On an obstacle cell every way out is as shallow as the next, so A* would leave through
  // the far side of a thin wall as readily as the near one. Farther than this from the last
  // clear start, that start says nothing about the side the boat is on.
  constexpr double kClearStartReachM = 2.0;
  if (const auto sc = v.cell_of(start); sc && v.at(*sc) == CellState::kOccupied) {
    if (last_clear_start_ && core::distance_m(*last_clear_start_, start) <= kClearStartReachM) {
      if (const auto lc = v.cell_of(*last_clear_start_); lc && v.at(*lc) != CellState::kOccupied) {
        start = *last_clear_start_;
      }
    }
  } else if (sc) {
    last_clear_start_ = start;
  }
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
      path_.clear();
      return status_;
    }
  }
  fade_near(g);
  status_ = astar_.plan(v, start, g, params_.max_expansions,
                        static_cast<float>(params_.heuristic_weight));
  if (status_ == PlanStatus::kOk) {
    path_ = astar_.path();
  } else {
    path_.clear();
  }
  return status_;
}

bool MapPlanner::line_clear(core::NavPoint a, core::NavPoint b) const {
  const GridView v = view();
  const auto start = v.cell_of(a);
  if (!start) return false;
  const std::uint8_t allowed = v.at(*start) == CellState::kOccupied ? 0 : depth_[v.index(*start)];
  const double len = core::distance_m(a, b);
  const auto samples = static_cast<int>(std::ceil(len / (0.5 * resolution_m_)));
  for (int i = 1; i <= samples; ++i) {
    const double t = static_cast<double>(i) / samples;
    const auto c =
        v.cell_of({a.north_m + t * (b.north_m - a.north_m), a.east_m + t * (b.east_m - a.east_m)});
    if (!c) return false;
    const std::size_t k = v.index(*c);
    if (state_[k] == CellState::kOccupied) return false;
    if (state_[k] == CellState::kInflated && depth_[k] > allowed) return false;
  }
  return true;
}

std::size_t MapPlanner::nearest_on_path(core::NavPoint position, core::NavPoint& nearest) const {
  const std::vector<core::NavPoint>& p = path_;
  std::size_t best_i = 0;
  double best_d = std::numeric_limits<double>::infinity();
  nearest = p.front();
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
    const core::NavPoint q{p[i].north_m + t * dn, p[i].east_m + t * de};
    const double d = core::distance_m(q, position);
    if (d < best_d) {
      best_d = d;
      best_i = i;
      nearest = q;
    }
  }
  return best_i;
}

double MapPlanner::seen_ahead_m(const NavMap& map, core::NavPoint position, double limit_m) const {
  if (status_ != PlanStatus::kOk || path_.empty()) return 0.0;
  core::NavPoint at;
  const std::size_t first = nearest_on_path(position, at);
  const double step = 0.5 * resolution_m_;
  // The water under and right round the boat is nearer than the map takes returns from; the
  // boat is on it, so it counts as seen.
  const double blind_m = map.params().min_range_m + 1.5 * resolution_m_;
  double run = 0.0;
  for (std::size_t i = first; i + 1 < path_.size(); ++i) {
    const double seg = core::distance_m(at, path_[i + 1]);
    for (double s = 0.0; s < seg; s += step) {
      const double f = s / seg;
      const auto c = map.cell_of({at.north_m + f * (path_[i + 1].north_m - at.north_m),
                                  at.east_m + f * (path_[i + 1].east_m - at.east_m)});
      if (!c) return std::min(run + s, limit_m);
      const std::size_t k = map.index(*c);
      if (!map.known(k) && map.log_odds(k) == 0.0F && run + s >= blind_m) {
        return std::min(run + s, limit_m);
      }
      if (run + s >= limit_m) return limit_m;
    }
    run += seg;
    at = path_[i + 1];
  }
  return limit_m;
}

namespace {

// The point `ahead` metres along `p` from `nearest`, which lies on its segment `from_i`.
core::NavPoint walk_along(const std::vector<core::NavPoint>& p, std::size_t from_i,
                          core::NavPoint nearest, double ahead) {
  core::NavPoint at = nearest;
  for (std::size_t i = from_i; i + 1 < p.size(); ++i) {
    const double seg = core::distance_m(at, p[i + 1]);
    if (seg >= ahead && seg > 0.0) {
      const double f = ahead / seg;
      return core::NavPoint{at.north_m + f * (p[i + 1].north_m - at.north_m),
                            at.east_m + f * (p[i + 1].east_m - at.east_m)};
    }
    ahead -= seg;
    at = p[i + 1];
  }
  return p.back();
}

}  // namespace

std::optional<core::NavPoint> MapPlanner::along_path(core::NavPoint position,
                                                     double ahead_m) const {
  const std::vector<core::NavPoint>& p = path_;
  if (status_ != PlanStatus::kOk || p.empty()) return std::nullopt;
  if (p.size() == 1) return p.front();
  core::NavPoint nearest;
  const std::size_t best_i = nearest_on_path(position, nearest);
  return walk_along(p, best_i, nearest, std::max(0.0, ahead_m));
}

std::optional<core::NavPoint> MapPlanner::subgoal(core::NavPoint position, double nearest_m) const {
  const std::vector<core::NavPoint>& p = path_;
  if (status_ != PlanStatus::kOk || p.empty()) return std::nullopt;
  if (p.size() == 1) return p.front();
  core::NavPoint nearest;
  const std::size_t best_i = nearest_on_path(position, nearest);
  const auto along = [&](double ahead) { return walk_along(p, best_i, nearest, ahead); };
  // The farthest point within the look-ahead the boat can steer straight at: a sub-goal round
  // a corner would have the boat cut it.
  const double step = resolution_m_;
  nearest_m = std::min(nearest_m, params_.lookahead_m);
  for (double ahead = params_.lookahead_m; ahead > nearest_m; ahead -= step) {
    const core::NavPoint q = along(ahead);
    if (line_clear(position, q)) return q;
  }
  return along(nearest_m);
}

}  // namespace coxswain::guidance
