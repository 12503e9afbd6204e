// SPDX-License-Identifier: Apache-2.0
#include "sim/sensors/ray_scene.hpp"

#include <algorithm>
#include <cmath>

#include "coxswain/core/angles.hpp"

namespace coxswain::sim::sensors {

namespace {
constexpr std::uint32_t kCircleTag = 0x80000000U;

double point_segment_distance(core::NavPoint p, const Segment& s) {
  const double vx = s.b.north_m - s.a.north_m;
  const double vy = s.b.east_m - s.a.east_m;
  const double wx = p.north_m - s.a.north_m;
  const double wy = p.east_m - s.a.east_m;
  const double len2 = vx * vx + vy * vy;
  const double t = len2 > 0.0 ? std::clamp((wx * vx + wy * vy) / len2, 0.0, 1.0) : 0.0;
  return std::hypot(wx - t * vx, wy - t * vy);
}
}  // namespace

double ray_segment(core::NavPoint o, double dn, double de, const Segment& s) {
  // o + t d = a + u (b - a), t >= 0, u in [0, 1].
  const double en = s.b.north_m - s.a.north_m;
  const double ee = s.b.east_m - s.a.east_m;
  const double denom = dn * ee - de * en;
  if (std::abs(denom) < 1e-12) return -1.0;  // parallel: grazing rays see nothing
  const double wn = s.a.north_m - o.north_m;
  const double we = s.a.east_m - o.east_m;
  const double t = (wn * ee - we * en) / denom;
  const double u = (wn * de - we * dn) / denom;
  if (t < 0.0 || u < 0.0 || u > 1.0) return -1.0;
  return t;
}

double ray_circle(core::NavPoint o, double dn, double de, const Circle& c) {
  const double wn = c.center.north_m - o.north_m;
  const double we = c.center.east_m - o.east_m;
  const double along = wn * dn + we * de;
  const double d2 = wn * wn + we * we;
  const double r2 = c.radius_m * c.radius_m;
  if (d2 <= r2) return -1.0;  // inside the buoy: no meaningful return
  if (along <= 0.0) return -1.0;
  const double perp2 = d2 - along * along;
  if (perp2 > r2) return -1.0;
  return along - std::sqrt(r2 - perp2);
}

RayScene::RayScene(const world::World& world) {
  const auto add_wall = [this](const world::Wall& w) {
    for (std::size_t i = 1; i < w.points.size(); ++i) add_segment({w.points[i - 1], w.points[i]});
  };
  for (const world::Wall& w : world.walls) add_wall(w);
  for (const world::Dock& d : world.docks) {
    for (const world::Wall& w : d.walls) add_wall(w);
  }
  for (const world::Buoy& b : world.buoys) add_circle({b.center, b.radius_m});
}

void RayScene::add_segment(const Segment& s) {
  segments_.push_back(s);
  radius_m_ = -1.0;
}

void RayScene::add_circle(const Circle& c) {
  circles_.push_back(c);
  radius_m_ = -1.0;
}

void RayScene::add_span(std::uint32_t tagged, double lo_deg, double hi_deg) {
  if (hi_deg - lo_deg >= 360.0 - kBinDeg) {
    for (auto& bin : bins_) bin.push_back(tagged);
    return;
  }
  const double lo = core::wrap_deg_360(lo_deg);
  const int first = static_cast<int>(lo / kBinDeg);
  const int count = static_cast<int>((lo + (hi_deg - lo_deg)) / kBinDeg) - first + 1;
  for (int k = 0; k < count && k < kBins; ++k)
    bins_[static_cast<std::size_t>((first + k) % kBins)].push_back(tagged);
}

void RayScene::prepare(core::NavPoint center, double radius_m, double max_range_m) {
  for (auto& bin : bins_) bin.clear();
  center_ = center;
  radius_m_ = radius_m;
  max_range_m_ = max_range_m;
  const double reach = max_range_m + radius_m;
  // Every direction from any point within radius_m of the centre to a point of the object lies
  // within the object's bearing span seen from the centre, widened by asin(radius / distance).
  const auto pad_deg = [radius_m](double dist) {
    return core::rad_to_deg(std::asin(std::min(1.0, radius_m / dist)));
  };
  for (std::size_t i = 0; i < segments_.size(); ++i) {
    const Segment& s = segments_[i];
    const double dist = point_segment_distance(center, s);
    if (dist > reach) continue;
    const auto tag = static_cast<std::uint32_t>(i);
    if (dist <= radius_m * 1.01 + 1e-6) {
      add_span(tag, 0.0, 360.0);
      continue;
    }
    const double ba = core::bearing_deg(center, s.a);
    const double bb = core::bearing_deg(center, s.b);
    // A segment not through the centre subtends less than 180 deg: the short arc.
    const double sweep = core::wrap_deg(bb - ba);
    const double lo = sweep >= 0.0 ? ba : bb;
    const double pad = pad_deg(dist) + 0.01;
    add_span(tag, lo - pad, lo + std::abs(sweep) + pad);
  }
  for (std::size_t i = 0; i < circles_.size(); ++i) {
    const Circle& c = circles_[i];
    const double dist = core::distance_m(center, c.center);
    if (dist - c.radius_m > reach) continue;
    const auto tag = static_cast<std::uint32_t>(i) | kCircleTag;
    const double rr = c.radius_m + radius_m;
    if (dist <= rr * 1.01 + 1e-6) {
      add_span(tag, 0.0, 360.0);
      continue;
    }
    const double half = core::rad_to_deg(std::asin(std::min(1.0, rr / dist))) + 0.01;
    const double b = core::bearing_deg(center, c.center);
    add_span(tag, b - half, b + half);
  }
}

std::size_t RayScene::bin_entries() const {
  std::size_t n = 0;
  for (const auto& bin : bins_) n += bin.size();
  return n;
}

bool RayScene::covers(core::NavPoint p) const {
  return radius_m_ >= 0.0 && core::distance_m(p, center_) <= radius_m_;
}

double RayScene::cast(core::NavPoint origin, double bearing_deg) const {
  const double rad = core::deg_to_rad(bearing_deg);
  return cast(origin, core::wrap_deg_360(bearing_deg), std::cos(rad), std::sin(rad));
}

double RayScene::cast(core::NavPoint origin, double bearing_360_deg, double dn, double de) const {
  const int bin = std::clamp(static_cast<int>(bearing_360_deg / kBinDeg), 0, kBins - 1);
  double best = -1.0;
  for (const std::uint32_t tagged : bins_[static_cast<std::size_t>(bin)]) {
    const double t = (tagged & kCircleTag) != 0U
                         ? ray_circle(origin, dn, de, circles_[tagged & ~kCircleTag])
                         : ray_segment(origin, dn, de, segments_[tagged]);
    if (t >= 0.0 && (best < 0.0 || t < best)) best = t;
  }
  return best >= 0.0 && best <= max_range_m_ ? best : -1.0;
}

double RayScene::cast_brute(core::NavPoint origin, double bearing_deg, double max_range_m) const {
  const double rad = core::deg_to_rad(bearing_deg);
  const double dn = std::cos(rad);
  const double de = std::sin(rad);
  double best = -1.0;
  for (const Segment& s : segments_) {
    const double t = ray_segment(origin, dn, de, s);
    if (t >= 0.0 && (best < 0.0 || t < best)) best = t;
  }
  for (const Circle& c : circles_) {
    const double t = ray_circle(origin, dn, de, c);
    if (t >= 0.0 && (best < 0.0 || t < best)) best = t;
  }
  return best >= 0.0 && best <= max_range_m ? best : -1.0;
}

}  // namespace coxswain::sim::sensors
