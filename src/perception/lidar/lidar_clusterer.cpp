// SPDX-License-Identifier: Apache-2.0
#include "coxswain/perception/lidar_clusterer.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "coxswain/core/angles.hpp"

namespace coxswain::perception {
namespace {

constexpr double kFullCircleDeg = 360.0;

bool finite_nonneg(double v) { return std::isfinite(v) && v >= 0.0; }

// hypot(dx, dy) > limit_m, decided on squares unless the two are within rounding of each other,
// where the exact comparison decides: the same answer as hypot, without its cost.
inline bool farther_than(double dx, double dy, double limit_m) {
  const double d2 = dx * dx + dy * dy;
  const double l2 = limit_m * limit_m;
  if (d2 > l2 * (1.0 + 1e-9)) return true;
  if (d2 < l2 * (1.0 - 1e-9)) return false;
  return std::hypot(dx, dy) > limit_m;
}

// Distance from the body origin to the segment [a, b]: the true closest point, not an endpoint.
double origin_to_segment_m(const core::BodyPoint& a, const core::BodyPoint& b) {
  const double dx = b.forward_m - a.forward_m;
  const double dy = b.starboard_m - a.starboard_m;
  const double len_sq = dx * dx + dy * dy;
  double t = 0.0;
  if (len_sq > 0.0) {
    t = std::clamp(-(a.forward_m * dx + a.starboard_m * dy) / len_sq, 0.0, 1.0);
  }
  return std::hypot(a.forward_m + t * dx, a.starboard_m + t * dy);
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
  constexpr std::size_t n = msg::LidarScan::kMaxPoints;
  beams_.resize(kBeamCapacity);
  fresh_beams_.resize(n);
  merged_beams_.resize(kBeamCapacity);
  scratch_x_m_.resize(n);
  scratch_y_m_.resize(n);
  scratch_range_m_.resize(n);
  scratch_bearing_deg_.resize(n);
  scratch_bin_.resize(n);
  x_m_.resize(n);
  y_m_.resize(n);
  range_m_.resize(n);
  bin_.resize(n);
  groups_.resize(n);
  stack_.resize(n + 2);
}

void LidarClusterer::process(const msg::LidarScan& scan, ObstacleList& out, RangeProfile& profile) {
  stats_ = LidarClusterStats{};
  out.clear();
  out.stamp_ns = scan.stamp_ns;
  out_ = &out;

  filter_points(scan);
  group_points();
  for (std::uint32_t g = 0; g < group_count_; ++g) split_group(groups_[g]);

  profile.stamp_ns = scan.stamp_ns;
  fill_profile(profile);
  out_ = nullptr;
}

const LidarClusterer::Beam& LidarClusterer::fresh_beam(float bearing_deg) {
  // Not cached: computed exactly as without the cache, and merged into the list after this
  // scan (one lookup per return, so fresh_beams_ has room).
  Beam& e = fresh_beams_[fresh_count_++];
  e = Beam{};
  e.raw_deg = bearing_deg;
  e.used_scan = beam_scan_;
  auto b = static_cast<double>(bearing_deg);
  if (!(b > -180.0 && b <= 180.0)) b = core::wrap_deg(b);
  if (!std::isfinite(b)) {
    e.bin = kNoBin;
    return e;
  }
  e.cos = std::cos(core::deg_to_rad(b));
  e.sin = std::sin(core::deg_to_rad(b));
  e.bearing_deg = static_cast<float>(b);
  // The profile bin of the stored (float) bearing; +180 is the -180 bin.
  const auto bins = static_cast<std::int64_t>(profile_bins_);
  auto idx = static_cast<std::int64_t>(
      std::floor((static_cast<double>(e.bearing_deg) + 180.0) / params_.profile_bin_width_deg));
  if (idx >= bins) idx -= bins;
  e.bin = static_cast<std::uint16_t>(std::clamp<std::int64_t>(idx, 0, bins - 1));
  return e;
}

void LidarClusterer::finish_beams() {
  // A fixed geometry keeps its entries through a few scans without a return; drifting angles
  // would only grow the list, so then the last scan's alone are kept.
  constexpr std::uint32_t kKeepUnusedScans = 8;
  const std::uint32_t lookups = beam_hits_ + fresh_count_;
  const std::uint32_t keep_scans = 2 * beam_hits_ >= lookups ? kKeepUnusedScans : 1;
  const bool prune = keep_scans != beam_keep_scans_ || beam_scan_ % kKeepUnusedScans == 0;
  beam_keep_scans_ = keep_scans;
  if (fresh_count_ > 0 || prune) {
    // Merge the kept entries and the new ones into one sorted list. Out-of-order or NaN
    // bearings (an unsorted scan) are simply not cached.
    std::uint32_t n = 0;
    std::uint32_t f = 0;
    const auto push = [&](const Beam& e) {
      if (n >= merged_beams_.size() || std::isnan(e.raw_deg)) return;
      if (n > 0 && !(merged_beams_[n - 1].raw_deg < e.raw_deg)) return;
      merged_beams_[n++] = e;
    };
    for (std::uint32_t i = 0; i < beam_count_; ++i) {
      const Beam& old = beams_[i];
      while (f < fresh_count_ && fresh_beams_[f].raw_deg < old.raw_deg) push(fresh_beams_[f++]);
      if (beam_scan_ - old.used_scan < beam_keep_scans_) push(old);
    }
    while (f < fresh_count_) push(fresh_beams_[f++]);
    beams_.swap(merged_beams_);
    beam_count_ = n;
  }
  ++beam_scan_;
  fresh_count_ = 0;
  beam_cursor_ = 0;
  beam_hits_ = 0;
}

void LidarClusterer::filter_points(const msg::LidarScan& scan) {
  const std::uint32_t n_in =
      std::min<std::uint32_t>(scan.point_count, static_cast<std::uint32_t>(scan.points.size()));
  stats_.points_in = n_in;
  double max_range_m = params_.max_range_m;
  if (scan.max_range_m > 0.0F)
    max_range_m = std::min(max_range_m, static_cast<double>(scan.max_range_m));

  // Pass 1: filters, in scan order (bearing ascending), into the scratch arrays.
  std::uint32_t kept = 0;
  for (std::uint32_t i = 0; i < n_in; ++i) {
    const msg::LidarPoint& p = scan.points[i];
    const auto r = static_cast<double>(p.range_m);
    if (!(r > 0.0) || !std::isfinite(r) || r < params_.min_range_m || r > max_range_m) continue;
    const Beam& b = beam(p.bearing_deg);
    if (b.bin == kNoBin) continue;
    const double x = r * b.cos;
    const double y = r * b.sin;
    if (params_.hull.contains(x, y)) continue;
    scratch_x_m_[kept] = x;
    scratch_y_m_[kept] = y;
    scratch_range_m_[kept] = static_cast<float>(r);
    scratch_bearing_deg_[kept] = b.bearing_deg;
    scratch_bin_[kept] = b.bin;
    ++kept;
  }
  finish_beams();
  point_count_ = kept;
  stats_.points_kept = kept;
  if (kept == 0) return;

  // The walk starts at walk_start_bearing_deg; group_points() reads the scratch arrays in walk
  // order through walk_source() and copies them once.
  const double start = params_.walk_start_bearing_deg;
  if (params_.walk_clockwise) {
    std::uint32_t s = 0;
    while (s < kept && static_cast<double>(scratch_bearing_deg_[s]) < start) ++s;
    walk_start_ = s == kept ? 0 : s;
  } else {
    // Last return at or before `start`, walking towards smaller bearings.
    walk_start_ = kept - 1;
    for (std::uint32_t i = kept; i-- > 0;) {
      if (static_cast<double>(scratch_bearing_deg_[i]) <= start) {
        walk_start_ = i;
        break;
      }
    }
  }
}

std::uint32_t LidarClusterer::walk_source(std::uint32_t walk_index) const {
  const std::uint32_t n = point_count_;
  return params_.walk_clockwise ? (walk_start_ + walk_index) % n
                                : (walk_start_ + n - walk_index % n) % n;
}

bool LidarClusterer::breaks_scratch(std::uint32_t a, std::uint32_t b) const {
  const double limit = params_.group_gap_m +
                       params_.group_gap_per_m *
                           static_cast<double>(std::min(scratch_range_m_[a], scratch_range_m_[b]));
  return farther_than(scratch_x_m_[b] - scratch_x_m_[a], scratch_y_m_[b] - scratch_y_m_[a], limit);
}

void LidarClusterer::group_points() {
  group_count_ = 0;
  const std::uint32_t n = point_count_;
  if (n == 0) return;

  // Seam merge: when the walk's last and first returns belong together, start the walk at the
  // first break instead, so the wrapping group comes out contiguous (and last).
  std::uint32_t offset = 0;
  if (params_.merge_across_seam && n > 1 && !breaks_scratch(walk_source(n - 1), walk_source(0))) {
    std::uint32_t prev = walk_source(0);
    for (std::uint32_t k = 1; k < n; ++k) {
      const std::uint32_t cur =
          params_.walk_clockwise ? (prev + 1 == n ? 0 : prev + 1) : (prev == 0 ? n - 1 : prev - 1);
      if (breaks_scratch(prev, cur)) {
        offset = k;
        stats_.seam_merged = true;
        break;
      }
      prev = cur;
    }
  }
  // One pass: copy into walk order (stepping through the scratch arrays without a division)
  // and close a group at each break.
  const bool strict = params_.semantics == ClusterSemantics::kTricat2022;
  const std::uint32_t min_points = params_.min_group_points;
  const double gap_m = params_.group_gap_m;
  const double gap_per_m = params_.group_gap_per_m;
  const bool forward = params_.walk_clockwise;
  const auto close_group = [&](std::uint32_t begin, std::uint32_t end) {
    const std::uint32_t size = end - begin;
    if (strict ? size > min_points : size >= min_points) {
      groups_[group_count_++] = Span{begin, end};
    } else {
      ++stats_.groups_dropped;
    }
  };
  std::uint32_t src = walk_source(offset);
  std::uint32_t begin = 0;
  double px = 0.0;
  double py = 0.0;
  float pr = 0.0F;
  for (std::uint32_t i = 0; i < n; ++i) {
    const double x = scratch_x_m_[src];
    const double y = scratch_y_m_[src];
    const float r = scratch_range_m_[src];
    x_m_[i] = x;
    y_m_[i] = y;
    range_m_[i] = r;
    bin_[i] = scratch_bin_[src];
    if (forward) {
      src = src + 1 == n ? 0 : src + 1;
    } else {
      src = src == 0 ? n - 1 : src - 1;
    }
    if (i > 0 &&
        farther_than(x - px, y - py, gap_m + gap_per_m * static_cast<double>(std::min(pr, r)))) {
      close_group(begin, i);
      begin = i;
    }
    px = x;
    py = y;
    pr = r;
  }
  close_group(begin, n);
  stats_.groups = group_count_;
}

void LidarClusterer::split_group(Span group) {
  // (B) Iterative farthest-from-chord splitting; the right half is pushed first so pieces come
  // out in walk order. Each split pops one span and pushes two, so the stack never exceeds the
  // number of returns.
  const bool tricat = params_.semantics == ClusterSemantics::kTricat2022;
  const double* xs = x_m_.data();
  const double* ys = y_m_.data();
  stack_size_ = 0;
  stack_[stack_size_++] = group;
  while (stack_size_ > 0) {
    const Span s = stack_[--stack_size_];
    const double ax = xs[s.begin];
    const double ay = ys[s.begin];
    const double dx = xs[s.end - 1] - ax;
    const double dy = ys[s.end - 1] - ay;
    const double len = std::hypot(dx, dy);
    double max_d = 0.0;
    std::uint32_t k = s.begin;
    if (len > 0.0) {
      for (std::uint32_t i = s.begin; i < s.end; ++i) {
        // Distance to the chord's line (the source documents project onto the infinite line).
        const double d = std::abs((xs[i] - ax) * dy - (ys[i] - ay) * dx) / len;
        if (d > max_d) {
          max_d = d;
          k = i;
        }
      }
    } else {
      for (std::uint32_t i = s.begin; i < s.end; ++i) {
        const double d = std::hypot(xs[i] - ax, ys[i] - ay);
        if (d > max_d) {
          max_d = d;
          k = i;
        }
      }
    }
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
  if (farther_than(x_m_[b] - x_m_[a], y_m_[b] - y_m_[a], params_.wall_min_length_m)) {
    emit_wall(piece);
  } else {
    emit_segment(piece, ObstacleKind::kBuoy);
  }
}

void LidarClusterer::emit_wall(Span piece) {
  // (D) Cut the wall into bounded pieces.
  const double max_len = params_.wall_piece_max_length_m;
  if (params_.semantics == ClusterSemantics::kTricat2022) {
    std::uint32_t start = piece.begin;
    for (std::uint32_t i = piece.begin; i < piece.end; ++i) {
      if (farther_than(x_m_[i] - x_m_[start], y_m_[i] - y_m_[start], max_len)) {
        emit_segment(Span{start, i}, ObstacleKind::kWall);
        start = i;
      }
    }
    emit_segment(Span{start, piece.end}, ObstacleKind::kWall);
    return;
  }
  // Equal pieces along the chord; neighbours share their boundary return, so they touch.
  const double ax = x_m_[piece.begin];
  const double ay = y_m_[piece.begin];
  const double len = std::hypot(x_m_[piece.end - 1] - ax, y_m_[piece.end - 1] - ay);
  const double count = std::ceil(len / max_len);
  if (count <= 1.0 || piece.end - piece.begin < 3) {
    emit_segment(piece, ObstacleKind::kWall);
    return;
  }
  const double ux = (x_m_[piece.end - 1] - ax) / len;
  const double uy = (y_m_[piece.end - 1] - ay) / len;
  const double step = len / count;
  double next_cut = step;
  std::uint32_t start = piece.begin;
  for (std::uint32_t i = piece.begin + 1; i + 1 < piece.end; ++i) {
    const double t = (x_m_[i] - ax) * ux + (y_m_[i] - ay) * uy;
    if (t >= next_cut) {
      emit_segment(Span{start, i + 1}, ObstacleKind::kWall);
      start = i;
      next_cut += step;
    }
  }
  emit_segment(Span{start, piece.end}, ObstacleKind::kWall);
}

void LidarClusterer::emit_segment(Span piece, ObstacleKind kind) {
  const std::uint32_t first = piece.begin;
  const std::uint32_t last = piece.end - 1;
  ObstacleSegment seg;
  seg.kind = kind;
  seg.begin = core::BodyPoint{x_m_[first], y_m_[first]};
  seg.end = core::BodyPoint{x_m_[last], y_m_[last]};
  const std::uint32_t n = piece.end - piece.begin;
  if (params_.line_fit && n >= 3) {
    // Total least squares: the line through the centroid along the principal axis; the segment
    // ends at the projections of the first and last returns.
    double mx = 0.0;
    double my = 0.0;
    for (std::uint32_t i = piece.begin; i < piece.end; ++i) {
      mx += x_m_[i];
      my += y_m_[i];
    }
    mx /= static_cast<double>(n);
    my /= static_cast<double>(n);
    double sxx = 0.0;
    double sxy = 0.0;
    double syy = 0.0;
    for (std::uint32_t i = piece.begin; i < piece.end; ++i) {
      const double dx = x_m_[i] - mx;
      const double dy = y_m_[i] - my;
      sxx += dx * dx;
      sxy += dx * dy;
      syy += dy * dy;
    }
    if (sxx + syy > 0.0) {
      const double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
      const double ux = std::cos(angle);
      const double uy = std::sin(angle);
      const auto project = [&](std::uint32_t i) {
        const double t = (x_m_[i] - mx) * ux + (y_m_[i] - my) * uy;
        return core::BodyPoint{mx + t * ux, my + t * uy};
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
  for (std::uint32_t g = 0; g < group_count_; ++g) {
    for (std::uint32_t i = groups_[g].begin; i < groups_[g].end; ++i) {
      float& slot = profile.closest_range_m[bin_[i]];
      slot = std::min(slot, range_m_[i]);
    }
  }
}

}  // namespace coxswain::perception
