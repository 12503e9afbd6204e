// SPDX-License-Identifier: Apache-2.0
#include "coxswain/perception/lidar_clusterer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "coxswain/core/angles.hpp"

namespace coxswain::perception {
namespace {

constexpr double kFullCircleDeg = 360.0;

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

std::string LidarClusterParams::validate() const {
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
  if (const std::string err = params_.validate(); !err.empty()) {
    throw std::invalid_argument("LidarClusterParams: " + err);
  }
  constexpr std::size_t n = msg::LidarScan::kMaxPoints;
  filtered_.resize(n);
  points_.resize(n);
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

void LidarClusterer::filter_points(const msg::LidarScan& scan) {
  const std::uint32_t n_in =
      std::min<std::uint32_t>(scan.point_count, static_cast<std::uint32_t>(scan.points.size()));
  stats_.points_in = n_in;
  double max_range_m = params_.max_range_m;
  if (scan.max_range_m > 0.0F)
    max_range_m = std::min(max_range_m, static_cast<double>(scan.max_range_m));

  // Pass 1: filters, in scan order (bearing ascending), into points_ as scratch.
  std::uint32_t kept = 0;
  for (std::uint32_t i = 0; i < n_in; ++i) {
    const msg::LidarPoint& p = scan.points[i];
    const auto r = static_cast<double>(p.range_m);
    if (!(r > 0.0) || !std::isfinite(r) || r < params_.min_range_m || r > max_range_m) continue;
    auto b = static_cast<double>(p.bearing_deg);
    if (!(b > -180.0 && b <= 180.0)) b = core::wrap_deg(b);
    if (!std::isfinite(b)) continue;
    const double x = r * std::cos(core::deg_to_rad(b));
    const double y = r * std::sin(core::deg_to_rad(b));
    if (params_.hull.contains(x, y)) continue;
    points_[kept++] = WorkPoint{x, y, static_cast<float>(r), static_cast<float>(b)};
  }
  point_count_ = kept;
  stats_.points_kept = kept;
  if (kept == 0) return;

  // Pass 2: walk order into filtered_, starting at walk_start_bearing_deg.
  const double start = params_.walk_start_bearing_deg;
  if (params_.walk_clockwise) {
    std::uint32_t s = 0;
    while (s < kept && static_cast<double>(points_[s].bearing_deg) < start) ++s;
    if (s == kept) s = 0;
    for (std::uint32_t i = 0; i < kept; ++i) filtered_[i] = points_[(s + i) % kept];
  } else {
    // Last return at or before `start`, walking towards smaller bearings.
    std::uint32_t s = kept - 1;
    bool found = false;
    for (std::uint32_t i = kept; i-- > 0;) {
      if (static_cast<double>(points_[i].bearing_deg) <= start) {
        s = i;
        found = true;
        break;
      }
    }
    if (!found) s = kept - 1;
    for (std::uint32_t i = 0; i < kept; ++i) filtered_[i] = points_[(s + kept - i) % kept];
  }
}

double LidarClusterer::gap_limit_m(const WorkPoint& a, const WorkPoint& b) const {
  return params_.group_gap_m +
         params_.group_gap_per_m * static_cast<double>(std::min(a.range_m, b.range_m));
}

bool LidarClusterer::breaks(const WorkPoint& a, const WorkPoint& b) const {
  return std::hypot(b.x_m - a.x_m, b.y_m - a.y_m) > gap_limit_m(a, b);
}

void LidarClusterer::group_points() {
  group_count_ = 0;
  const std::uint32_t n = point_count_;
  if (n == 0) return;

  // Seam merge: when the walk's last and first returns belong together, start the walk at the
  // first break instead, so the wrapping group comes out contiguous (and last).
  std::uint32_t offset = 0;
  if (params_.merge_across_seam && n > 1 && !breaks(filtered_[n - 1], filtered_[0])) {
    for (std::uint32_t k = 1; k < n; ++k) {
      if (breaks(filtered_[k - 1], filtered_[k])) {
        offset = k;
        stats_.seam_merged = true;
        break;
      }
    }
  }
  for (std::uint32_t i = 0; i < n; ++i) points_[i] = filtered_[(i + offset) % n];

  const bool strict = params_.semantics == ClusterSemantics::kTricat2022;
  std::uint32_t begin = 0;
  for (std::uint32_t i = 1; i <= n; ++i) {
    if (i < n && !breaks(points_[i - 1], points_[i])) continue;
    const std::uint32_t size = i - begin;
    const bool keep = strict ? size > params_.min_group_points : size >= params_.min_group_points;
    if (keep) {
      groups_[group_count_++] = Span{begin, i};
    } else {
      ++stats_.groups_dropped;
    }
    begin = i;
  }
  stats_.groups = group_count_;
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
    const WorkPoint& a = points_[s.begin];
    const WorkPoint& b = points_[s.end - 1];
    const double dx = b.x_m - a.x_m;
    const double dy = b.y_m - a.y_m;
    const double len = std::hypot(dx, dy);
    double max_d = 0.0;
    std::uint32_t k = s.begin;
    for (std::uint32_t i = s.begin; i < s.end; ++i) {
      const WorkPoint& p = points_[i];
      // Distance to the chord's line (the source documents project onto the infinite line).
      const double d = len > 0.0 ? std::abs((p.x_m - a.x_m) * dy - (p.y_m - a.y_m) * dx) / len
                                 : std::hypot(p.x_m - a.x_m, p.y_m - a.y_m);
      if (d > max_d) {
        max_d = d;
        k = i;
      }
    }
    const double limit = params_.split_distance_m +
                         params_.split_distance_per_m * static_cast<double>(points_[k].range_m);
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
  const WorkPoint& a = points_[piece.begin];
  const WorkPoint& b = points_[piece.end - 1];
  if (std::hypot(b.x_m - a.x_m, b.y_m - a.y_m) > params_.wall_min_length_m) {
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
      const WorkPoint& s = points_[start];
      if (std::hypot(points_[i].x_m - s.x_m, points_[i].y_m - s.y_m) > max_len) {
        emit_segment(Span{start, i}, ObstacleKind::kWall);
        start = i;
      }
    }
    emit_segment(Span{start, piece.end}, ObstacleKind::kWall);
    return;
  }
  // Equal pieces along the chord; neighbours share their boundary return, so they touch.
  const WorkPoint& a = points_[piece.begin];
  const WorkPoint& b = points_[piece.end - 1];
  const double len = std::hypot(b.x_m - a.x_m, b.y_m - a.y_m);
  const double count = std::ceil(len / max_len);
  if (count <= 1.0 || piece.end - piece.begin < 3) {
    emit_segment(piece, ObstacleKind::kWall);
    return;
  }
  const double ux = (b.x_m - a.x_m) / len;
  const double uy = (b.y_m - a.y_m) / len;
  const double step = len / count;
  double next_cut = step;
  std::uint32_t start = piece.begin;
  for (std::uint32_t i = piece.begin + 1; i + 1 < piece.end; ++i) {
    const double t = (points_[i].x_m - a.x_m) * ux + (points_[i].y_m - a.y_m) * uy;
    if (t >= next_cut) {
      emit_segment(Span{start, i + 1}, ObstacleKind::kWall);
      start = i;
      next_cut += step;
    }
  }
  emit_segment(Span{start, piece.end}, ObstacleKind::kWall);
}

void LidarClusterer::emit_segment(Span piece, ObstacleKind kind) {
  const WorkPoint& first = points_[piece.begin];
  const WorkPoint& last = points_[piece.end - 1];
  ObstacleSegment seg;
  seg.kind = kind;
  seg.begin = core::BodyPoint{first.x_m, first.y_m};
  seg.end = core::BodyPoint{last.x_m, last.y_m};
  const std::uint32_t n = piece.end - piece.begin;
  if (params_.line_fit && n >= 3) {
    // Total least squares: the line through the centroid along the principal axis; the segment
    // ends at the projections of the first and last returns.
    double mx = 0.0;
    double my = 0.0;
    for (std::uint32_t i = piece.begin; i < piece.end; ++i) {
      mx += points_[i].x_m;
      my += points_[i].y_m;
    }
    mx /= static_cast<double>(n);
    my /= static_cast<double>(n);
    double sxx = 0.0;
    double sxy = 0.0;
    double syy = 0.0;
    for (std::uint32_t i = piece.begin; i < piece.end; ++i) {
      const double dx = points_[i].x_m - mx;
      const double dy = points_[i].y_m - my;
      sxx += dx * dx;
      sxy += dx * dy;
      syy += dy * dy;
    }
    if (sxx + syy > 0.0) {
      const double angle = 0.5 * std::atan2(2.0 * sxy, sxx - syy);
      const double ux = std::cos(angle);
      const double uy = std::sin(angle);
      const auto project = [&](const WorkPoint& p) {
        const double t = (p.x_m - mx) * ux + (p.y_m - my) * uy;
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
  const double width = params_.profile_bin_width_deg;
  const auto bins = static_cast<std::uint32_t>(std::lround(kFullCircleDeg / width));
  profile.bin_width_deg = static_cast<float>(width);
  profile.bin_count = bins;
  profile.closest_range_m.fill(RangeProfile::kNoReturn);
  // Only returns that survived the noise filter count: a lone spray return is not an obstacle.
  for (std::uint32_t g = 0; g < group_count_; ++g) {
    for (std::uint32_t i = groups_[g].begin; i < groups_[g].end; ++i) {
      const WorkPoint& p = points_[i];
      auto idx = static_cast<std::int64_t>(
          std::floor((static_cast<double>(p.bearing_deg) + 180.0) / width));
      if (idx >= static_cast<std::int64_t>(bins))
        idx -= static_cast<std::int64_t>(bins);  // +180 is the -180 bin
      idx = std::clamp<std::int64_t>(idx, 0, static_cast<std::int64_t>(bins) - 1);
      float& slot = profile.closest_range_m[static_cast<std::size_t>(idx)];
      slot = std::min(slot, p.range_m);
    }
  }
}

}  // namespace coxswain::perception
