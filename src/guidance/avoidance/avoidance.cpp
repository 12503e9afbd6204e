// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/avoidance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "coxswain/core/angles.hpp"

namespace coxswain::guidance {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kTieEps = 1e-9;

bool tied(double a, double b) { return std::abs(a - b) <= kTieEps * (1.0 + std::abs(a)); }

double bearing_of(const core::BodyPoint& p) {
  return core::rad_to_deg(std::atan2(p.starboard_m, p.forward_m));
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

std::string AvoidanceParams::validate() const {
  if (std::string e = fan.validate(); !e.empty()) return e;
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
  return {};
}

double AvoidanceParams::risk_range_m() const {
  // e^(-g d + o) > t  <=>  d < (o - ln t) / g
  return (risk_offset - std::log(risk_threshold)) / risk_gain_per_m;
}

std::optional<Avoidance> Avoidance::create(const AvoidanceParams& params, std::string* error) {
  std::string e = params.validate();
  if (!e.empty()) {
    if (error != nullptr) *error = std::move(e);
    return std::nullopt;
  }
  return Avoidance(params);
}

Avoidance::Avoidance(const AvoidanceParams& params) : params_(params) {
  (void)bins_.configure(params.fan);  // validated by create()
  cost_per_deg_ = params.strategy == Strategy::kScore ? params.score_goal_weight / 180.0 : 1.0;
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
  for (std::size_t j = 0; j < n; ++j) {
    const double c = bins_.center_deg(j);
    const double d = bins_.range_m(j);
    const double turn = std::abs(core::angle_diff_deg(c, goal_deg_));
    double cost = kInf;
    if (params_.strategy == Strategy::kScore) {
      if (!(d < block_m)) {
        cost = params_.score_goal_weight * turn / 180.0;
        if (d < limit_m) {
          cost += params_.score_distance_weight * (1.0 - d / limit_m) +
                  params_.score_angle_weight * (1.0 - std::abs(c) / 180.0);
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
    const double tj = std::abs(core::angle_diff_deg(bins_.center_deg(j), goal_deg));
    const double tb = std::abs(core::angle_diff_deg(bins_.center_deg(best), goal_deg));
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
    const double off = sign * core::angle_diff_deg(bins_.center_deg(j), goal_deg_);
    if (off > 0.0 && off <= window_deg) {
      room += std::min(bins_.range_m(j), params_.detection_range_m) / limit_m;
    }
  }
  return room;
}

std::size_t Avoidance::most_open_bin(double goal_deg) const {
  std::size_t best = 0;
  for (std::size_t j = 1; j < bins_.size(); ++j) {
    const double rj = bins_.range_m(j);
    const double rb = bins_.range_m(best);
    if (rj > rb) {
      best = j;
    } else if (rj == rb) {
      const double tj = std::abs(core::angle_diff_deg(bins_.center_deg(j), goal_deg));
      const double tb = std::abs(core::angle_diff_deg(bins_.center_deg(best), goal_deg));
      // Nearer the goal; on a full tie the later (starboard) bin, the COLREG-preferred side.
      if (tj <= tb + kTieEps) best = j;
    }
  }
  return best;
}

double Avoidance::speed_for(double nearest_m) const {
  if (nearest_m >= params_.slow_down_range_m) return 1.0;
  const double f = std::max(0.0, nearest_m) / params_.slow_down_range_m;
  return params_.min_speed_factor + (1.0 - params_.min_speed_factor) * f;
}

void Avoidance::fill_danger(AvoidanceDecision& out, double limit_m) const {
  const std::size_t n = bins_.size();
  out.danger.fill(0.0F);
  for (std::size_t j = 0; j < n; ++j) {
    const double d = bins_.range_m(j);
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
          const double risk =
              params_.score_distance_weight * (1.0 - d / limit_m) +
              params_.score_angle_weight * (1.0 - std::abs(bins_.center_deg(j)) / 180.0);
          danger = w > 0.0 ? std::clamp(risk / w, 0.0, 1.0) : 0.0;
        } else if (d < params_.detection_range_m) {
          danger = 0.5;  // seen, but beyond the shrunken range
        }
        break;
      default:
        danger = d < limit_m ? 1.0 : (d < params_.detection_range_m ? 0.5 : 0.0);
        break;
    }
    out.danger[j] = static_cast<float>(danger);
  }
}

AvoidanceDecision Avoidance::decide(const perception::ObstacleList& obstacles,
                                    double goal_bearing_body_deg, core::TimeNs now) {
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

  const double hull_m = params_.half_beam_m + params_.clearance_m;
  bins_.fill(obstacles, hull_m, params_.detection_range_m);
  out.nearest_m = bins_.min_range_m();

  // All blocked: shrink the range stepwise so only near obstacles count.
  double limit = params_.detection_range_m;
  if (params_.strategy == Strategy::kRiskBin) limit = std::min(limit, params_.risk_range_m());
  std::uint8_t steps = 0;
  bool found = compute_costs(limit);
  while (!found) {
    const double next = limit * params_.shrink_factor;
    if (next < params_.min_detection_range_m) break;
    limit = next;
    ++steps;
    found = compute_costs(limit);
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
    out.status = steps > 0                         ? AvoidanceStatus::kBlockedSlow
                 : bins_.range_m(goal_bin) < limit ? AvoidanceStatus::kAvoiding
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

void Avoidance::decide_naive(const perception::ObstacleList& obstacles, AvoidanceDecision& out) {
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
    const double turn = std::abs(core::angle_diff_deg(c, goal_deg_));
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
