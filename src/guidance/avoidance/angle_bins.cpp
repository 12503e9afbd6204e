// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/angle_bins.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "coxswain/core/angles.hpp"

namespace coxswain::guidance {
namespace {

constexpr double kEps = 1e-9;

// Narrows [t_lo, t_hi] to the t where a + b * t >= 0. Returns false when nothing is left.
bool clip(double a, double b, double& t_lo, double& t_hi) {
  if (std::abs(b) < kEps) return a >= 0.0;
  const double root = -a / b;
  if (b > 0.0) {
    t_lo = std::max(t_lo, root);
  } else {
    t_hi = std::min(t_hi, root);
  }
  return t_lo <= t_hi;
}

}  // namespace

std::optional<std::string> AngleFan::validate() const {
  if (!std::isfinite(min_deg) || !std::isfinite(max_deg) || !std::isfinite(bin_width_deg)) {
    return "fan: angles must be finite";
  }
  const double span = max_deg - min_deg;
  if (!(span > 0.0) || span > 360.0 + 1e-9) return "fan: max_deg - min_deg must be in (0, 360]";
  if (!(bin_width_deg >= 0.1) || bin_width_deg > 10.0) {
    return "fan: bin_width_deg must be in [0.1, 10]";
  }
  const double n = span / bin_width_deg;
  if (std::abs(n - std::round(n)) > 1e-6) return "fan: span must be a whole number of bins";
  if (std::round(n) > static_cast<double>(AngleBins::kMaxBins)) return "fan: too many bins";
  return {};
}

bool AngleBins::configure(const AngleFan& fan) {
  if (fan.validate()) return false;
  fan_ = fan;
  const double span = fan.max_deg - fan.min_deg;
  count_ = static_cast<std::size_t>(std::lround(span / fan.bin_width_deg));
  for (std::size_t i = 0; i <= count_; ++i) {
    const double a = core::deg_to_rad(fan.min_deg + static_cast<double>(i) * fan.bin_width_deg);
    edge_cos_[i] = std::cos(a);
    edge_sin_[i] = std::sin(a);
  }
  for (std::size_t i = 0; i < count_; ++i) {
    const double a = core::deg_to_rad(center_deg(i));
    mid_cos_[i] = std::cos(a);
    mid_sin_[i] = std::sin(a);
  }
  clear();
  return true;
}

void AngleBins::clear() { range_m_.fill(kNoObstacle); }

std::size_t AngleBins::index_of(double bearing_deg) const {
  if (!std::isfinite(bearing_deg) || count_ == 0) return count_;
  const double u = core::wrap_deg_360(bearing_deg - fan_.min_deg);
  const auto i = static_cast<std::size_t>(std::floor(u / fan_.bin_width_deg));
  return std::min(i, count_);
}

double AngleBins::min_range_m() const {
  double m = kNoObstacle;
  for (std::size_t i = 0; i < count_; ++i) m = std::min(m, range_m_[i]);
  return m;
}

AngleBins::Runs AngleBins::candidate_bins(double from_deg, double sweep_deg) const {
  Runs r;
  const double w = fan_.bin_width_deg;
  const double span = static_cast<double>(count_) * w;
  if (sweep_deg >= 360.0) {
    r.begin[0] = 0;
    r.end[0] = count_;
    r.count = 1;
    return r;
  }
  const double u0 = core::wrap_deg_360(from_deg - fan_.min_deg);
  const double u1 = u0 + sweep_deg;
  const auto add = [&](double a, double b) {
    if (a >= span) return;
    const auto first = static_cast<std::size_t>(std::floor(a / w));
    const auto last = std::min(count_, static_cast<std::size_t>(std::floor(b / w)) + 1);
    if (first < last) {
      r.begin[r.count] = first;
      r.end[r.count] = last;
      ++r.count;
    }
  };
  add(u0, std::min(u1, 360.0));
  if (u1 >= 360.0) add(0.0, u1 - 360.0);
  return r;
}

namespace {

// The parameter of segment a + t d's closest point to the body origin.
double closest_t(double af, double as, double df, double ds) {
  const double dd = df * df + ds * ds;
  return dd < kEps ? 0.0 : std::clamp(-(af * df + as * ds) / dd, 0.0, 1.0);
}

}  // namespace

AngleBins::Closest AngleBins::closest_at(double af, double as, double df, double ds, double t) {
  return {t, std::hypot(af + t * df, as + t * ds)};
}

AngleBins::Closest AngleBins::closest_to_origin(double af, double as, double df, double ds) {
  return closest_at(af, as, df, ds, closest_t(af, as, df, ds));
}

template <class Visit>
void AngleBins::visit_bins(const perception::ObstacleSegment& seg, const Closest& closest,
                           double corridor_half_width_m, Visit&& visit) const {
  if (count_ == 0) return;
  const double af = seg.begin.forward_m;
  const double as = seg.begin.starboard_m;
  const double df = seg.end.forward_m - af;
  const double ds = seg.end.starboard_m - as;
  if (!std::isfinite(af) || !std::isfinite(as) || !std::isfinite(df) || !std::isfinite(ds)) {
    return;
  }
  const double r = std::max(0.0, corridor_half_width_m);
  const double t_star = closest.t;
  const double d_min = closest.d_m;

  // Which bins can be touched: the segment's angular interval (the short way round: a segment
  // not through the origin subtends less than 180 deg) widened by the largest margin.
  Runs runs;
  if (d_min <= r || d_min < 1e-6) {
    runs = candidate_bins(0.0, 360.0);
  } else {
    const double a_deg = core::rad_to_deg(std::atan2(as, af));
    const double b_deg = core::rad_to_deg(std::atan2(as + ds, af + df));
    const double sweep = core::angle_diff_deg(b_deg, a_deg);
    const double from = sweep >= 0.0 ? a_deg : b_deg;
    const double margin = core::rad_to_deg(std::asin(r / d_min)) + 1e-6;
    runs = candidate_bins(from - margin, std::abs(sweep) + 2.0 * margin);
  }

  for (int k = 0; k < runs.count; ++k) {
    for (std::size_t j = runs.begin[k]; j < runs.end[k]; ++j) {
      // Points of the segment that a hull steered inside bin j reaches: not more than r to port
      // of the bin's port edge, not more than r to starboard of its starboard edge, and ahead.
      // cross(u, P) = u.f * P.s - u.s * P.f is positive when P lies to starboard of u.
      double t_lo = 0.0;
      double t_hi = 1.0;
      const double cl0 = edge_cos_[j] * as - edge_sin_[j] * af;
      const double cld = edge_cos_[j] * ds - edge_sin_[j] * df;
      const double ch0 = edge_cos_[j + 1] * as - edge_sin_[j + 1] * af;
      const double chd = edge_cos_[j + 1] * ds - edge_sin_[j + 1] * df;
      const double al0 = mid_cos_[j] * af + mid_sin_[j] * as;
      const double ald = mid_cos_[j] * df + mid_sin_[j] * ds;
      if (!clip(cl0 + r, cld, t_lo, t_hi)) continue;
      if (!clip(r - ch0, -chd, t_lo, t_hi)) continue;
      if (!clip(al0, ald, t_lo, t_hi)) continue;
      // |P(t)|^2 is convex in t, so the closest point of the piece is the clamped minimiser:
      // the segment's own closest point, or the point at tc.
      const double tc = std::clamp(t_star, t_lo, t_hi);
      if (tc == t_star) {
        visit(j, d_min, 0.0, 0.0, true);
      } else {
        visit(j, d_min, af + tc * df, as + tc * ds, false);
      }
    }
  }
}

void AngleBins::fill(const perception::ObstacleList& list, double corridor_half_width_m,
                     double max_range_m) {
  clear();
  const std::uint32_t n = std::min<std::uint32_t>(
      list.count, static_cast<std::uint32_t>(perception::ObstacleList::kMaxSegments));
  for (std::uint32_t k = 0; k < n; ++k) {
    const auto& seg = list.segments[k];
    const double df = seg.end.forward_m - seg.begin.forward_m;
    const double ds = seg.end.starboard_m - seg.begin.starboard_m;
    const Closest closest = closest_to_origin(seg.begin.forward_m, seg.begin.starboard_m, df, ds);
    if (closest.d_m <= max_range_m) add_segment(seg, closest, corridor_half_width_m);
  }
}

void AngleBins::add_segment(const perception::ObstacleSegment& seg, double corridor_half_width_m) {
  const double df = seg.end.forward_m - seg.begin.forward_m;
  const double ds = seg.end.starboard_m - seg.begin.starboard_m;
  add_segment(seg, closest_to_origin(seg.begin.forward_m, seg.begin.starboard_m, df, ds),
              corridor_half_width_m);
}

void AngleBins::add_segment(const perception::ObstacleSegment& seg, const Closest& closest,
                            double corridor_half_width_m) {
  visit_bins(seg, closest, corridor_half_width_m,
             [this](std::size_t j, double d_min, double pf, double ps, bool at_closest) {
               if (at_closest) {
                 range_m_[j] = std::min(range_m_[j], d_min);  // the same point, the same hypot()
                 return;
               }
               // A point whose square is clearly beyond the bin's range cannot lower it: hypot()
               // only when it might.
               const double r_j = range_m_[j];
               if (pf * pf + ps * ps >= r_j * r_j * (1.0 + 1e-9)) return;
               range_m_[j] = std::min(r_j, std::hypot(pf, ps));
             });
}

double AngleBins::nearest_m(const perception::ObstacleList& list, double corridor_half_width_m,
                            double max_range_m) const {
  // fill() leaves in each bin the least of the distances its segments give it (a distance it
  // skips is above the bin's, so above the least of all): the least over all bins is the least
  // over every (segment, bin) pair, in any order. A segment gives no distance below its own
  // closest point's (but for rounding), so the segments are taken nearest first and the search
  // stops at the first that cannot come closer than what was found. They are ordered by squared
  // distances (the same order but for rounding, which the margins cover); hypot() only for
  // those visited.
  const std::uint32_t n = std::min<std::uint32_t>(
      list.count, static_cast<std::uint32_t>(perception::ObstacleList::kMaxSegments));
  std::array<double, perception::ObstacleList::kMaxSegments> closest_ts{};
  std::array<double, perception::ObstacleList::kMaxSegments> closest_sq{};
  std::array<std::uint16_t, perception::ObstacleList::kMaxSegments> order{};
  const double max_sq = max_range_m * max_range_m * (1.0 + 1e-9);
  std::uint32_t m = 0;
  for (std::uint32_t k = 0; k < n; ++k) {
    const auto& seg = list.segments[k];
    const double af = seg.begin.forward_m;
    const double as = seg.begin.starboard_m;
    const double df = seg.end.forward_m - af;
    const double ds = seg.end.starboard_m - as;
    const double t = closest_t(af, as, df, ds);
    const double x = af + t * df;
    const double y = as + t * ds;
    const double sq = x * x + y * y;
    if (!(sq <= max_sq)) continue;
    closest_ts[k] = t;
    // Insertion by distance (a list of at most kMaxSegments, mostly a few dozen).
    std::uint32_t at = m++;
    while (at > 0 && closest_sq[at - 1] > sq) {
      closest_sq[at] = closest_sq[at - 1];
      order[at] = order[at - 1];
      --at;
    }
    closest_sq[at] = sq;
    order[at] = static_cast<std::uint16_t>(k);
  }
  double nearest = kNoObstacle;
  for (std::uint32_t i = 0; i < m; ++i) {
    const double limit = (nearest * (1.0 + 1e-9) + 1e-12) * (1.0 + 1e-9);
    if (closest_sq[i] > limit * limit) break;
    const auto& seg = list.segments[order[i]];
    const double af = seg.begin.forward_m;
    const double as = seg.begin.starboard_m;
    const Closest closest =
        closest_at(af, as, seg.end.forward_m - af, seg.end.starboard_m - as, closest_ts[order[i]]);
    if (!(closest.d_m <= max_range_m)) continue;
    visit_bins(seg, closest, corridor_half_width_m,
               [&nearest](std::size_t, double d_min, double pf, double ps, bool at_closest) {
                 nearest = std::min(nearest, at_closest ? d_min : std::hypot(pf, ps));
               });
  }
  return nearest;
}

}  // namespace coxswain::guidance
