// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/docking_approach.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "coxswain/core/angles.hpp"

namespace coxswain::guidance {

std::optional<std::string> DockingApproachParams::validate() const {
  if (!(lookahead_m > 0.0)) return "docking: lookahead_m must be > 0";
  if (!(stop_range_m > 0.0)) return "docking: stop_range_m must be > 0";
  if (!(marker_gain > 0.0)) return "docking: marker_gain must be > 0";
  if (!(max_marker_turn_deg > 0.0)) return "docking: max_marker_turn_deg must be > 0";
  if (!(ahead_half_angle_deg > 0.0 && ahead_half_angle_deg <= 90.0)) {
    return "docking: ahead_half_angle_deg must be in (0, 90]";
  }
  return std::nullopt;
}

std::optional<double> min_range_ahead_m(const perception::RangeProfile& profile,
                                        double half_angle_deg) {
  const std::size_t bins = std::min<std::size_t>(profile.bin_count, profile.closest_range_m.size());
  const double w = static_cast<double>(profile.bin_width_deg);
  if (!(w > 0.0)) return std::nullopt;
  std::optional<double> best;
  for (std::size_t i = 0; i < bins; ++i) {
    const double centre_deg = -180.0 + (static_cast<double>(i) + 0.5) * w;
    if (std::abs(centre_deg) > half_angle_deg + 0.5 * w) continue;
    const float r = profile.closest_range_m[i];
    if (!(r > 0.0F) || r >= perception::RangeProfile::kNoReturn) continue;
    const double rd = static_cast<double>(r);
    if (!best || rd < *best) best = rd;
  }
  return best;
}

std::optional<std::size_t> slip_of_marker(std::span<const double> marker_bearings_deg,
                                          std::size_t target_index,
                                          std::span<const double> slip_bearings_deg,
                                          double window_deg) {
  if (target_index >= marker_bearings_deg.size() || slip_bearings_deg.empty()) return std::nullopt;
  const double target = marker_bearings_deg[target_index];
  if (marker_bearings_deg.size() == slip_bearings_deg.size()) {
    // Rank by counting (no sort, no allocation); ties broken by index so ranks are distinct.
    const auto rank_of = [](std::span<const double> v, std::size_t i) {
      std::size_t r = 0;
      for (std::size_t k = 0; k < v.size(); ++k) {
        if (v[k] < v[i] || (v[k] == v[i] && k < i)) ++r;
      }
      return r;
    };
    const std::size_t rank = rank_of(marker_bearings_deg, target_index);
    for (std::size_t j = 0; j < slip_bearings_deg.size(); ++j) {
      if (rank_of(slip_bearings_deg, j) == rank) return j;
    }
  }
  std::optional<std::size_t> best;
  double best_err = window_deg;
  for (std::size_t j = 0; j < slip_bearings_deg.size(); ++j) {
    const double err = std::abs(core::angle_diff_deg(slip_bearings_deg[j], target));
    if (err <= best_err) {
      best_err = err;
      best = j;
    }
  }
  return best;
}

std::optional<std::string> SlipFinderParams::validate() const {
  if (!(min_width_m > 0.0 && max_width_m > min_width_m)) {
    return "docking: slip widths need 0 < min_width_m < max_width_m";
  }
  if (!(min_depth_m > 0.0 && max_depth_m > min_depth_m)) {
    return "docking: slip depths need 0 < min_depth_m < max_depth_m";
  }
  if (!(max_bearing_deg > 0.0 && max_bearing_deg <= 180.0)) {
    return "docking: slip max_bearing_deg must be in (0, 180]";
  }
  if (!(max_range_m > 0.0)) return "docking: slip max_range_m must be > 0";
  if (!(max_axis_deg > 0.0 && max_axis_deg <= 180.0)) {
    return "docking: slip max_axis_deg must be in (0, 180]";
  }
  return std::nullopt;
}

namespace {

/// Every slip mouth in the sector, scored by `score_of` (lower is better; the best is returned).
/// A mouth is two tips -- returns nearer than every return within a few bins either side, as the
/// end of a finger or of a quay wall is, whether the wall is seen edge-on or along its face --
/// the right distance apart, with nothing between them nearer than the line joining them and the
/// inside reaching at least min_depth_m beyond it.
template <typename Score>
std::optional<SlipOpening> best_slip(const perception::RangeProfile& profile,
                                     const SlipFinderParams& params, double forward_body_deg,
                                     Score score_of) {
  const std::size_t bins = std::min<std::size_t>(profile.bin_count, profile.closest_range_m.size());
  const double w = static_cast<double>(profile.bin_width_deg);
  if (bins < 8 || !(w > 0.0)) return std::nullopt;
  const auto bearing = [w](std::size_t i) { return -180.0 + (static_cast<double>(i) + 0.5) * w; };
  const auto range = [&profile](std::size_t i) {
    const float r = profile.closest_range_m[i];
    return r > 0.0F && r < perception::RangeProfile::kNoReturn ? static_cast<double>(r) : -1.0;
  };
  const auto in_sector = [&](std::size_t i) {
    return std::abs(core::angle_diff_deg(bearing(i), forward_body_deg)) <= params.max_bearing_deg;
  };
  // Tips: local minima of range over +-kTipWindow bins (the first of a plateau).
  constexpr std::size_t kTipWindow = 3;
  constexpr std::size_t kMaxTips = 96;
  std::array<std::size_t, kMaxTips> tips{};
  std::size_t tip_count = 0;
  for (std::size_t i = 0; i < bins && tip_count < kMaxTips; ++i) {
    const double ri = range(i);
    if (ri < 0.0 || ri > params.max_range_m || !in_sector(i)) continue;
    bool minimum = true;
    for (std::size_t k = 1; k <= kTipWindow && minimum; ++k) {
      const double before = range((i + bins - k) % bins);
      const double after = range((i + k) % bins);
      minimum = !(before >= 0.0 && before <= ri) && !(after >= 0.0 && after < ri);
    }
    if (minimum) tips[tip_count++] = i;
  }
  std::optional<SlipOpening> best;
  double best_score = 0.0;
  for (std::size_t a = 0; a < tip_count; ++a) {
    const std::size_t i = tips[a];
    const double ri = range(i);
    const double bi = core::deg_to_rad(bearing(i));
    const double xi = ri * std::cos(bi);
    const double yi = ri * std::sin(bi);
    for (std::size_t b = 0; b < tip_count; ++b) {
      const std::size_t j = tips[b];
      // j lies to starboard of i, within the angle the widest slip could span.
      const std::size_t steps = (j + bins - i) % bins;
      if (steps < 2 || static_cast<double>(steps) * w > 120.0) continue;
      const double rj = range(j);
      const double bj = core::deg_to_rad(bearing(j));
      const double xj = rj * std::cos(bj);
      const double yj = rj * std::sin(bj);
      const double width = std::hypot(xj - xi, yj - yi);
      if (width < params.min_width_m || width > params.max_width_m) continue;
      // The chord runs port tip -> starboard tip; turned 90 deg to port it points inside.
      const double nx = (yj - yi) / width;
      const double ny = -(xj - xi) / width;
      const double axis_deg = core::rad_to_deg(std::atan2(ny, nx));
      if (std::abs(core::angle_diff_deg(axis_deg, forward_body_deg)) > params.max_axis_deg) {
        continue;
      }
      double deepest = 0.0;
      bool open = true;
      for (std::size_t step = 1; step < steps && open; ++step) {
        const std::size_t k = (i + step) % bins;
        const double rk = range(k);
        if (rk < 0.0) {  // nothing within range: open water through the gap, no back wall
          open = false;
          break;
        }
        const double bk = core::deg_to_rad(bearing(k));
        const double depth = (rk * std::cos(bk) - xi) * nx + (rk * std::sin(bk) - yi) * ny;
        open = depth > -0.1;  // something in the mouth: not a way in
        deepest = std::max(deepest, depth);
      }
      if (!open || deepest < params.min_depth_m || deepest > params.max_depth_m) continue;
      SlipOpening s;
      s.mouth_x_m = 0.5 * (xi + xj);
      s.mouth_y_m = 0.5 * (yi + yj);
      s.axis_body_deg = axis_deg;
      s.width_m = width;
      s.depth_m = deepest;
      const double score = score_of(s);
      if (!best || score < best_score) {
        best = s;
        best_score = score;
      }
    }
  }
  return best;
}

}  // namespace

std::optional<SlipOpening> find_slip(const perception::RangeProfile& profile,
                                     const SlipFinderParams& params, double forward_body_deg) {
  const double nominal = 0.5 * (params.min_width_m + params.max_width_m);
  return best_slip(profile, params, forward_body_deg,
                   [nominal](const SlipOpening& s) { return std::abs(s.width_m - nominal); });
}

std::optional<SlipOpening> find_slip_near(const perception::RangeProfile& profile,
                                          const SlipFinderParams& params, double forward_body_deg,
                                          core::BodyPoint expected_mouth, double max_offset_m) {
  auto best = best_slip(profile, params, forward_body_deg, [expected_mouth](const SlipOpening& s) {
    return std::hypot(s.mouth_x_m - expected_mouth.forward_m,
                      s.mouth_y_m - expected_mouth.starboard_m);
  });
  if (best && std::hypot(best->mouth_x_m - expected_mouth.forward_m,
                         best->mouth_y_m - expected_mouth.starboard_m) > max_offset_m) {
    return std::nullopt;
  }
  return best;
}

std::optional<SlipOpening> find_slip_toward(const perception::RangeProfile& profile,
                                            const SlipFinderParams& params, double forward_body_deg,
                                            double marker_bearing_deg, double marker_depth_m,
                                            double max_error_deg) {
  const auto error_of = [&](const SlipOpening& s) {
    const double a = core::deg_to_rad(s.axis_body_deg);
    const double x = s.mouth_x_m + marker_depth_m * std::cos(a);
    const double y = s.mouth_y_m + marker_depth_m * std::sin(a);
    return std::abs(core::angle_diff_deg(core::rad_to_deg(std::atan2(y, x)), marker_bearing_deg));
  };
  auto best = best_slip(profile, params, forward_body_deg, error_of);
  if (best && error_of(*best) > max_error_deg) return std::nullopt;
  return best;
}

FingersAlongside fingers_alongside(const perception::RangeProfile& profile, double max_side_m,
                                   double aft_m, double bow_ahead_m, double max_skew_m) {
  const std::size_t bins = std::min<std::size_t>(profile.bin_count, profile.closest_range_m.size());
  const double w = static_cast<double>(profile.bin_width_deg);
  FingersAlongside out;
  if (!(w > 0.0) || !(max_side_m > 0.0)) return out;
  // Nearest distance across the centre line of the returns in two bands along the hull, per
  // side: abeam of the lidar and `aft_m` behind it (each +-kBandM long).
  constexpr double kBandM = 0.25;
  constexpr double kNone = 1e9;
  std::array<std::array<double, 2>, 2> nearest{};  // [side: 0 port, 1 starboard][band]
  for (auto& side : nearest) side.fill(kNone);
  for (std::size_t i = 0; i < bins; ++i) {
    const float r = profile.closest_range_m[i];
    if (!(r > 0.0F) || r >= perception::RangeProfile::kNoReturn) continue;
    const double b = core::deg_to_rad(-180.0 + (static_cast<double>(i) + 0.5) * w);
    const double x = static_cast<double>(r) * std::cos(b);
    const double y = static_cast<double>(r) * std::sin(b);
    const std::size_t side = y < 0.0 ? 0 : 1;
    const double across = std::abs(y);
    if (x > bow_ahead_m) continue;
    if (std::abs(x) <= kBandM) nearest[side][0] = std::min(nearest[side][0], across);
    if (std::abs(x + aft_m) <= kBandM) nearest[side][1] = std::min(nearest[side][1], across);
  }
  const auto side_m = [&](std::size_t side) {
    const double abeam = nearest[side][0];
    const double aft = nearest[side][1];
    if (abeam > max_side_m || aft > max_side_m || std::abs(abeam - aft) > max_skew_m) return -1.0;
    return std::min(abeam, aft);
  };
  out.port_m = side_m(0);
  out.starboard_m = side_m(1);
  return out;
}

double slip_pursuit_bearing_deg(const SlipOpening& slip, double lookahead_m) {
  const double a = core::deg_to_rad(slip.axis_body_deg);
  const double ux = std::cos(a);
  const double uy = std::sin(a);
  // The boat is the origin: its projection on the axis, measured from the mouth.
  const double along = -(slip.mouth_x_m * ux + slip.mouth_y_m * uy);
  const double s = along + lookahead_m;
  return core::rad_to_deg(std::atan2(slip.mouth_y_m + s * uy, slip.mouth_x_m + s * ux));
}

bool DockingApproach::set_ray(core::NavPoint decision_point, core::NavPoint dock_point) {
  if (core::distance_m(decision_point, dock_point) < 0.1) return false;
  origin_ = decision_point;
  ray_bearing_deg_ = core::bearing_deg(decision_point, dock_point);
  has_ray_ = true;
  stopped_ = false;
  return true;
}

bool DockingApproach::check_stop(std::optional<double> range_ahead_m) {
  if (range_ahead_m && std::isfinite(*range_ahead_m) && *range_ahead_m < p_.stop_range_m) {
    stopped_ = true;
  }
  return stopped_;
}

DockingCommand DockingApproach::pursue(const core::NavPose& pose,
                                       std::optional<double> range_ahead_m) {
  DockingCommand c;
  c.stop = check_stop(range_ahead_m);
  c.desired_heading_deg = pose.heading_deg;
  if (!has_ray_) return c;
  const double a = core::deg_to_rad(ray_bearing_deg_);
  const double un = std::cos(a);
  const double ue = std::sin(a);
  const double pn = pose.position.north_m - origin_.north_m;
  const double pe = pose.position.east_m - origin_.east_m;
  c.along_ray_m = pn * un + pe * ue;
  c.cross_ray_m = -pn * ue + pe * un;
  // A ray, not a line: a boat still behind the decision point aims at the first metres of it.
  const double s = std::max(c.along_ray_m, 0.0) + p_.lookahead_m;
  c.aim = {origin_.north_m + s * un, origin_.east_m + s * ue};
  c.desired_heading_deg = core::bearing_deg(pose.position, c.aim);
  return c;
}

DockingCommand DockingApproach::hold_marker(double heading_deg,
                                            std::optional<double> marker_bearing_deg,
                                            std::optional<double> range_ahead_m) {
  DockingCommand c;
  c.stop = check_stop(range_ahead_m);
  double turn = 0.0;
  if (marker_bearing_deg && std::isfinite(*marker_bearing_deg)) {
    turn = std::clamp(p_.marker_gain * core::wrap_deg(*marker_bearing_deg), -p_.max_marker_turn_deg,
                      p_.max_marker_turn_deg);
  }
  c.desired_heading_deg = core::wrap_deg(heading_deg + turn);
  return c;
}

}  // namespace coxswain::guidance
