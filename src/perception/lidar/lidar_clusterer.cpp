// SPDX-License-Identifier: Apache-2.0
#include "coxswain/perception/lidar_clusterer.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "coxswain/core/angles.hpp"
#include "coxswain/core/lanes.hpp"

namespace coxswain::perception {
namespace {

constexpr double kFullCircleDeg = 360.0;

using core::lanes::abs4;
using core::lanes::all4;
using core::lanes::and4;
using core::lanes::any4;
using core::lanes::load4;
using core::lanes::max4;
using core::lanes::splat4;
using core::lanes::store4;
using core::lanes::V2d;
using core::lanes::V4f;
using core::lanes::V4i;
using core::lanes::widen2;

// The float next to v towards +inf (up) or -inf (down) when v is not one: with it a float x
// compares as the double comparison with v would (x >= v <=> x >= up(v), x <= v <=> x <= down(v)).
float float_at_or_above(double v) {
  auto f = static_cast<float>(v);
  if (static_cast<double>(f) < v) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}
float float_at_or_below(double v) {
  auto f = static_cast<float>(v);
  if (static_cast<double>(f) > v) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

bool finite_nonneg(double v) { return std::isfinite(v) && v >= 0.0; }

// Distance from the body origin to the segment [a, b]: the true closest point, not an endpoint.
double origin_to_segment_m(const core::BodyPoint& a, const core::BodyPoint& b) {
  const double dx = b.forward_m - a.forward_m;
  const double dy = b.starboard_m - a.starboard_m;
  const double len_sq = dx * dx + dy * dy;
  double t = 0.0;
  if (len_sq > 0.0) {
    t = std::clamp(-(a.forward_m * dx + a.starboard_m * dy) / len_sq, 0.0, 1.0);
  }
  const double px = a.forward_m + t * dx;
  const double py = a.starboard_m + t * dy;
  return std::sqrt(px * px + py * py);
}

}  // namespace

LidarClusterParams LidarClusterParams::reference_tricat2022() {
  LidarClusterParams p;
  p.group_gap_m = 0.1;
  p.group_gap_per_m = 0.0;
  p.min_group_points = 10;  // their rule is "more than 10"
  p.split_distance_m = 0.1;
  p.split_distance_per_m = 0.0;
  p.wall_min_length_m = 0.3;
  p.wall_piece_max_length_m = 0.7;
  p.min_range_m = 0.15;  // rplidar_ros range_min / range_max of the recording
  p.max_range_m = 25.0;
  p.hull = HullBox{};
  p.line_fit = false;
  p.merge_across_seam = false;
  // Their first beam lies at theta_ros = angle_min = -(float)pi, i.e. body bearing +2.5e-6 deg;
  // 0.1 deg (under half a 0.265 deg beam step) starts the walk on exactly that beam.
  p.walk_start_bearing_deg = 0.1;
  p.walk_clockwise = false;
  p.semantics = ClusterSemantics::kTricat2022;
  return p;
}

std::optional<std::string> LidarClusterParams::validate() const {
  if (!finite_nonneg(group_gap_m) || !finite_nonneg(group_gap_per_m)) {
    return "group_gap_m and group_gap_per_m must be finite and >= 0";
  }
  if (group_gap_m <= 0.0 && group_gap_per_m <= 0.0) return "the group gap must be > 0";
  if (min_group_points < 1) return "min_group_points must be >= 1";
  if (!finite_nonneg(split_distance_m) || !finite_nonneg(split_distance_per_m)) {
    return "split_distance_m and split_distance_per_m must be finite and >= 0";
  }
  if (min_split_points < 2) return "min_split_points must be >= 2";
  if (!finite_nonneg(wall_min_length_m)) return "wall_min_length_m must be finite and >= 0";
  if (!std::isfinite(wall_piece_max_length_m) || wall_piece_max_length_m <= 0.0) {
    return "wall_piece_max_length_m must be finite and > 0";
  }
  if (!finite_nonneg(min_range_m) || !std::isfinite(max_range_m) || max_range_m <= min_range_m) {
    return "need 0 <= min_range_m < max_range_m, both finite";
  }
  if (!std::isfinite(hull.forward_min_m) || !std::isfinite(hull.forward_max_m) ||
      !std::isfinite(hull.starboard_min_m) || !std::isfinite(hull.starboard_max_m)) {
    return "hull box bounds must be finite";
  }
  if (!std::isfinite(profile_bin_width_deg) || profile_bin_width_deg <= 0.0) {
    return "profile_bin_width_deg must be > 0";
  }
  const double bins = std::round(kFullCircleDeg / profile_bin_width_deg);
  if (bins < 1.0 || bins > static_cast<double>(RangeProfile::kMaxBins) ||
      std::abs(bins * profile_bin_width_deg - kFullCircleDeg) > 1e-6) {
    return "profile_bin_width_deg must divide 360 into at most RangeProfile::kMaxBins bins";
  }
  if (!std::isfinite(walk_start_bearing_deg) || walk_start_bearing_deg < -180.0 ||
      walk_start_bearing_deg > 180.0) {
    return "walk_start_bearing_deg must lie in [-180, 180]";
  }
  return {};
}

LidarClusterer::LidarClusterer(const LidarClusterParams& params) : params_(params) {
  if (auto err = params_.validate()) {
    throw std::invalid_argument("LidarClusterParams: " + *err);
  }
  profile_bins_ =
      static_cast<std::uint32_t>(std::lround(kFullCircleDeg / params_.profile_bin_width_deg));
  int exponent = 0;
  const double mantissa = std::frexp(params_.profile_bin_width_deg, &exponent);
  bin_by_floor_ = mantissa == 0.5 && exponent <= 1 && profile_bins_ % 2 == 0;
  bins_per_deg_ = static_cast<float>(1.0 / params_.profile_bin_width_deg);
  half_bins_ = static_cast<std::int32_t>(profile_bins_ / 2);
  // A kept return has 0 < r, min <= r <= max: the smallest positive float stands for "> 0".
  min_range_f_ =
      std::max(float_at_or_above(params_.min_range_m), std::numeric_limits<float>::denorm_min());
  max_range_f_ = float_at_or_below(params_.max_range_m);
  trig_.resize(2 * (360 * static_cast<std::size_t>(kTrigStepsPerDeg) + 1));
  for (std::size_t i = 0; i < trig_.size() / 2; ++i) {
    const double a = core::deg_to_rad(-180.0 + static_cast<double>(i) / kTrigStepsPerDeg);
    trig_[2 * i] = static_cast<float>(std::cos(a));
    trig_[2 * i + 1] = static_cast<float>(std::sin(a));
  }
  constexpr std::size_t n = msg::LidarScan::kMaxPoints;
  x_m_.resize(3 * n);
  y_m_.resize(3 * n);
  range_m_.resize(3 * n);
  bearing_deg_.resize(3 * n);
  bin_.resize(3 * n);
  breaks_.resize(n);
  groups_.resize(n);
  stack_.resize(n + 2);
}

void LidarClusterer::process(const msg::LidarScan& scan, ObstacleList& out, RangeProfile& profile) {
  stats_ = LidarClusterStats{};
  out.clear();
  out.stamp_ns = scan.stamp_ns;
  out_ = &out;

  filter_points(scan);
  find_walk_start();
  group_points();
  for (std::uint32_t g = 0; g < group_count_; ++g) split_group(groups_[g]);

  profile.stamp_ns = scan.stamp_ns;
  fill_profile(profile);
  out_ = nullptr;
}

namespace {
constexpr float kRadPerDeg = static_cast<float>(3.14159265358979323846 / 180.0);
constexpr float kStepsPerDeg = static_cast<float>(LidarClusterer::kTrigStepsPerDeg);
}  // namespace

// The table entry below a bearing and the remainder past it in radians; then the turn by the
// remainder d: cos d = 1 - d^2 / 2 and sin d = d to a float's rounding (d < 4.4e-3 rad, so the
// terms left out are below 1.5e-8). One template for the scalar and the four-lane path, so a
// return's point is the same whichever path takes it.
template <class F, class I>
inline F table_step(F bearing_deg, I& index) {
  index = __builtin_convertvector((bearing_deg + 180.0F) * kStepsPerDeg, I);
  // The entry's own bearing is exact in floats, and so is the difference (both are multiples of
  // the bearing's last place): the remainder is rounded once, to radians.
  const F entry_deg = __builtin_convertvector(index, F) * (1.0F / kStepsPerDeg) - 180.0F;
  return (bearing_deg - entry_deg) * kRadPerDeg;
}
template <class F>
inline void turn_by(F d, F c0, F s0, F& cos_out, F& sin_out) {
  const F cd = 1.0F - d * d * 0.5F;
  cos_out = c0 * cd - s0 * d;
  sin_out = s0 * cd + c0 * d;
}

void LidarClusterer::unit_of(float bearing_deg, float& cos_out, float& sin_out) const {
  // Through the four-lane arithmetic with one lane used, so both paths agree bit for bit.
  V4i index;
  const V4f d = table_step(splat4(bearing_deg), index);
  const auto at = 2 * static_cast<std::size_t>(index[0]);
  V4f c;
  V4f sn;
  turn_by(d, splat4(trig_[at]), splat4(trig_[at + 1]), c, sn);
  cos_out = c[0];
  sin_out = sn[0];
}

std::int32_t LidarClusterer::bin_of(float bearing_deg) const {
  // The profile bin of the bearing; +180 is the -180 bin. The quotient is not negative (the
  // bearing lies in [-180, 180]), so truncation is the floor.
  const double shifted = static_cast<double>(bearing_deg) + 180.0;
  auto idx = static_cast<std::uint32_t>(shifted / params_.profile_bin_width_deg);
  if (idx >= profile_bins_) idx = std::min(idx - profile_bins_, profile_bins_ - 1);
  return static_cast<std::int32_t>(idx);
}

std::uint32_t LidarClusterer::append_checked(std::uint32_t kept, const msg::LidarPoint& p) {
  const float r = p.range_m;
  if (!(r >= min_range_f_ && r <= scan_max_range_f_)) return kept;
  float b = p.bearing_deg;
  if (!(b > -180.0F && b <= 180.0F)) {
    const double wrapped = core::wrap_deg(static_cast<double>(b));
    if (!std::isfinite(wrapped)) return kept;
    b = static_cast<float>(wrapped);
    if (b <= -180.0F) b = 180.0F;  // rounded onto the seam: the same direction
  }
  float c = 0.0F;
  float sn = 0.0F;
  unit_of(b, c, sn);
  const float x = r * c;
  const float y = r * sn;
  if (params_.hull.contains(static_cast<double>(x), static_cast<double>(y))) return kept;
  x_m_[kept] = x;
  y_m_[kept] = y;
  range_m_[kept] = r;
  bearing_deg_[kept] = b;
  bin_[kept] = bin_of(b);
  return kept + 1;
}

void LidarClusterer::filter_points(const msg::LidarScan& scan) {
  std::uint32_t n_in =
      std::min<std::uint32_t>(scan.point_count, static_cast<std::uint32_t>(scan.points.size()));
  stats_.points_in = n_in;
  scan_max_range_f_ = max_range_f_;
  if (scan.max_range_m > 0.0F) scan_max_range_f_ = std::min(max_range_f_, scan.max_range_m);
  const HullBox& hull = params_.hull;
  const bool hull_on = !hull.empty();
  const bool clockwise = params_.walk_clockwise;

  // The scan in walk direction (bearing ascending when clockwise, descending otherwise), four
  // returns at a time: when all four pass every check (the common case) they are appended as
  // they are, else append_checked() takes them one by one.
  float* xs = x_m_.data();
  float* ys = y_m_.data();
  float* rs = range_m_.data();
  float* bs = bearing_deg_.data();
  std::int32_t* bins = bin_.data();
  const float* trig = trig_.data();
  const V4f v_bins_per_deg = splat4(bins_per_deg_);
  const auto bin_count = static_cast<std::int32_t>(profile_bins_);
  const V4i v_half_bins = {half_bins_, half_bins_, half_bins_, half_bins_};
  const V4i v_bins = {bin_count, bin_count, bin_count, bin_count};
  const V4f v_min = splat4(min_range_f_);
  const V4f v_max = splat4(scan_max_range_f_);
  const V4f v_lo = splat4(-180.0F);
  const V4f v_hi = splat4(180.0F);
  // Hull bounds widened to the float at or beyond each: the box's edge itself stays inside.
  const V4f v_fmin = splat4(float_at_or_below(hull.forward_min_m));
  const V4f v_fmax = splat4(float_at_or_above(hull.forward_max_m));
  const V4f v_smin = splat4(float_at_or_below(hull.starboard_min_m));
  const V4f v_smax = splat4(float_at_or_above(hull.starboard_max_m));
  const msg::LidarPoint* points = scan.points.data();
  const std::ptrdiff_t step = clockwise ? 1 : -1;
  std::uint32_t kept = 0;
  std::uint32_t k = 0;
  for (; k + 3 < n_in; k += 4) {
    const msg::LidarPoint* q = clockwise ? points + k : points + (n_in - 1 - k);
    const msg::LidarPoint& p0 = q[0];
    const msg::LidarPoint& p1 = q[step];
    const msg::LidarPoint& p2 = q[2 * step];
    const msg::LidarPoint& p3 = q[3 * step];
    const V4f r = {p0.range_m, p1.range_m, p2.range_m, p3.range_m};
    const V4f b = {p0.bearing_deg, p1.bearing_deg, p2.bearing_deg, p3.bearing_deg};
    const V4i range_ok = (r >= v_min) & (r <= v_max);
    const V4i bearing_ok = (b > v_lo) & (b <= v_hi);
    // unit_of() on four lanes (an odd bearing looks up 0 deg; it takes the scalar path).
    V4i whole;
    const V4f d = table_step(and4(bearing_ok, b), whole);
    V4f c0;
    V4f s0;
    for (std::uint32_t lane = 0; lane < 4; ++lane) {
      const auto at = 2 * static_cast<std::size_t>(whole[lane]);
      c0[lane] = trig[at];
      s0[lane] = trig[at + 1];
    }
    V4f cs;
    V4f sn;
    turn_by(d, c0, s0, cs, sn);
    const V4f x = r * cs;
    const V4f y = r * sn;
    V4i keep = range_ok & bearing_ok;
    if (hull_on) keep &= ~((x >= v_fmin) & (x <= v_fmax) & (y >= v_smin) & (y <= v_smax));
    if (all4(keep)) {
      store4(xs + kept, x);
      store4(ys + kept, y);
      store4(rs + kept, r);
      store4(bs + kept, b);
      if (bin_by_floor_) {
        // floor(b * bins per degree) + half the bins, exact in floats; +180 is the -180 bin.
        const V4f scaled = b * v_bins_per_deg;
        V4i bin = __builtin_convertvector(scaled, V4i);
        bin += __builtin_convertvector(bin, V4f) > scaled;  // truncation to floor: -1 where above
        bin += v_half_bins;
        bin -= v_bins & (bin >= v_bins);
        std::memcpy(bins + kept, &bin, sizeof bin);
      } else {
        for (std::uint32_t lane = 0; lane < 4; ++lane) bins[kept + lane] = bin_of(b[lane]);
      }
      kept += 4;
      continue;
    }
    kept = append_checked(kept, p0);
    kept = append_checked(kept, p1);
    kept = append_checked(kept, p2);
    kept = append_checked(kept, p3);
  }
  for (; k < n_in; ++k) kept = append_checked(kept, points[clockwise ? k : n_in - 1 - k]);
  point_count_ = kept;
  stats_.points_kept = kept;
}

void LidarClusterer::find_walk_start() {
  // The first kept return at or past the start bearing in walk direction (clockwise: at or
  // after it; counter-clockwise: at or before it), else the first.
  const float* bs = bearing_deg_.data();
  const double start = params_.walk_start_bearing_deg;
  const std::uint32_t n = point_count_;
  walk_start_ = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto b = static_cast<double>(bs[i]);
    if (params_.walk_clockwise ? b >= start : b <= start) {
      walk_start_ = i;
      return;
    }
  }
}

void LidarClusterer::copy_points(std::uint32_t from, std::uint32_t count, std::uint32_t to) {
  std::copy_n(x_m_.data() + from, count, x_m_.data() + to);
  std::copy_n(y_m_.data() + from, count, y_m_.data() + to);
  std::copy_n(range_m_.data() + from, count, range_m_.data() + to);
  std::copy_n(bearing_deg_.data() + from, count, bearing_deg_.data() + to);
  std::copy_n(bin_.data() + from, count, bin_.data() + to);
}

void LidarClusterer::group_points() {
  group_count_ = 0;
  const std::uint32_t n = point_count_;
  if (n == 0) return;
  // The walk from walk_start_ is contiguous once the returns before it follow the last one.
  const std::uint32_t base = walk_start_;
  copy_points(0, base, n);

  // Where a new group starts: neighbours farther apart than the gap (squared distances, four
  // pairs at a time; a break is rare).
  const auto gap_m = static_cast<float>(params_.group_gap_m);
  const auto gap_per_m = static_cast<float>(params_.group_gap_per_m);
  const float* xs = x_m_.data() + base;
  const float* ys = y_m_.data() + base;
  const float* rs = range_m_.data() + base;
  const auto breaks_at = [&](std::uint32_t j) {
    const float dx = xs[j] - xs[j - 1];
    const float dy = ys[j] - ys[j - 1];
    const float limit = gap_m + gap_per_m * std::min(rs[j - 1], rs[j]);
    return dx * dx + dy * dy > limit * limit;
  };
  std::uint32_t* starts = breaks_.data();
  std::uint32_t count = 0;
  std::uint32_t j = 1;
  for (; j + 3 < n; j += 4) {
    const V4f dx = load4(xs + j) - load4(xs + j - 1);
    const V4f dy = load4(ys + j) - load4(ys + j - 1);
    const V4f r0 = load4(rs + j - 1);
    const V4f r1 = load4(rs + j);
    const V4f limit = gap_m + gap_per_m * (r0 < r1 ? r0 : r1);
    const V4i far = dx * dx + dy * dy > limit * limit;
    if (!any4(far)) continue;
    for (std::uint32_t lane = 0; lane < 4; ++lane) {
      if (far[lane] != 0) starts[count++] = j + lane;
    }
  }
  for (; j < n; ++j) {
    if (breaks_at(j)) starts[count++] = j;
  }

  const bool strict = params_.semantics == ClusterSemantics::kTricat2022;
  const std::uint32_t min_points = params_.min_group_points;
  const auto close_group = [&](std::uint32_t begin, std::uint32_t end) {
    const std::uint32_t size = end - begin;
    if (strict ? size > min_points : size >= min_points) {
      groups_[group_count_++] = Span{base + begin, base + end};
    } else {
      ++stats_.groups_dropped;
    }
  };
  // Seam merge: when the walk's last and first returns belong together, the walk starts at the
  // first break instead, so the wrapping group comes out contiguous (and last).
  if (params_.merge_across_seam && n > 1 && count > 0) {
    const float dx = xs[0] - xs[n - 1];
    const float dy = ys[0] - ys[n - 1];
    const float limit = gap_m + gap_per_m * std::min(rs[n - 1], rs[0]);
    if (!(dx * dx + dy * dy > limit * limit)) {
      stats_.seam_merged = true;
      const std::uint32_t first = starts[0];
      copy_points(base, first, base + n);
      for (std::uint32_t m = 0; m + 1 < count; ++m) close_group(starts[m], starts[m + 1]);
      close_group(starts[count - 1], n + first);
      stats_.groups = group_count_;
      return;
    }
  }
  std::uint32_t begin = 0;
  for (std::uint32_t m = 0; m < count; ++m) {
    close_group(begin, starts[m]);
    begin = starts[m];
  }
  close_group(begin, n);
  stats_.groups = group_count_;
}

std::uint32_t LidarClusterer::farthest_from_chord(Span s, double& max_d, double no_split_m) const {
  const float* xs = x_m_.data();
  const float* ys = y_m_.data();
  const float ax = xs[s.begin];
  const float ay = ys[s.begin];
  const float dx = xs[s.end - 1] - ax;
  const float dy = ys[s.end - 1] - ay;
  const float len = std::sqrt(dx * dx + dy * dy);
  // Distance to the chord's line (the source documents project onto the infinite line) is
  // |cross| / len, so the largest cross product marks the farthest return: no division per
  // return. A degenerate chord (first and last returns at one spot) measures from that spot.
  const bool chord = len > 0.0F;
  const V4f vax = splat4(ax);
  const V4f vay = splat4(ay);
  const V4f vdx = splat4(dx);
  const V4f vdy = splat4(dy);
  const auto values = [&](std::uint32_t i) {
    const V4f px = load4(xs + i) - vax;
    const V4f py = load4(ys + i) - vay;
    return chord ? abs4(px * vdy - py * vdx) : px * px + py * py;
  };
  const auto value = [&](std::uint32_t i) {
    const float px = xs[i] - ax;
    const float py = ys[i] - ay;
    return chord ? std::abs(px * dy - py * dx) : px * px + py * py;
  };
  // The largest value four lanes at a time without a branch, then the first return that has it.
  V4f top = splat4(0.0F);
  std::uint32_t i = s.begin;
  for (; i + 3 < s.end; i += 4) top = max4(top, values(i));
  float max_v = std::max(std::max(top[0], top[1]), std::max(top[2], top[3]));
  for (; i < s.end; ++i) max_v = std::max(max_v, value(i));
  max_d = chord ? static_cast<double>(max_v) / static_cast<double>(len)
                : std::sqrt(static_cast<double>(max_v));
  std::uint32_t k = s.begin;
  if (max_v > 0.0F && max_d > no_split_m) {
    i = s.begin;
    const V4f target = splat4(max_v);
    while (i + 3 < s.end && !any4(values(i) == target)) i += 4;
    while (value(i) != max_v) ++i;
    k = i;
  }
  return k;
}

void LidarClusterer::split_group(Span group) {
  // (B) Iterative farthest-from-chord splitting; the right half is pushed first so pieces come
  // out in walk order. Each split pops one span and pushes two, so the stack never exceeds the
  // number of returns.
  const bool tricat = params_.semantics == ClusterSemantics::kTricat2022;
  stack_size_ = 0;
  stack_[stack_size_++] = group;
  while (stack_size_ > 0) {
    const Span s = stack_[--stack_size_];
    double max_d = 0.0;
    // No split at or below the fixed part of the limit: then which return it is does not matter.
    const std::uint32_t k = farthest_from_chord(s, max_d, params_.split_distance_m);
    const double limit =
        params_.split_distance_m + params_.split_distance_per_m * static_cast<double>(range_m_[k]);
    bool split = max_d > limit;
    Span left{};
    Span right{};
    if (split) {
      if (tricat) {
        const std::uint32_t rel = k - s.begin;
        const std::uint32_t size = s.end - s.begin;
        split = rel >= params_.min_group_points && size - rel >= params_.min_group_points;
        left = Span{s.begin, k};
        right = Span{k, s.end};
      } else {
        left = Span{s.begin, k + 1};  // the split return ends one piece and starts the next
        right = Span{k, s.end};
        split = left.end - left.begin >= params_.min_split_points &&
                right.end - right.begin >= params_.min_split_points;
      }
    }
    if (split && stack_size_ + 2 <= stack_.size()) {
      stack_[stack_size_++] = right;
      stack_[stack_size_++] = left;
    } else {
      emit_piece(s);
    }
  }
}

void LidarClusterer::emit_piece(Span piece) {
  // (C) Classify by the chord between the first and last returns.
  const std::uint32_t a = piece.begin;
  const std::uint32_t b = piece.end - 1;
  const double dx = static_cast<double>(x_m_[b]) - static_cast<double>(x_m_[a]);
  const double dy = static_cast<double>(y_m_[b]) - static_cast<double>(y_m_[a]);
  if (dx * dx + dy * dy > params_.wall_min_length_m * params_.wall_min_length_m) {
    emit_wall(piece);
  } else {
    emit_segment(piece, ObstacleKind::kBuoy);
  }
}

void LidarClusterer::emit_wall(Span piece) {
  // (D) Cut the wall into bounded pieces.
  const double max_len = params_.wall_piece_max_length_m;
  const auto px = [&](std::uint32_t i) { return static_cast<double>(x_m_[i]); };
  const auto py = [&](std::uint32_t i) { return static_cast<double>(y_m_[i]); };
  if (params_.semantics == ClusterSemantics::kTricat2022) {
    std::uint32_t start = piece.begin;
    const double max_sq = max_len * max_len;
    for (std::uint32_t i = piece.begin; i < piece.end; ++i) {
      const double dx = px(i) - px(start);
      const double dy = py(i) - py(start);
      if (dx * dx + dy * dy > max_sq) {
        emit_segment(Span{start, i}, ObstacleKind::kWall);
        start = i;
      }
    }
    emit_segment(Span{start, piece.end}, ObstacleKind::kWall);
    return;
  }
  // Equal pieces along the chord; neighbours share their boundary return, so they touch.
  const double ax = px(piece.begin);
  const double ay = py(piece.begin);
  const double ex = px(piece.end - 1) - ax;
  const double ey = py(piece.end - 1) - ay;
  const double len = std::sqrt(ex * ex + ey * ey);
  const double count = std::ceil(len / max_len);
  if (count <= 1.0 || piece.end - piece.begin < 3) {
    emit_segment(piece, ObstacleKind::kWall);
    return;
  }
  const double ux = ex / len;
  const double uy = ey / len;
  const double step = len / count;
  double next_cut = step;
  std::uint32_t start = piece.begin;
  const float* xs = x_m_.data();
  const float* ys = y_m_.data();
  const auto along = [&](std::uint32_t i) { return (px(i) - ax) * ux + (py(i) - ay) * uy; };
  // The returns past the next cut: searched four at a time in floats, with a margin far above
  // their rounding (a few um at these ranges), the return found then decided in doubles.
  constexpr float kSearchMarginM = 1e-3F;
  const V4f vax = splat4(static_cast<float>(ax));
  const V4f vay = splat4(static_cast<float>(ay));
  const V4f vux = splat4(static_cast<float>(ux));
  const V4f vuy = splat4(static_cast<float>(uy));
  std::uint32_t i = piece.begin + 1;
  while (i + 1 < piece.end) {
    if (i + 4 < piece.end) {
      const V4f t = (load4(xs + i) - vax) * vux + (load4(ys + i) - vay) * vuy;
      if (!any4(t >= splat4(static_cast<float>(next_cut) - kSearchMarginM))) {
        i += 4;
        continue;
      }
    }
    if (along(i) >= next_cut) {
      emit_segment(Span{start, i + 1}, ObstacleKind::kWall);
      start = i;
      next_cut += step;
    }
    ++i;
  }
  emit_segment(Span{start, piece.end}, ObstacleKind::kWall);
}

void LidarClusterer::emit_segment(Span piece, ObstacleKind kind) {
  const std::uint32_t first = piece.begin;
  const std::uint32_t last = piece.end - 1;
  const float* xs = x_m_.data();
  const float* ys = y_m_.data();
  ObstacleSegment seg;
  seg.kind = kind;
  const double ox = static_cast<double>(xs[first]);
  const double oy = static_cast<double>(ys[first]);
  seg.begin = core::BodyPoint{ox, oy};
  seg.end = core::BodyPoint{static_cast<double>(xs[last]), static_cast<double>(ys[last])};
  const std::uint32_t n = piece.end - piece.begin;
  if (params_.line_fit && n >= 3) {
    // Total least squares: the line through the centroid along the principal axis; the segment
    // ends at the projections of the first and last returns. The moments are summed in doubles
    // in one pass about the first return (a piece is short, so nothing cancels), two returns at
    // a time.
    const V2d vox = {ox, ox};
    const V2d voy = {oy, oy};
    V2d sx2 = {0.0, 0.0};
    V2d sy2 = sx2;
    V2d sxx2 = sx2;
    V2d sxy2 = sx2;
    V2d syy2 = sx2;
    const auto add = [&](V2d dx, V2d dy) {
      sx2 += dx;
      sy2 += dy;
      sxx2 += dx * dx;
      sxy2 += dx * dy;
      syy2 += dy * dy;
    };
    std::uint32_t i = first;
    for (; i + 1 < piece.end; i += 2) add(widen2(xs + i) - vox, widen2(ys + i) - voy);
    if (i < piece.end) {
      add(V2d{static_cast<double>(xs[i]) - ox, 0.0}, V2d{static_cast<double>(ys[i]) - oy, 0.0});
    }
    const double sx = sx2[0] + sx2[1];
    const double sy = sy2[0] + sy2[1];
    const double mx = sx / static_cast<double>(n);  // centroid, relative to the first return
    const double my = sy / static_cast<double>(n);
    const double cxx = (sxx2[0] + sxx2[1]) - sx * mx;
    const double cxy = (sxy2[0] + sxy2[1]) - sx * my;
    const double cyy = (syy2[0] + syy2[1]) - sy * my;
    if (cxx + cyy > 0.0) {
      // The principal axis at half the angle of (cxx - cyy, 2 cxy), by the half-angle identity
      // (no trigonometry): (a + r, b) or, equally, (b, r - a), whichever does not cancel.
      const double a = cxx - cyy;
      const double b = 2.0 * cxy;
      const double r = std::sqrt(a * a + b * b);
      double vx = a >= 0.0 ? a + r : b;
      double vy = a >= 0.0 ? b : r - a;
      const double norm = std::sqrt(vx * vx + vy * vy);
      if (norm > 0.0) {
        vx /= norm;
        vy /= norm;
      } else {
        vx = 1.0;  // isotropic: any axis will do
        vy = 0.0;
      }
      const auto project = [&](std::uint32_t k) {
        const double t = (static_cast<double>(xs[k]) - ox - mx) * vx +
                         (static_cast<double>(ys[k]) - oy - my) * vy;
        return core::BodyPoint{ox + mx + t * vx, oy + my + t * vy};
      };
      seg.begin = project(first);
      seg.end = project(last);
    }
  }
  seg.closest_range_m = static_cast<float>(origin_to_segment_m(seg.begin, seg.end));
  seg.point_count = static_cast<std::uint16_t>(
      std::min<std::uint32_t>(n, std::numeric_limits<std::uint16_t>::max()));
  if (out_->push(seg)) {
    ++stats_.segments;
  } else {
    ++stats_.segments_overflow;
  }
}

void LidarClusterer::fill_profile(RangeProfile& profile) const {
  profile.bin_width_deg = static_cast<float>(params_.profile_bin_width_deg);
  profile.bin_count = profile_bins_;
  profile.closest_range_m.fill(RangeProfile::kNoReturn);
  // Only returns that survived the noise filter count: a lone spray return is not an obstacle.
  // Neighbouring returns mostly share a bin: the minimum is kept in a register until the bin
  // changes.
  float* slots = profile.closest_range_m.data();
  const std::int32_t* bins = bin_.data();
  const float* rs = range_m_.data();
  for (std::uint32_t g = 0; g < group_count_; ++g) {
    const Span s = groups_[g];
    std::int32_t bin = bins[s.begin];
    float closest = rs[s.begin];
    for (std::uint32_t i = s.begin + 1; i < s.end; ++i) {
      if (bins[i] != bin) {
        slots[bin] = std::min(slots[bin], closest);
        bin = bins[i];
        closest = rs[i];
      } else {
        closest = std::min(closest, rs[i]);
      }
    }
    slots[bin] = std::min(slots[bin], closest);
  }
}

}  // namespace coxswain::perception
