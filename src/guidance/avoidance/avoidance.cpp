// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/avoidance.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>

#include "coxswain/core/angles.hpp"
#include "coxswain/core/lanes.hpp"

namespace coxswain::guidance {
namespace {

using core::lanes::abs2;
using core::lanes::all2;
using core::lanes::bits4;
using core::lanes::load2;
using core::lanes::load4;
using core::lanes::load4i;
using core::lanes::max4;
using core::lanes::splat2;
using core::lanes::splat4;
using core::lanes::store2;
using core::lanes::V2d;
using core::lanes::V4f;
using core::lanes::V4i;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTieEps = 1e-9;

// core::angle_diff_deg with its common case (already in range) inline: the same value.
inline double diff_deg(double to_deg, double from_deg) {
  const double d = to_deg - from_deg;
  return d > -180.0 && d <= 180.0 ? d : core::wrap_deg(d);
}

bool tied(double a, double b) { return std::abs(a - b) <= kTieEps * (1.0 + std::abs(a)); }

double bearing_of(const core::BodyPoint& p) {
  return core::rad_to_deg(std::atan2(p.starboard_m, p.forward_m));
}

// A segment's ends in the body frame (forward, starboard of each).
struct SegmentEnds {
  double af = 0.0;
  double as = 0.0;
  double bf = 0.0;
  double bs = 0.0;
};

// Its ends when all four coordinates are finite; a segment with any other is passed over.
std::optional<SegmentEnds> finite_ends(const perception::ObstacleSegment& seg) {
  const SegmentEnds e{seg.begin.forward_m, seg.begin.starboard_m, seg.end.forward_m,
                      seg.end.starboard_m};
  if (!std::isfinite(e.af) || !std::isfinite(e.as) || !std::isfinite(e.bf) ||
      !std::isfinite(e.bs)) {
    return std::nullopt;
  }
  return e;
}

// The hull as a rectangle in its own body frame: forward in [aft_m, fore_m], |starboard| <= half.
struct HullBox {
  double aft_m = 0.0;
  double fore_m = 0.0;
  double half_m = 0.0;
};

double point_box_distance(double f, double s, const HullBox& b) {
  const double df = std::max({b.aft_m - f, 0.0, f - b.fore_m});
  const double ds = std::max(std::abs(s) - b.half_m, 0.0);
  return std::hypot(df, ds);
}

// hypot() of point p to its nearest point of segment a-b > limit_m, decided on squares unless
// rounding could matter.
bool point_segment_farther_than(double pf, double ps, double af, double as, double bf, double bs,
                                double limit_m) {
  const double df = bf - af;
  const double ds = bs - as;
  const double dd = df * df + ds * ds;
  const double t = dd < 1e-18 ? 0.0 : std::clamp(((pf - af) * df + (ps - as) * ds) / dd, 0.0, 1.0);
  const double x = pf - (af + t * df);
  const double y = ps - (as + t * ds);
  const double sq = x * x + y * y;
  const double limit_sq = limit_m * limit_m;
  if (sq > limit_sq * (1.0 + 1e-9)) return true;
  if (sq < limit_sq * (1.0 - 1e-9)) return false;
  return std::hypot(x, y) > limit_m;
}

// True when the segment a-b crosses the box (Liang-Barsky clipping).
bool segment_crosses_box(double af, double as, double bf, double bs, const HullBox& b) {
  double t0 = 0.0;
  double t1 = 1.0;
  const double df = bf - af;
  const double ds = bs - as;
  const double p[4] = {-df, df, -ds, ds};
  const double q[4] = {af - b.aft_m, b.fore_m - af, as + b.half_m, b.half_m - as};
  for (int i = 0; i < 4; ++i) {
    if (std::abs(p[i]) < 1e-15) {
      if (q[i] < 0.0) return false;
      continue;
    }
    const double r = q[i] / p[i];
    if (p[i] < 0.0) {
      t0 = std::max(t0, r);
    } else {
      t1 = std::min(t1, r);
    }
    if (t0 > t1) return false;
  }
  return true;
}

// The six candidate offsets whose lengths segment_box_distance takes the least of: each end to
// the box, each box corner to the segment (the same arithmetic as point_box_distance and
// a point-to-segment hypot()).
struct BoxOffsets {
  std::array<double, 6> x{};
  std::array<double, 6> y{};
  double min_sq = 0.0;
};

BoxOffsets box_offsets(double af, double as, double bf, double bs, const HullBox& b) {
  BoxOffsets o;
  const auto to_box = [&](std::size_t i, double f, double s) {
    o.x[i] = std::max({b.aft_m - f, 0.0, f - b.fore_m});
    o.y[i] = std::max(std::abs(s) - b.half_m, 0.0);
  };
  to_box(0, af, as);
  to_box(1, bf, bs);
  const double df = bf - af;
  const double ds = bs - as;
  const double dd = df * df + ds * ds;
  std::size_t i = 2;
  for (const double cf : {b.aft_m, b.fore_m}) {
    for (const double cs : {-b.half_m, b.half_m}) {
      const double t =
          dd < 1e-18 ? 0.0 : std::clamp(((cf - af) * df + (cs - as) * ds) / dd, 0.0, 1.0);
      o.x[i] = cf - (af + t * df);
      o.y[i] = cs - (as + t * ds);
      ++i;
    }
  }
  o.min_sq = kInf;
  for (std::size_t k = 0; k < 6; ++k)
    o.min_sq = std::min(o.min_sq, o.x[k] * o.x[k] + o.y[k] * o.y[k]);
  return o;
}

// Relative band within which squared lengths leave the order of their hypot() to rounding.
constexpr double kSqBand = 1e-9;

// The least hypot() of the offsets, taken only over those whose squares come near the least.
double least_length(const BoxOffsets& o) {
  double d = kInf;
  const double cap = o.min_sq * (1.0 + kSqBand);
  for (std::size_t k = 0; k < 6; ++k) {
    if (o.x[k] * o.x[k] + o.y[k] * o.y[k] <= cap) d = std::min(d, std::hypot(o.x[k], o.y[k]));
  }
  return d;
}

// Distance between a segment and the box; 0 when they touch or overlap.
double segment_box_distance(double af, double as, double bf, double bs, const HullBox& b) {
  if (segment_crosses_box(af, as, bf, bs, b)) return 0.0;
  return least_length(box_offsets(af, as, bf, bs, b));
}

// segment_box_distance(...) < room_m, mostly decided on squares.
bool segment_box_closer_than(double af, double as, double bf, double bs, const HullBox& b,
                             double room_m) {
  if (segment_crosses_box(af, as, bf, bs, b)) return 0.0 < room_m;
  const BoxOffsets o = box_offsets(af, as, bf, bs, b);
  const double room_sq = room_m * room_m;
  if (o.min_sq >= room_sq * (1.0 + kSqBand)) return false;
  if (o.min_sq < room_sq * (1.0 - kSqBand)) return true;
  return least_length(o) < room_m;
}

// Squared distance from a point to a segment (start a, direction d, inv_dd = 1 / |d|^2 or 0),
// for one double or four floats at once, lane by lane the same arithmetic (std::clamp(v, 0, 1)
// is v < 0 ? 0 : (1 < v ? 1 : v)).
template <class V>
V point_segment_sq(V pf, V ps, V af, V as, V df, V ds, V inv_dd) {
  const V wf = pf - af;
  const V ws = ps - as;
  const V zero{};
  const V one = zero + 1;
  V t = (wf * df + ws * ds) * inv_dd;
  t = t < zero ? zero : t;
  t = one < t ? one : t;
  const V ef = wf - t * df;
  const V es = ws - t * ds;
  return ef * ef + es * es;
}

// Margin of the culling tests: far above rounding (1e-15 m at these sizes), far below anything
// that matters, so a culled pair is one the exact test would have passed over too.
constexpr double kCullEps = 1e-6;
// The same for the culling tests in floats: far above their rounding (1e-4 m at most within
// kLaneLimitM).
constexpr double kLaneEpsM = 1e-3;
// Where the float tables put what is not there (steps past the last): far beyond any reach,
// its square still finite.
constexpr float kFarOffM = 1e15F;

// Within this, the culling tests' float rounding stays below 1e-4 m.
constexpr double kLaneLimitM = 100.0;
bool within_lanes(double af, double as, double bf, double bs) {
  return std::abs(af) <= kLaneLimitM && std::abs(as) <= kLaneLimitM &&
         std::abs(bf) <= kLaneLimitM && std::abs(bs) <= kLaneLimitM;
}

}  // namespace

const char* to_string(Strategy s) {
  switch (s) {
    case Strategy::kSelection:
      return "selection";
    case Strategy::kScore:
      return "score";
    case Strategy::kRiskBin:
      return "risk_bin";
    case Strategy::kSelectionNaive2022:
      return "selection_naive_2022";
  }
  return "unknown";
}

std::optional<Strategy> parse_strategy(std::string_view name) {
  for (const Strategy s : {Strategy::kSelection, Strategy::kScore, Strategy::kRiskBin,
                           Strategy::kSelectionNaive2022}) {
    if (name == to_string(s)) return s;
  }
  return std::nullopt;
}

const char* to_string(AvoidanceStatus s) {
  switch (s) {
    case AvoidanceStatus::kClear:
      return "clear";
    case AvoidanceStatus::kAvoiding:
      return "avoiding";
    case AvoidanceStatus::kBlockedSlow:
      return "blocked_slow";
    case AvoidanceStatus::kBlockedStop:
      return "blocked_stop";
    case AvoidanceStatus::kBackOff:
      return "back_off";
  }
  return "unknown";
}

std::optional<std::string> AvoidanceParams::validate() const {
  if (auto e = fan.validate()) return e;
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  const auto non_negative = [](double v) { return std::isfinite(v) && v >= 0.0; };
  const auto unit = [](double v) { return std::isfinite(v) && v >= 0.0 && v <= 1.0; };
  if (!positive(detection_range_m)) return "detection_range_m must be > 0";
  if (!non_negative(half_beam_m) || !non_negative(clearance_m)) {
    return "half_beam_m and clearance_m must be >= 0";
  }
  if (!positive(slow_down_range_m)) return "slow_down_range_m must be > 0";
  if (!unit(min_speed_factor)) return "min_speed_factor must be in [0, 1]";
  if (!(shrink_factor > 0.0 && shrink_factor < 1.0)) return "shrink_factor must be in (0, 1)";
  if (!positive(min_detection_range_m) || min_detection_range_m > detection_range_m) {
    return "min_detection_range_m must be in (0, detection_range_m]";
  }
  if (!unit(blocked_speed_factor)) return "blocked_speed_factor must be in [0, 1]";
  if (!unit(back_off_speed_factor)) return "back_off_speed_factor must be in [0, 1]";
  if (!non_negative(hysteresis_deg) || !non_negative(hold_time_s)) {
    return "hysteresis_deg and hold_time_s must be >= 0";
  }
  if (!positive(score_goal_weight)) return "score_goal_weight must be > 0";
  if (!non_negative(score_distance_weight) || !non_negative(score_angle_weight)) {
    return "score weights must be >= 0";
  }
  if (!non_negative(score_block_range_m) || score_block_range_m > detection_range_m) {
    return "score_block_range_m must be in [0, detection_range_m]";
  }
  if (!positive(risk_gain_per_m) || !std::isfinite(risk_offset) || !positive(risk_max) ||
      !positive(risk_threshold) || risk_threshold >= risk_max) {
    return "risk: gain > 0, max > 0 and 0 < threshold < max";
  }
  if (!(risk_range_m() > 0.0)) return "risk: threshold above the risk at distance 0";
  if (!non_negative(naive_margin_deg)) return "naive_margin_deg must be >= 0";
  if (!positive(hull_length_m) || !non_negative(bow_ahead_m) || bow_ahead_m > hull_length_m) {
    return "sweep: hull_length_m > 0 and 0 <= bow_ahead_m <= hull_length_m";
  }
  if (!std::isfinite(pivot_ahead_m) || !non_negative(sweep_turn_radius_m) ||
      !non_negative(sweep_clearance_m)) {
    return "sweep: pivot_ahead_m finite, turn radius and clearance >= 0";
  }
  if (!(sweep_step_deg >= 0.5 && sweep_step_deg <= 45.0)) {
    return "sweep: sweep_step_deg must be in [0.5, 45]";
  }
  if (std::isnan(path_clearance_m) || path_clearance_m > 2.0 || path_bins < 0 || path_bins > 45) {
    return "path_clearance_m must be <= 2 (negative: clearance_m), path_bins in [0, 45]";
  }
  return {};
}

double AvoidanceParams::risk_range_m() const {
  // e^(-g d + o) > t  <=>  d < (o - ln t) / g
  return (risk_offset - std::log(risk_threshold)) / risk_gain_per_m;
}

std::optional<Avoidance> Avoidance::create(const AvoidanceParams& params, std::string* error) {
  if (auto e = params.validate()) {
    if (error != nullptr) *error = std::move(*e);
    return std::nullopt;
  }
  return Avoidance(params);
}

Avoidance::Avoidance(const AvoidanceParams& params) : params_(params) {
  (void)bins_.configure(params.fan);  // validated by create()
  cost_per_deg_ = params.strategy == Strategy::kScore ? params.score_goal_weight / 180.0 : 1.0;
  for (std::size_t j = 0; j < bins_.size(); ++j) {
    center_deg_[j] = bins_.center_deg(j);
    angle_term_[j] = params.score_angle_weight * (1.0 - std::abs(center_deg_[j]) / 180.0);
  }
  // The pose at the end of each bin's turn: the pivot (pivot_ahead_m ahead of the origin) on a
  // circle of the turn radius, the origin pivot_ahead_m behind it along the new heading.
  const double p = params.pivot_ahead_m;
  const double radius = params.sweep_turn_radius_m;
  for (std::size_t j = 0; j < bins_.size(); ++j) {
    const double c = bins_.center_deg(j);
    const double a = core::deg_to_rad(std::min(std::abs(c), 180.0));
    const double sign = c < 0.0 ? -1.0 : 1.0;
    arc_cos_[j] = std::cos(a);
    arc_sin_[j] = sign * std::sin(a);
    arc_end_f_m_[j] = p + radius * std::sin(a) - p * arc_cos_[j];
    arc_end_s_m_[j] = sign * radius * (1.0 - arc_cos_[j]) - p * arc_sin_[j];
    arc_len_m_[j] = radius * a;
  }
  // A point of the segment that lowers bin j's range below the detection range D lies within w
  // of the corridor's centre line, less than D - arc length ahead of the turn's end: no farther
  // from the origin than D + w + (the turn end's distance - its arc length).
  double end_past_arc_m = 0.0;
  for (std::size_t j = 0; j < bins_.size(); ++j) {
    end_past_arc_m =
        std::max(end_past_arc_m, std::hypot(arc_end_f_m_[j], arc_end_s_m_[j]) - arc_len_m_[j]);
  }
  path_reach_m_ =
      params.detection_range_m + params.half_beam_m + params.clearance_m + end_past_arc_m + 1e-6;
  // Blocks of bins for the path ranges' first test: the corridors of a block's bins all lie in
  // the wedge between its first and last bin's directions, from its first bin's arc end,
  // widened by the farthest other arc end of the block (valid while the directions turn one
  // way through the block; otherwise every bin of it is tested).
  const std::size_t n_bins = bins_.size();
  block_count_ = (n_bins + kBlockBins - 1) / kBlockBins;
  BlockLanes& bl = block_lanes_;
  for (std::size_t b = 0; b < block_count_; ++b) {
    const std::size_t j0 = b * kBlockBins;
    const std::size_t j1 = std::min(n_bins, j0 + kBlockBins) - 1;
    const double origin_f = arc_end_f_m_[j0];  // arc end of the block's first bin
    const double origin_s = arc_end_s_m_[j0];
    const double lo_cos = arc_cos_[j0];  // direction of its first bin
    const double lo_sin = arc_sin_[j0];
    const double hi_cos = arc_cos_[j1];  // direction of its last bin
    const double hi_sin = arc_sin_[j1];
    double radius_m = 0.0;  // farthest arc end of the block from origin
    bool wedge = lo_cos * hi_cos + lo_sin * hi_sin > 0.0;
    double shortest_arc_m = arc_len_m_[j0];
    for (std::size_t j = j0; j <= j1; ++j) {
      shortest_arc_m = std::min(shortest_arc_m, arc_len_m_[j]);
      radius_m =
          std::max(radius_m, std::hypot(arc_end_f_m_[j] - origin_f, arc_end_s_m_[j] - origin_s));
      const double from_lo = lo_cos * arc_sin_[j] - lo_sin * arc_cos_[j];
      const double to_hi = arc_cos_[j] * hi_sin - arc_sin_[j] * hi_cos;
      if (from_lo < -1e-12 || to_hi < -1e-12) wedge = false;
    }
    // How far past its arc end a return can still lower a capped range of the block: the
    // detection range less the block's shortest arc (at least 0).
    const double ahead_m = std::max(0.0, params.detection_range_m - shortest_arc_m);
    bl.origin_f_m[b] = static_cast<float>(origin_f);
    bl.origin_s_m[b] = static_cast<float>(origin_s);
    bl.reach_m[b] = static_cast<float>(ahead_m + radius_m);
    bl.radius_m[b] = static_cast<float>(radius_m);
    bl.lo_cos[b] = static_cast<float>(lo_cos);
    bl.lo_sin[b] = static_cast<float>(lo_sin);
    bl.hi_cos[b] = static_cast<float>(hi_cos);
    bl.hi_sin[b] = static_cast<float>(hi_sin);
    bl.wedge[b] = wedge ? -1 : 0;
    bl.live[b] = -1;
  }
  // The bins, as floats for the culling tests.
  lanes_usable_ = params.detection_range_m <= kLaneLimitM;
  for (std::size_t j = 0; j < bin_lanes_.arc_len_m.size(); ++j) {
    const bool bin = j < n_bins;
    bin_lanes_.arc_end_f_m[j] = bin ? static_cast<float>(arc_end_f_m_[j]) : 0.0F;
    bin_lanes_.arc_end_s_m[j] = bin ? static_cast<float>(arc_end_s_m_[j]) : 0.0F;
    bin_lanes_.cos[j] = bin ? static_cast<float>(arc_cos_[j]) : 1.0F;
    bin_lanes_.sin[j] = bin ? static_cast<float>(arc_sin_[j]) : 0.0F;
    bin_lanes_.arc_len_m[j] =
        bin ? static_cast<float>(arc_len_m_[j]) : std::numeric_limits<float>::infinity();
    if (bin && (std::abs(arc_end_f_m_[j]) > kLaneLimitM ||
                std::abs(arc_end_s_m_[j]) > kLaneLimitM || arc_len_m_[j] > kLaneLimitM)) {
      lanes_usable_ = false;
    }
  }
  // The swept hull's poses, step by step, with the same arithmetic the check used to do per
  // call (so the same turns come out).
  const HullBox box{params.bow_ahead_m - params.hull_length_m, params.bow_ahead_m,
                    params.half_beam_m};
  const double box_mid_m = 0.5 * (box.aft_m + box.fore_m);
  box_radius_m_ = std::hypot(0.5 * (box.fore_m - box.aft_m), box.half_m);
  const double step = params.sweep_step_deg;
  for (int side = 0; side < 2; ++side) {
    const double side_sign = side == 0 ? -1.0 : 1.0;
    SweepSide& w = sweep_sides_[static_cast<std::size_t>(side)];
    const double extent = side_sign > 0.0 ? params.fan.max_deg : -params.fan.min_deg;
    w.max_turn_deg = extent <= 0.0 ? 0.0 : std::min(extent, 180.0);
    w.centre_f_m = p;
    w.centre_s_m = side_sign * radius;
    w.box_near_m = point_box_distance(w.centre_f_m, w.centre_s_m, box);
    w.box_far_m = 0.0;
    for (const double cf : {box.aft_m, box.fore_m}) {
      for (const double cs : {-box.half_m, box.half_m}) {
        w.box_far_m = std::max(w.box_far_m, std::hypot(cf - w.centre_f_m, cs - w.centre_s_m));
      }
    }
    // Steps through a half turn: those within the fan's extent serve the bins, the rest a
    // manoeuvre's turn back (turn_room_deg).
    w.steps = 0;
    w.all_steps = 0;
    for (double a_deg = step; a_deg <= 180.0 + 1e-9 && w.all_steps < kMaxSweepSteps;
         a_deg += step) {
      const double a = core::deg_to_rad(a_deg);
      const double c = std::cos(a);
      const double sn = side_sign * std::sin(a);
      // The pivot on its circle, then the body origin p behind it along the new heading.
      const double of = p + radius * std::sin(a) - p * c;
      const double os = side_sign * radius * (1.0 - c) - p * sn;
      const std::size_t k = w.all_steps++;
      if (a_deg <= w.max_turn_deg + 1e-9) w.steps = w.all_steps;
      w.a_deg[k] = a_deg;
      w.cos[k] = c;
      w.sin[k] = sn;
      w.origin_f_m[k] = of;
      w.origin_s_m[k] = os;
      const double box_f = of + box_mid_m * c;
      const double box_s = os + box_mid_m * sn;
      if (std::abs(box_f) > kLaneLimitM || std::abs(box_s) > kLaneLimitM) lanes_usable_ = false;
      w.lane_box_f_m[k] = static_cast<float>(box_f);
      w.lane_box_s_m[k] = static_cast<float>(box_s);
    }
    for (std::size_t k = w.all_steps; k < w.lane_box_f_m.size(); ++k) {
      w.lane_box_f_m[k] = kFarOffM;
      w.lane_box_s_m[k] = kFarOffM;
    }
  }
}

void Avoidance::reset() {
  prev_side_ = Side::kNone;
  side_since_ns_ = core::kNeverNs;
  side_used_ns_ = core::kNeverNs;
}

bool Avoidance::compute_costs(double limit_m) {
  const std::size_t n = bins_.size();
  bool any = false;
  // The score's hard block shrinks with the range once the range falls below it.
  const double block_m = std::min(params_.score_block_range_m, limit_m);
  std::size_t j = 0;
  if (params_.strategy == Strategy::kScore) {
    // Two bins at a time, lane by lane the arithmetic below (a pair whose turn needs wrapping
    // goes through it).
    const V2d inf = splat2(kInf);
    const V2d goal = splat2(goal_deg_);
    const V2d port = splat2(sweep_port_deg_);
    const V2d stbd = splat2(sweep_starboard_deg_);
    const V2d limit = splat2(limit_m);
    const V2d block = splat2(block_m);
    for (; j + 1 < n; j += 2) {
      const V2d c = load2(&center_deg_[j]);
      const V2d diff = c - goal;
      if (!all2((diff > splat2(-180.0)) & (diff <= splat2(180.0)))) break;
      const V2d d = load2(&range_m_[j]);
      const V2d base = params_.score_goal_weight * abs2(diff) / 180.0;
      const V2d near =
          base + (params_.score_distance_weight * (1.0 - d / limit) + load2(&angle_term_[j]));
      V2d cost = d < limit ? near : base;
      cost = (d < block) ? inf : cost;
      cost = ((c > stbd) | (-c > port)) ? inf : cost;
      store2(&cost_[j], cost);
      any = any || cost[0] < kInf || cost[1] < kInf;
    }
  }
  for (; j < n; ++j) {
    const double c = center_deg_[j];
    const double d = range_m_[j];
    const double turn = std::abs(diff_deg(c, goal_deg_));
    double cost = kInf;
    if (swept_out(c)) {
      // The hull would swing into an obstacle on the way: refused at every range.
    } else if (params_.strategy == Strategy::kScore) {
      if (!(d < block_m)) {
        cost = params_.score_goal_weight * turn / 180.0;
        if (d < limit_m) {
          cost += params_.score_distance_weight * (1.0 - d / limit_m) + angle_term_[j];
        }
      }
    } else if (!(d < limit_m)) {  // selection and risk bins: the limit is the threshold range
      cost = turn;
    }
    cost_[j] = cost;
    any = any || cost < kInf;
  }
  return any;
}

std::size_t Avoidance::best_in(std::size_t first, std::size_t last, double goal_deg) const {
  std::size_t best = bins_.size();
  for (std::size_t j = first; j < last; ++j) {
    if (!(cost_[j] < kInf)) continue;
    if (best == bins_.size() || (cost_[j] < cost_[best] && !tied(cost_[j], cost_[best]))) {
      best = j;
      continue;
    }
    if (!tied(cost_[j], cost_[best])) continue;
    // Within one side of the goal: nearer the goal, then the smaller turn.
    const double tj = std::abs(diff_deg(bins_.center_deg(j), goal_deg));
    const double tb = std::abs(diff_deg(bins_.center_deg(best), goal_deg));
    if (tj < tb - kTieEps ||
        (tied(tj, tb) && std::abs(bins_.center_deg(j)) < std::abs(bins_.center_deg(best)))) {
      best = j;
    }
  }
  return best;
}

double Avoidance::free_room(Side side, double window_deg, double limit_m) const {
  // Clearance summed over the bins within `window_deg` of the goal on one side; the same window
  // on both sides so the fan's own asymmetry about the goal does not decide.
  double room = 0.0;
  const double sign = side == Side::kPort ? -1.0 : 1.0;
  for (std::size_t j = 0; j < bins_.size(); ++j) {
    const double off = sign * diff_deg(bins_.center_deg(j), goal_deg_);
    if (off > 0.0 && off <= window_deg) {
      room += std::min(range_m_[j], params_.detection_range_m) / limit_m;
    }
  }
  return room;
}

std::size_t Avoidance::most_open_bin(double goal_deg) const {
  // Among the bins the swept hull allows (a turn of under half a bin always is).
  std::size_t best = bins_.size();
  for (std::size_t j = 0; j < bins_.size(); ++j) {
    if (swept_out(bins_.center_deg(j))) continue;
    if (best == bins_.size()) {
      best = j;
      continue;
    }
    const double rj = range_m_[j];
    const double rb = range_m_[best];
    if (rj > rb) {
      best = j;
    } else if (rj == rb) {
      const double tj = std::abs(diff_deg(bins_.center_deg(j), goal_deg));
      const double tb = std::abs(diff_deg(bins_.center_deg(best), goal_deg));
      // Nearer the goal; on a full tie the later (starboard) bin, the COLREG-preferred side.
      if (tj <= tb + kTieEps) best = j;
    }
  }
  return best < bins_.size() ? best : bins_.index_of(0.0);
}

double Avoidance::speed_for(double nearest_m) const {
  if (nearest_m >= params_.slow_down_range_m) return 1.0;
  const double f = std::max(0.0, nearest_m) / params_.slow_down_range_m;
  return params_.min_speed_factor + (1.0 - params_.min_speed_factor) * f;
}

void Avoidance::fill_danger(AvoidanceDecision& out, double limit_m) const {
  const std::size_t n = bins_.size();
  out.danger.fill(0.0F);
  std::size_t j = 0;
  if (params_.strategy == Strategy::kScore) {
    // Two bins at a time, lane by lane the arithmetic below.
    const double w = params_.score_distance_weight + params_.score_angle_weight;
    const V2d limit = splat2(limit_m);
    const V2d port = splat2(sweep_port_deg_);
    const V2d stbd = splat2(sweep_starboard_deg_);
    const V2d zero = splat2(0.0);
    const V2d one = splat2(1.0);
    for (; j + 1 < n; j += 2) {
      const V2d d = load2(&range_m_[j]);
      const V2d c = load2(&center_deg_[j]);
      V2d risk = params_.score_distance_weight * (1.0 - d / limit) + load2(&angle_term_[j]);
      if (w > 0.0) {
        risk = risk / w;
        risk = risk < zero ? zero : risk;  // std::clamp(risk, 0, 1)
        risk = one < risk ? one : risk;
      } else {
        risk = zero;
      }
      V2d danger = d < splat2(params_.detection_range_m) ? splat2(0.5) : zero;
      danger = d < limit ? risk : danger;
      danger = load2(&cost_[j]) < splat2(kInf) ? danger : one;
      danger = ((c > stbd) | (-c > port)) ? one : danger;
      out.danger[j] = static_cast<float>(danger[0]);
      out.danger[j + 1] = static_cast<float>(danger[1]);
    }
  }
  for (; j < n; ++j) {
    const double d = range_m_[j];
    double danger = 0.0;
    switch (params_.strategy) {
      case Strategy::kRiskBin: {
        const double thr = std::exp(-params_.risk_gain_per_m * limit_m + params_.risk_offset);
        const double risk = std::min(params_.risk_max,
                                     std::exp(-params_.risk_gain_per_m * d + params_.risk_offset));
        danger = std::min(1.0, risk / thr);
        break;
      }
      case Strategy::kScore:
        if (!(cost_[j] < kInf)) {
          danger = 1.0;
        } else if (d < limit_m) {
          const double w = params_.score_distance_weight + params_.score_angle_weight;
          const double risk = params_.score_distance_weight * (1.0 - d / limit_m) + angle_term_[j];
          danger = w > 0.0 ? std::clamp(risk / w, 0.0, 1.0) : 0.0;
        } else if (d < params_.detection_range_m) {
          danger = 0.5;  // seen, but beyond the shrunken range
        }
        break;
      default:
        danger = d < limit_m ? 1.0 : (d < params_.detection_range_m ? 0.5 : 0.0);
        break;
    }
    if (swept_out(center_deg_[j])) danger = 1.0;
    out.danger[j] = static_cast<float>(danger);
  }
}

double Avoidance::sweep_turn_limit(const perception::ObstacleList& obstacles, int side) {
  const SweepSide& w = sweep_sides_[static_cast<std::size_t>(side)];
  if (w.max_turn_deg <= 0.0) return 0.0;
  if (sweep_count_ == 0) return w.max_turn_deg;
  const std::size_t first_hit = first_sweep_hit(obstacles, side, w.steps);
  return first_hit < w.steps ? w.a_deg[first_hit] - params_.sweep_step_deg : w.max_turn_deg;
}

double Avoidance::turn_room_deg(const perception::ObstacleList& obstacles, Side side,
                                double turn_deg) {
  turn_deg = std::clamp(turn_deg, 0.0, 180.0);
  if (!params_.sweep_enabled || side == Side::kNone) return turn_deg;
  const int s = side == Side::kPort ? 0 : 1;
  const SweepSide& w = sweep_sides_[static_cast<std::size_t>(s)];
  // The steps the turn needs: up to the first at or past turn_deg.
  const auto past =
      std::lower_bound(w.a_deg.begin(), w.a_deg.begin() + w.all_steps, turn_deg - 1e-9);
  const auto steps = std::min(w.all_steps, static_cast<std::size_t>(past - w.a_deg.begin()) + 1);
  const std::size_t first_hit = first_sweep_hit(obstacles, s, steps);
  if (first_hit >= steps) return turn_deg;
  return std::max(0.0, w.a_deg[first_hit] - params_.sweep_step_deg);
}

double Avoidance::astern_room_m(const perception::ObstacleList& obstacles, double look_m) const {
  const double stern_m = params_.bow_ahead_m - params_.hull_length_m;
  const HullBox box{stern_m - std::max(0.0, look_m), stern_m, params_.half_beam_m};
  double least_m = AngleBins::kNoObstacle;
  const std::uint32_t count =
      std::min<std::uint32_t>(obstacles.count, perception::ObstacleList::kMaxSegments);
  for (std::uint32_t k = 0; k < count; ++k) {
    const std::optional<SegmentEnds> ends = finite_ends(obstacles.segments[k]);
    if (!ends) continue;
    const auto [af, as, bf, bs] = *ends;
    least_m = std::min(least_m, segment_box_distance(af, as, bf, bs, box));
  }
  return least_m;
}

std::size_t Avoidance::first_sweep_hit(const perception::ObstacleList& obstacles, int side,
                                       std::size_t steps) {
  const SweepSide& w = sweep_sides_[static_cast<std::size_t>(side)];
  const std::size_t gathered = sweep_count_;
  if (gathered == 0) return steps;
  const HullBox box{params_.bow_ahead_m - params_.hull_length_m, params_.bow_ahead_m,
                    params_.half_beam_m};
  // The turn is a rotation about the turning centre: keep the segments whose distances from it
  // come within the room of the hull box's.
  std::size_t n = 0;
  for (std::size_t i = 0; i < gathered; ++i) {
    const auto& seg = obstacles.segments[sweep_index_[i]];
    const double room = sweep_room_m_[i] + kCullEps;
    const double af = seg.begin.forward_m - w.centre_f_m;
    const double as = seg.begin.starboard_m - w.centre_s_m;
    const double bf = seg.end.forward_m - w.centre_f_m;
    const double bs = seg.end.starboard_m - w.centre_s_m;
    const double df = bf - af;
    const double ds = bs - as;
    const double dd = df * df + ds * ds;
    const double near_sq = point_segment_sq(0.0, 0.0, af, as, df, ds, dd > 0.0 ? 1.0 / dd : 0.0);
    const double far_sq = std::max(af * af + as * as, bf * bf + bs * bs);
    const double outer = w.box_far_m + room;
    const double inner = w.box_near_m - room;
    if (near_sq > outer * outer || (inner > 0.0 && far_sq < inner * inner)) continue;
    side_index_[n++] = static_cast<std::uint16_t>(i);
  }
  // The first step at which any of them comes within its room of the hull box: each segment is
  // stepped through only up to the first hit found so far (the answer is the least step over
  // the segments, whatever their order), the box-centre distance tested two steps at a time.
  std::size_t first_hit = steps;
  for (std::size_t m = 0; m < n; ++m) {
    const std::size_t i = side_index_[m];
    const auto& seg = obstacles.segments[sweep_index_[i]];
    // The hull box lies within box_radius_m_ of its centre: a segment farther than that plus
    // the room from the centre cannot touch it.
    const double af = seg.begin.forward_m;
    const double as = seg.begin.starboard_m;
    const double df = seg.end.forward_m - af;
    const double ds = seg.end.starboard_m - as;
    const double dd = df * df + ds * ds;
    const double inv_dd = dd > 0.0 ? 1.0 / dd : 0.0;
    const double reach = box_radius_m_ + sweep_room_m_[i] + kCullEps;
    const auto touches = [&](std::size_t k) {
      const double c = w.cos[k];
      const double sn = w.sin[k];
      const auto to_future = [&](const core::BodyPoint& q, double& f, double& s_m) {
        const double qf = q.forward_m - w.origin_f_m[k];
        const double qs = q.starboard_m - w.origin_s_m[k];
        f = qf * c + qs * sn;
        s_m = -qf * sn + qs * c;
      };
      double fa = 0.0;
      double sa = 0.0;
      double fb = 0.0;
      double sb = 0.0;
      to_future(seg.begin, fa, sa);
      to_future(seg.end, fb, sb);
      return segment_box_closer_than(fa, sa, fb, sb, box, sweep_room_m_[i]);
    };
    if (lanes_usable_ && within_lanes(af, as, seg.end.forward_m, seg.end.starboard_m)) {
      // Four steps at a time in floats, the reach widened by kLaneEpsM (a segment shorter than
      // 1e-6 m is taken as its first end, which moves it less than that).
      const V4f v_af = splat4(static_cast<float>(af));
      const V4f v_as = splat4(static_cast<float>(as));
      const V4f v_df = splat4(static_cast<float>(df));
      const V4f v_ds = splat4(static_cast<float>(ds));
      const V4f v_inv = splat4(dd > 1e-12 ? static_cast<float>(inv_dd) : 0.0F);
      const auto lane_reach = static_cast<float>(reach + kLaneEpsM);
      const V4f v_reach_sq = splat4(lane_reach * lane_reach);
      for (std::size_t k = 0; k < first_hit; k += 4) {
        const V4f near = point_segment_sq(load4(&w.lane_box_f_m[k]), load4(&w.lane_box_s_m[k]),
                                          v_af, v_as, v_df, v_ds, v_inv);
        const unsigned in = bits4(near <= v_reach_sq);
        if (in == 0) continue;
        std::size_t hit = first_hit;
        for (std::size_t lane = 0; lane < 4 && k + lane < first_hit; ++lane) {
          if ((in & (1U << lane)) != 0 && touches(k + lane)) {
            hit = k + lane;
            break;
          }
        }
        if (hit < first_hit) {
          first_hit = hit;
          break;
        }
      }
      continue;
    }
    for (std::size_t k = 0; k < first_hit; ++k) {  // far off: every step, exactly
      if (touches(k)) {
        first_hit = k;
        break;
      }
    }
  }
  return first_hit;
}

void Avoidance::compute_path_ranges(const perception::ObstacleList& obstacles) {
  const std::size_t n_bins = bins_.size();
  if (!params_.sweep_enabled) {
    for (std::size_t j = 0; j < n_bins; ++j) range_m_[j] = bins_.range_m(j);
    return;
  }
  // Selection and score read a range only as "below the detection range or not" (every limit
  // they compare it with is at most that range, and the room they sum is capped there): for them
  // a bin starts at the detection range, and a segment or bin that cannot come nearer along the
  // path is passed over. The risk bins' danger reads the range itself: every range counts.
  const double w = params_.half_beam_m + params_.clearance_m;
  const bool capped = path_ranges_capped();
  const double start_m = path_range_start_m();
  for (std::size_t j = 0; j < n_bins; ++j) {
    range_m_[j] = start_m;
    bin_lanes_.range_m[j] = static_cast<float>(start_m);
  }
  const double reach = capped
                           ? path_reach_m_
                           : params_.detection_range_m + params_.sweep_turn_radius_m * core::kPi +
                                 std::abs(params_.pivot_ahead_m);
  const std::uint32_t count =
      std::min<std::uint32_t>(obstacles.count, perception::ObstacleList::kMaxSegments);
  for (std::uint32_t k = 0; k < count; ++k) {
    const std::optional<SegmentEnds> ends = finite_ends(obstacles.segments[k]);
    if (!ends) continue;
    const auto [af, as, bf, bs] = *ends;
    if (point_segment_farther_than(0.0, 0.0, af, as, bf, bs, reach)) continue;
    if (lanes_usable_ && within_lanes(af, as, bf, bs)) {
      cull_path_ranges(af, as, bf, bs, w, capped);
    } else {
      for (std::size_t j = 0; j < n_bins; ++j) path_range_exact(j, af, as, bf, bs, w);
    }
  }
}

void Avoidance::cull_path_ranges(double af, double as, double bf, double bs, double w,
                                 bool capped) {
  // The segment's bounding circle first decides which blocks of bins it can reach at all (by
  // their wedge), then its two ends decide each bin of a block that passes (not both beyond one
  // side of the corridor, not both behind the turn's end, the nearer near enough to lower the
  // range). Every bound is widened by kLaneEpsM, so float rounding (under 1e-4 m within
  // kLaneLimitM) never culls a bin the exact test would lower.
  const double half_len = 0.5 * std::sqrt((bf - af) * (bf - af) + (bs - as) * (bs - as));
  const auto mid_f = static_cast<float>(0.5 * (af + bf));
  const auto mid_s = static_cast<float>(0.5 * (as + bs));
  const auto lateral = static_cast<float>(w + half_len + kLaneEpsM);
  const auto near_back = static_cast<float>(half_len + kLaneEpsM);
  const auto eps = static_cast<float>(kLaneEpsM);
  const V4f v_mid_f = splat4(mid_f);
  const V4f v_mid_s = splat4(mid_s);
  const V4f v_zero = splat4(0.0F);
  const V4f v_a_f = splat4(static_cast<float>(af));
  const V4f v_a_s = splat4(static_cast<float>(as));
  const V4f v_b_f = splat4(static_cast<float>(bf));
  const V4f v_b_s = splat4(static_cast<float>(bs));
  const V4f v_half_width = splat4(static_cast<float>(w + kLaneEpsM));
  const V4f v_neg_eps = splat4(-eps);
  // A bin lowered by the segment has its middle within `lateral` of the corridor's centre line,
  // between `behind` and ahead_m + near_back along it from the bin's arc end: within their sum
  // of that arc end, so within that plus radius_m of the block's origin.
  const V4f v_bound_extra = splat4(near_back + lateral + eps);
  const V4f v_wedge_extra = splat4(lateral + eps);
  const BlockLanes& bl = block_lanes_;
  for (std::size_t b = 0; b < block_count_; b += 4) {
    const V4f qf = v_mid_f - load4(&bl.origin_f_m[b]);  // the middle from each block's origin
    const V4f qs = v_mid_s - load4(&bl.origin_s_m[b]);
    V4i pass = load4i(&bl.live[b]);
    if (capped) {
      const V4f bound = load4(&bl.reach_m[b]) + v_bound_extra;
      pass &= qf * qf + qs * qs <= bound * bound;
    }
    const V4f margin = load4(&bl.radius_m[b]) + v_wedge_extra;
    const V4i outside = (load4(&bl.lo_cos[b]) * qs - load4(&bl.lo_sin[b]) * qf < -margin) |
                        (load4(&bl.hi_cos[b]) * qs - load4(&bl.hi_sin[b]) * qf > margin);
    pass &= ~(outside & load4i(&bl.wedge[b]));
    const unsigned blocks = bits4(pass);
    if (blocks == 0) continue;
    for (std::size_t lane = 0; lane < 4; ++lane) {
      if ((blocks & (1U << lane)) == 0) continue;
      const std::size_t j0 = (b + lane) * kBlockBins;
      for (std::size_t j = j0; j < j0 + kBlockBins; j += 4) {  // bins past the last never pass
        const V4f c = load4(&bin_lanes_.cos[j]);
        const V4f sn = load4(&bin_lanes_.sin[j]);
        const V4f ef = load4(&bin_lanes_.arc_end_f_m[j]);
        const V4f es = load4(&bin_lanes_.arc_end_s_m[j]);
        const V4f pa_f = v_a_f - ef;
        const V4f pa_s = v_a_s - es;
        const V4f pb_f = v_b_f - ef;
        const V4f pb_s = v_b_s - es;
        const V4f f0 = pa_f * c + pa_s * sn;
        const V4f s0 = pa_s * c - pa_f * sn;
        const V4f f1 = pb_f * c + pb_s * sn;
        const V4f s1 = pb_s * c - pb_f * sn;
        const V4i out = ((s0 > v_half_width) & (s1 > v_half_width)) |
                        ((s0 < -v_half_width) & (s1 < -v_half_width)) |
                        ((f0 < v_neg_eps) & (f1 < v_neg_eps)) |
                        (load4(&bin_lanes_.arc_len_m[j]) + max4(v_zero, (f0 < f1 ? f0 : f1)) >=
                         load4(&bin_lanes_.range_m[j]) + splat4(eps));
        const unsigned near = bits4(~out);
        if (near == 0) continue;
        for (std::size_t i = 0; i < 4; ++i) {
          if ((near & (1U << i)) != 0) path_range_exact(j + i, af, as, bf, bs, w);
        }
      }
    }
  }
}

void Avoidance::path_range_exact(std::size_t j, double af, double as, double bf, double bs,
                                 double w) {
  const double entry_m = corridor_entry_m(j, af, as, bf, bs, w);
  if (!(entry_m < range_m_[j])) return;
  range_m_[j] = entry_m;
  bin_lanes_.range_m[j] = static_cast<float>(range_m_[j]);
}

double Avoidance::corridor_entry_m(std::size_t j, double af, double as, double bf, double bs,
                                   double w) const {
  // The segment in the frame of the boat at the end of the turn onto bin j.
  const double c = arc_cos_[j];
  const double sn = arc_sin_[j];
  const double pf = af - arc_end_f_m_[j];
  const double ps = as - arc_end_s_m_[j];
  const double qf = bf - arc_end_f_m_[j];
  const double qs = bs - arc_end_s_m_[j];
  const double f0 = pf * c + ps * sn;
  const double s0 = -pf * sn + ps * c;
  const double f1 = qf * c + qs * sn;
  const double s1 = -qf * sn + qs * c;
  // The part of it inside the corridor ahead: |s| <= w and f >= 0.
  double t_lo = 0.0;
  double t_hi = 1.0;
  const auto keep = [&](double v0, double v1) {  // keeps v(t) = v0 + (v1 - v0) t >= 0
    // Both ends kept: the root lies outside (0, 1) whatever the rounding (|dv| <= the larger
    // end), so neither t_lo nor t_hi would move; the division is skipped.
    if (v0 >= 0.0 && v1 >= 0.0) return;
    const double dv = v1 - v0;
    if (std::abs(dv) < 1e-15) {
      if (v0 < 0.0) t_lo = 2.0;
      return;
    }
    const double root = -v0 / dv;
    if (dv > 0.0) {
      t_lo = std::max(t_lo, root);
    } else {
      t_hi = std::min(t_hi, root);
    }
  };
  keep(w + s0, w + s1);
  keep(w - s0, w - s1);
  keep(f0, f1);
  if (t_lo > t_hi) return kInf;
  const double f_near = std::min(f0 + (f1 - f0) * t_lo, f0 + (f1 - f0) * t_hi);
  return arc_len_m_[j] + std::max(0.0, f_near);
}

void Avoidance::open_path_bins(const perception::ObstacleList& obstacles, std::size_t goal_bin) {
  const double w = params_.half_beam_m + params_.path_clearance_m;
  // As compute_path_ranges: a capped range starts at the detection range, and a segment that
  // cannot come nearer along any bin's path cannot lower it.
  const bool capped = path_ranges_capped();
  const double start_m = path_range_start_m();
  const auto span = static_cast<std::size_t>(std::max(0, params_.path_bins));
  const std::size_t lo = goal_bin > span ? goal_bin - span : 0;
  const std::size_t hi = std::min(bins_.size(), goal_bin + span + 1);
  // The bins of the window not worked out for this geometry yet (a new scan: all of them; a
  // tick between scans: those the goal's bearing has drifted onto, mostly none).
  std::size_t stale_lo = hi;
  std::size_t stale_hi = lo;
  for (std::size_t j = lo; j < hi; ++j) {
    if (narrow_stamp_[j] == geometry_stamp_) continue;
    narrow_stamp_[j] = geometry_stamp_;
    narrow_range_m_[j] = start_m;
    stale_lo = std::min(stale_lo, j);
    stale_hi = j + 1;
  }
  if (stale_lo < stale_hi) {
    const std::uint32_t count =
        std::min<std::uint32_t>(obstacles.count, perception::ObstacleList::kMaxSegments);
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::optional<SegmentEnds> ends = finite_ends(obstacles.segments[k]);
      if (!ends) continue;
      const auto [af, as, bf, bs] = *ends;
      if (capped && point_segment_farther_than(0.0, 0.0, af, as, bf, bs, path_reach_m_)) continue;
      // A bin between stale ones that was already worked out gets the same minimum again.
      for (std::size_t j = stale_lo; j < stale_hi; ++j) {
        narrow_range_m_[j] = std::min(narrow_range_m_[j], corridor_entry_m(j, af, as, bf, bs, w));
      }
    }
  }
  // Never narrower than the full corridor's (a narrower corridor meets less).
  for (std::size_t j = lo; j < hi; ++j) range_m_[j] = std::max(range_m_[j], narrow_range_m_[j]);
}

void Avoidance::compute_sweep(const perception::ObstacleList& obstacles) {
  sweep_port_deg_ = 180.0;
  sweep_starboard_deg_ = 180.0;
  if (!params_.sweep_enabled) return;
  // Segments within reach of the swept hull on either side, each with the room it must keep:
  // the clearance, or what it has now when it is already closer (so the boat may still turn
  // away from it). The same for both sides, so gathered once.
  sweep_count_ = 0;
  if (sweep_sides_[0].max_turn_deg > 0.0 || sweep_sides_[1].max_turn_deg > 0.0) {
    const HullBox box{params_.bow_ahead_m - params_.hull_length_m, params_.bow_ahead_m,
                      params_.half_beam_m};
    const double p = params_.pivot_ahead_m;
    const double clearance = params_.sweep_clearance_m;
    const double box_mid_m = 0.5 * (box.aft_m + box.fore_m);
    // Farthest any hull point gets from the pivot's start on an arc of up to 180 deg.
    const double hull_reach =
        std::hypot(std::max(std::abs(box.aft_m - p), std::abs(box.fore_m - p)), box.half_m);
    const double reach = 2.0 * params_.sweep_turn_radius_m + hull_reach + clearance;
    const std::uint32_t count =
        std::min<std::uint32_t>(obstacles.count, perception::ObstacleList::kMaxSegments);
    for (std::uint32_t k = 0; k < count; ++k) {
      const std::optional<SegmentEnds> ends = finite_ends(obstacles.segments[k]);
      if (!ends) continue;
      const auto [af, as, bf, bs] = *ends;
      if (point_segment_farther_than(p, 0.0, af, as, bf, bs, reach)) continue;
      // A segment clearly farther than the clearance from the box's circumcircle keeps the
      // clearance: its exact distance is wanted only when it may be nearer.
      const double df = bf - af;
      const double ds = bs - as;
      const double dd = df * df + ds * ds;
      const double clear = box_radius_m_ + clearance + kCullEps;
      const double now_m = point_segment_sq(box_mid_m, 0.0, af, as, df, ds,
                                            dd > 0.0 ? 1.0 / dd : 0.0) > clear * clear
                               ? clearance
                               : segment_box_distance(af, as, bf, bs, box);
      sweep_index_[sweep_count_] = static_cast<std::uint16_t>(k);
      sweep_room_m_[sweep_count_] = now_m >= clearance ? clearance : std::max(0.0, now_m - 1e-3);
      ++sweep_count_;
    }
  }
  // A turn of less than half a bin counts as straight on: never refused.
  const double half_bin = 0.5 * params_.fan.bin_width_deg;
  sweep_port_deg_ = std::max(half_bin, sweep_turn_limit(obstacles, 0));
  sweep_starboard_deg_ = std::max(half_bin, sweep_turn_limit(obstacles, 1));
}

AvoidanceDecision Avoidance::decide(const perception::ObstacleList& obstacles,
                                    double goal_bearing_body_deg, core::TimeNs now,
                                    bool planned_goal) {
  AvoidanceDecision out;
  const std::size_t n = bins_.size();
  out.bin_count = static_cast<std::uint32_t>(n);
  out.bin_min_deg = params_.fan.min_deg;
  out.bin_width_deg = params_.fan.bin_width_deg;
  goal_deg_ = std::isfinite(goal_bearing_body_deg) ? core::wrap_deg(goal_bearing_body_deg) : 0.0;
  if (params_.strategy == Strategy::kSelectionNaive2022) {
    decide_naive(obstacles, out);
    return out;
  }

  if (same_geometry(obstacles)) {
    std::copy_n(geometry_range_m_.begin(), n, range_m_.begin());
    sweep_port_deg_ = geometry_sweep_port_deg_;
    sweep_starboard_deg_ = geometry_sweep_starboard_deg_;
    out.nearest_m = geometry_nearest_m_;
  } else {
    const double hull_m = params_.half_beam_m + params_.clearance_m;
    if (params_.sweep_enabled) {
      // The bins' ranges are wanted only if the swept hull leaves no way out (below); their
      // least is found without them.
      out.nearest_m = bins_.nearest_m(obstacles, hull_m, params_.detection_range_m);
      bins_filled_ = false;
    } else {
      bins_.fill(obstacles, hull_m, params_.detection_range_m);
      out.nearest_m = bins_.min_range_m();
      bins_filled_ = true;
    }
    compute_sweep(obstacles);
    compute_path_ranges(obstacles);
    geometry_count_ =
        std::min<std::uint32_t>(obstacles.count, perception::ObstacleList::kMaxSegments);
    for (std::uint32_t k = 0; k < geometry_count_; ++k) {
      const auto& seg = obstacles.segments[k];
      geometry_segments_[k] = {seg.begin.forward_m, seg.begin.starboard_m, seg.end.forward_m,
                               seg.end.starboard_m};
    }
    std::copy_n(range_m_.begin(), n, geometry_range_m_.begin());
    geometry_sweep_port_deg_ = sweep_port_deg_;
    geometry_sweep_starboard_deg_ = sweep_starboard_deg_;
    geometry_nearest_m_ = out.nearest_m;
    geometry_valid_ = true;
    ++geometry_stamp_;
  }
  out.sweep_port_deg = sweep_port_deg_;
  out.sweep_starboard_deg = sweep_starboard_deg_;
  if (planned_goal && params_.sweep_enabled && params_.path_clearance_m >= 0.0 &&
      params_.path_clearance_m < params_.clearance_m) {
    const std::size_t goal_bin = bins_.index_of(goal_deg_);
    if (goal_bin < n) open_path_bins(obstacles, goal_bin);
  }

  // All blocked: shrink the range stepwise so only near obstacles count.
  const double full_limit = params_.strategy == Strategy::kRiskBin
                                ? std::min(params_.detection_range_m, params_.risk_range_m())
                                : params_.detection_range_m;
  double limit = full_limit;
  std::uint8_t steps = 0;
  const auto search = [&] {
    limit = full_limit;
    steps = 0;
    bool any = compute_costs(limit);
    while (!any) {
      const double next = limit * params_.shrink_factor;
      if (next < params_.min_detection_range_m) break;
      limit = next;
      ++steps;
      any = compute_costs(limit);
    }
    return any;
  };
  bool found = search();
  if (!found && params_.sweep_enabled) {
    // The predicted arcs leave no way out (a boat at rest turns tighter than the arc, and a
    // stop would hold it there for good): fall back to the plain rays from the bow, slowly.
    sweep_port_deg_ = 180.0;
    sweep_starboard_deg_ = 180.0;
    out.sweep_port_deg = sweep_port_deg_;
    out.sweep_starboard_deg = sweep_starboard_deg_;
    if (!bins_filled_) {
      bins_.fill(obstacles, params_.half_beam_m + params_.clearance_m, params_.detection_range_m);
      bins_filled_ = true;
    }
    for (std::size_t j = 0; j < n; ++j) range_m_[j] = bins_.range_m(j);
    found = search();
    if (found) steps = std::max<std::uint8_t>(steps, 1);
  }
  out.shrink_steps = steps;
  out.effective_range_m = limit;
  fill_danger(out, limit);

  if (!found) {
    out.bearing_body_deg = bins_.center_deg(most_open_bin(goal_deg_));
    if (params_.all_blocked_policy == AllBlockedPolicy::kBackOff) {
      out.status = AvoidanceStatus::kBackOff;
      out.speed_factor = -params_.back_off_speed_factor;
    } else {
      out.status = AvoidanceStatus::kBlockedStop;
      out.speed_factor = 0.0;
    }
    out.side = prev_side_;
    return out;
  }

  // The goal's bin, or the fan edge nearest the goal when it lies outside the fan.
  std::size_t goal_bin = bins_.index_of(goal_deg_);
  const bool goal_in_fan = goal_bin < n;
  if (!goal_in_fan) {
    goal_bin = std::abs(core::angle_diff_deg(goal_deg_, params_.fan.min_deg)) <
                       std::abs(core::angle_diff_deg(goal_deg_, params_.fan.max_deg))
                   ? 0
                   : n - 1;
  }

  const core::TimeNs hold_ns = core::sec_to_ns(params_.hold_time_s);
  if (prev_side_ != Side::kNone &&
      (side_used_ns_ == core::kNeverNs || now - side_used_ns_ > hold_ns)) {
    reset();  // clear for longer than the hold time: the old side no longer means anything
  }

  double best_cost = kInf;
  for (std::size_t j = 0; j < n; ++j) best_cost = std::min(best_cost, cost_[j]);
  const double speed = speed_for(out.nearest_m);
  out.speed_factor = steps > 0 ? std::min(speed, params_.blocked_speed_factor) : speed;

  if (cost_[goal_bin] < kInf &&
      (cost_[goal_bin] <= best_cost || tied(cost_[goal_bin], best_cost))) {
    out.bearing_body_deg = goal_in_fan ? goal_deg_ : bins_.center_deg(goal_bin);
    out.status = steps > 0                    ? AvoidanceStatus::kBlockedSlow
                 : range_m_[goal_bin] < limit ? AvoidanceStatus::kAvoiding
                                              : AvoidanceStatus::kClear;
    out.side = Side::kNone;
    return out;
  }

  // Best bin on each side of the goal, then which side: cost, hysteresis and hold time.
  const std::size_t port = best_in(0, goal_bin, goal_deg_);
  const std::size_t stbd = best_in(goal_bin + 1, n, goal_deg_);
  const double cp = port < n ? cost_[port] : kInf;
  const double cs = stbd < n ? cost_[stbd] : kInf;
  const auto cost_of = [&](Side s) { return s == Side::kPort ? cp : cs; };
  Side side = Side::kNone;
  if (cp < kInf && cs < kInf && tied(cp, cs)) {
    // Exact tie: the smaller turn, then the previous side, then the more open side, then
    // starboard (COLREG rule 14) -- never a fixed port bias.
    const double tp = std::abs(bins_.center_deg(port));
    const double ts = std::abs(bins_.center_deg(stbd));
    if (!tied(tp, ts)) {
      side = tp < ts ? Side::kPort : Side::kStarboard;
    } else if (prev_side_ != Side::kNone) {
      side = prev_side_;
    } else {
      const double window =
          std::min(std::abs(core::angle_diff_deg(goal_deg_, params_.fan.min_deg)),
                   std::abs(core::angle_diff_deg(params_.fan.max_deg, goal_deg_)));
      const double rp = free_room(Side::kPort, window, limit);
      const double rs = free_room(Side::kStarboard, window, limit);
      side = rp > rs && !tied(rp, rs) ? Side::kPort : Side::kStarboard;
    }
  } else {
    // At least one side is finite: some bin is allowed and, the goal bin not being the best,
    // the best lies on a side.
    side = cp < cs ? Side::kPort : Side::kStarboard;
  }
  if (prev_side_ != Side::kNone && side != prev_side_ && cost_of(prev_side_) < kInf) {
    const bool holding = side_since_ns_ != core::kNeverNs && now - side_since_ns_ < hold_ns;
    const bool clearly_better =
        cost_of(side) + params_.hysteresis_deg * cost_per_deg_ < cost_of(prev_side_);
    if (holding || !clearly_better) side = prev_side_;
  }
  if (side != prev_side_) side_since_ns_ = now;
  prev_side_ = side;
  side_used_ns_ = now;

  out.bearing_body_deg = bins_.center_deg(side == Side::kPort ? port : stbd);
  out.side = side;
  out.status = steps > 0 ? AvoidanceStatus::kBlockedSlow : AvoidanceStatus::kAvoiding;
  return out;
}

bool Avoidance::same_geometry(const perception::ObstacleList& obstacles) const {
  const std::uint32_t count =
      std::min<std::uint32_t>(obstacles.count, perception::ObstacleList::kMaxSegments);
  if (!geometry_valid_ || count != geometry_count_) return false;
  // Bit for bit (so -0.0 and 0.0 differ and a NaN equals itself): the same inputs.
  const auto bits = [](double v) { return std::bit_cast<std::uint64_t>(v); };
  std::uint64_t differ = 0;
  for (std::uint32_t k = 0; k < count; ++k) {
    const auto& seg = obstacles.segments[k];
    const std::array<double, 4>& was = geometry_segments_[k];
    differ |= (bits(seg.begin.forward_m) ^ bits(was[0])) |
              (bits(seg.begin.starboard_m) ^ bits(was[1])) |
              (bits(seg.end.forward_m) ^ bits(was[2])) | (bits(seg.end.starboard_m) ^ bits(was[3]));
  }
  return differ == 0;
}

void Avoidance::decide_naive(const perception::ObstacleList& obstacles, AvoidanceDecision& out) {
  geometry_valid_ = false;  // the bins are used differently here
  bins_filled_ = false;
  // Faithful to the 2022 code: an obstacle counts only if one of its END angles lies inside
  // the fan; its distance is that of its FIRST point; the margin is a FIXED angle; the bins from
  // the smaller to the larger end angle (plus margin) are dangerous.
  const std::size_t n = bins_.size();
  bins_.clear();
  std::size_t dangerous = 0;
  for (std::size_t j = 0; j < n; ++j) cost_[j] = 0.0;
  const std::uint32_t count =
      std::min<std::uint32_t>(obstacles.count, perception::ObstacleList::kMaxSegments);
  for (std::uint32_t k = 0; k < count; ++k) {
    const auto& seg = obstacles.segments[k];
    const double a = bearing_of(seg.begin);
    const double b = bearing_of(seg.end);
    const double first_point_m = std::hypot(seg.begin.forward_m, seg.begin.starboard_m);
    const bool end_in_fan = (a >= params_.fan.min_deg && a <= params_.fan.max_deg) ||
                            (b >= params_.fan.min_deg && b <= params_.fan.max_deg);
    if (!end_in_fan || first_point_m > params_.detection_range_m) continue;
    const double lo = std::min(a, b) - params_.naive_margin_deg;
    const double hi = std::max(a, b) + params_.naive_margin_deg;
    for (std::size_t j = 0; j < n; ++j) {
      const double c = bins_.center_deg(j);
      if (c >= lo && c <= hi && cost_[j] < kInf) {
        cost_[j] = kInf;
        ++dangerous;
      }
    }
  }
  out.effective_range_m = params_.detection_range_m;
  out.danger.fill(0.0F);
  for (std::size_t j = 0; j < n; ++j) out.danger[j] = cost_[j] < kInf ? 0.0F : 1.0F;
  out.speed_factor = 1.0;
  if (dangerous == 0 || dangerous == n) {
    // "No obstacle, or obstacles everywhere: steer at the goal."
    out.bearing_body_deg = goal_deg_;
    out.status = dangerous == 0 ? AvoidanceStatus::kClear : AvoidanceStatus::kAvoiding;
    return;
  }
  // Scan port to starboard, keep the first strictly better: ties go to port.
  std::size_t best = n;
  double best_turn = kInf;
  double best_abs = kInf;
  for (std::size_t j = 0; j < n; ++j) {
    if (!(cost_[j] < kInf)) continue;
    const double c = bins_.center_deg(j);
    const double turn = std::abs(diff_deg(c, goal_deg_));
    if (turn < best_turn || (turn == best_turn && std::abs(c) < best_abs)) {
      best = j;
      best_turn = turn;
      best_abs = std::abs(c);
    }
  }
  const double c = bins_.center_deg(best);
  const std::size_t goal_bin = bins_.index_of(goal_deg_);
  out.bearing_body_deg = goal_bin == best ? goal_deg_ : c;
  out.status = goal_bin == best ? AvoidanceStatus::kClear : AvoidanceStatus::kAvoiding;
  out.side = goal_bin == best ? Side::kNone : (c < goal_deg_ ? Side::kPort : Side::kStarboard);
}

}  // namespace coxswain::guidance
