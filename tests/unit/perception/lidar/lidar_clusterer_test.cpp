// SPDX-License-Identifier: Apache-2.0
// LidarClusterer on synthetic scans built here by ray casting (no recordings needed).
#include "coxswain/perception/lidar_clusterer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <new>
#include <optional>
#include <vector>

#include "coxswain/core/angles.hpp"

// Counts heap allocations while `g_counting` is set, to prove process() allocates nothing. GCC
// flags free() inside a replaced operator delete as a mismatch once inlined; the pair is matched.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
}  // namespace

void* operator new(std::size_t size) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace coxswain::perception {
namespace {

using core::BodyPoint;

struct Wall {
  BodyPoint a;
  BodyPoint b;
};
struct Circle {
  BodyPoint centre;
  double radius_m;
};

// Casts rays every `step_deg` over the full circle (bearing ascending from just above -180) and
// keeps the nearest hit of each; no hit = no return (left out, as the drivers do).
struct SceneBuilder {
  std::vector<Wall> walls;
  std::vector<Circle> circles;
  double step_deg = 0.25;
  double max_range_m = 40.0;

  [[nodiscard]] std::unique_ptr<msg::LidarScan> scan() const {
    auto s = std::make_unique<msg::LidarScan>();
    s->stamp_ns = 123456789;
    s->max_range_m = static_cast<float>(max_range_m);
    const int n = static_cast<int>(std::lround(360.0 / step_deg));
    for (int i = 1; i <= n; ++i) {
      const double b = -180.0 + step_deg * i;
      const double dx = std::cos(core::deg_to_rad(b));
      const double dy = std::sin(core::deg_to_rad(b));
      std::optional<double> best;
      for (const Wall& w : walls) {
        // Solve t * d = a + u * (b - a).
        const double ex = w.b.forward_m - w.a.forward_m;
        const double ey = w.b.starboard_m - w.a.starboard_m;
        const double den = dx * ey - dy * ex;
        if (std::abs(den) < 1e-12) continue;
        const double t = (w.a.forward_m * ey - w.a.starboard_m * ex) / den;
        const double u = (w.a.forward_m * dy - w.a.starboard_m * dx) / den;
        if (t > 0.0 && u >= 0.0 && u <= 1.0 && (!best || t < *best)) best = t;
      }
      for (const Circle& c : circles) {
        const double proj = c.centre.forward_m * dx + c.centre.starboard_m * dy;
        const double d2 = c.centre.forward_m * c.centre.forward_m +
                          c.centre.starboard_m * c.centre.starboard_m - proj * proj;
        const double r2 = c.radius_m * c.radius_m;
        if (d2 > r2 || proj <= 0.0) continue;
        const double t = proj - std::sqrt(r2 - d2);
        if (t > 0.0 && (!best || t < *best)) best = t;
      }
      if (best && *best <= max_range_m) {
        msg::LidarPoint p;
        p.bearing_deg = static_cast<float>(b);
        p.range_m = static_cast<float>(*best);
        p.quality = 47;
        EXPECT_TRUE(s->push(p));
      }
    }
    return s;
  }
};

struct Result {
  ObstacleList list;
  RangeProfile profile;
  LidarClusterStats stats;
};

std::unique_ptr<Result> run(const LidarClusterParams& params, const msg::LidarScan& scan) {
  LidarClusterer clusterer(params);
  auto r = std::make_unique<Result>();
  clusterer.process(scan, r->list, r->profile);
  r->stats = clusterer.last_stats();
  return r;
}

double length_m(const ObstacleSegment& s) {
  return std::hypot(s.end.forward_m - s.begin.forward_m, s.end.starboard_m - s.begin.starboard_m);
}
double gap_m(BodyPoint a, BodyPoint b) {
  return std::hypot(a.forward_m - b.forward_m, a.starboard_m - b.starboard_m);
}
// Distance of point p from the infinite line through s.
double off_line_m(const ObstacleSegment& s, BodyPoint p) {
  const double dx = s.end.forward_m - s.begin.forward_m;
  const double dy = s.end.starboard_m - s.begin.starboard_m;
  return std::abs((p.forward_m - s.begin.forward_m) * dy -
                  (p.starboard_m - s.begin.starboard_m) * dx) /
         std::hypot(dx, dy);
}

TEST(LidarClusterParams, DefaultsAndReferenceAreValid) {
  EXPECT_FALSE(LidarClusterParams{}.validate().has_value());
  EXPECT_FALSE(LidarClusterParams::reference_tricat2022().validate().has_value());
}

TEST(LidarClusterParams, RejectsBadValues) {
  LidarClusterParams p;
  p.min_range_m = 30.0;
  EXPECT_TRUE(p.validate().has_value());
  EXPECT_THROW(LidarClusterer{p}, std::invalid_argument);
  p = {};
  p.profile_bin_width_deg = 0.25;  // 1440 bins > kMaxBins
  EXPECT_TRUE(p.validate().has_value());
  p.profile_bin_width_deg = 0.7;  // does not divide 360
  EXPECT_TRUE(p.validate().has_value());
  p = {};
  p.wall_piece_max_length_m = 0.0;
  EXPECT_TRUE(p.validate().has_value());
  p = {};
  p.group_gap_m = std::nan("");
  EXPECT_TRUE(p.validate().has_value());
}

TEST(LidarClusterer, EmptyScanGivesNothing) {
  msg::LidarScan scan;
  auto r = run({}, scan);
  EXPECT_EQ(r->list.count, 0U);
  for (std::uint32_t i = 0; i < r->profile.bin_count; ++i) {
    EXPECT_EQ(r->profile.closest_range_m[i], RangeProfile::kNoReturn);
  }
}

TEST(LidarClusterer, BuoyIsOneBuoySegmentWithProfile) {
  SceneBuilder scene;
  scene.circles.push_back({BodyPoint{4.33, 2.5}, 0.1});  // bearing 30 deg, 5 m
  auto scan = scene.scan();
  auto r = run({}, *scan);
  ASSERT_EQ(r->list.count, 1U);
  const ObstacleSegment& s = r->list.segments[0];
  EXPECT_EQ(s.kind, ObstacleKind::kBuoy);
  EXPECT_NEAR(s.closest_range_m, 5.0 - 0.1, 0.03);
  EXPECT_EQ(r->list.stamp_ns, 123456789);
  EXPECT_EQ(r->profile.bin_count, 360U);
  EXPECT_NEAR(r->profile.closest_range_m[180 + 30], 4.9, 0.01);
  EXPECT_EQ(r->profile.closest_range_m[180 + 40], RangeProfile::kNoReturn);
  EXPECT_EQ(r->profile.closest_range_m[0], RangeProfile::kNoReturn);
}

TEST(LidarClusterer, WallIsCutIntoTouchingPiecesOnTheLine) {
  SceneBuilder scene;
  scene.walls.push_back({BodyPoint{6.0, -1.0}, BodyPoint{6.0, 1.0}});  // 2 m across the bow
  auto scan = scene.scan();
  auto r = run({}, *scan);
  // ceil(2.0 / 0.7) = 3 equal pieces of ~0.67 m.
  ASSERT_EQ(r->list.count, 3U);
  for (std::uint32_t i = 0; i < r->list.count; ++i) {
    const ObstacleSegment& s = r->list.segments[i];
    EXPECT_EQ(s.kind, ObstacleKind::kWall);
    EXPECT_NEAR(s.begin.forward_m, 6.0, 1e-6);
    EXPECT_NEAR(s.end.forward_m, 6.0, 1e-6);
    EXPECT_LE(length_m(s), 0.7 + 0.03);  // + one beam spacing at 6 m
    if (i > 0) {
      EXPECT_LT(gap_m(r->list.segments[i - 1].end, s.begin), 1e-6);  // shared return
    }
  }
  // The middle piece crosses the bow: its closest point is straight ahead.
  EXPECT_NEAR(r->list.segments[1].closest_range_m, 6.0, 1e-4);
}

TEST(LidarClusterer, LCornerSplitsAtTheCorner) {
  SceneBuilder scene;
  scene.walls.push_back({BodyPoint{4.0, -1.0}, BodyPoint{4.0, 1.0}});
  scene.walls.push_back({BodyPoint{4.0, 1.0}, BodyPoint{2.5, 1.0}});
  auto scan = scene.scan();
  LidarClusterParams p;
  p.wall_piece_max_length_m = 10.0;  // isolate step (B)
  auto r = run(p, *scan);
  ASSERT_EQ(r->list.count, 2U);
  const ObstacleSegment& front = r->list.segments[0];  // walk is clockwise: x = 4 leg first
  const ObstacleSegment& side = r->list.segments[1];
  EXPECT_LT(off_line_m(front, BodyPoint{4.0, -0.5}), 0.01);
  EXPECT_LT(off_line_m(front, BodyPoint{4.0, 0.5}), 0.01);
  EXPECT_LT(off_line_m(side, BodyPoint{3.0, 1.0}), 0.02);
  EXPECT_LT(off_line_m(side, BodyPoint{3.5, 1.0}), 0.02);
  // The corner return is shared, so both pieces end near the corner.
  EXPECT_LT(gap_m(front.end, BodyPoint{4.0, 1.0}), 0.05);
  EXPECT_LT(gap_m(side.begin, BodyPoint{4.0, 1.0}), 0.05);
  // Without splitting the chord from (4,-1) to (2.5,1) would cut the corner by ~0.9 m.
  LidarClusterParams no_split = p;
  no_split.split_distance_m = 100.0;
  EXPECT_EQ(run(no_split, *scan)->list.count, 1U);
}

TEST(LidarClusterer, ReferenceSemanticsCutAtTheBowAndLeaveGapsBetweenWallPieces) {
  SceneBuilder scene;
  scene.walls.push_back({BodyPoint{6.0, -1.0}, BodyPoint{6.0, 1.0}});
  auto scan = scene.scan();
  auto r = run(LidarClusterParams::reference_tricat2022(), *scan);
  // Their walk starts at the bow and never merges across that seam: the wall dead ahead becomes
  // two 1 m groups (port half first, walking to port; the starboard half last), each cut into
  // two pieces where a return lies more than 0.7 m from the piece's first return.
  ASSERT_EQ(r->list.count, 4U);
  for (std::uint32_t i = 0; i < r->list.count; ++i) {
    EXPECT_LE(length_m(r->list.segments[i]), 0.7);
    EXPECT_EQ(r->list.segments[i].kind, ObstacleKind::kWall);
  }
  EXPECT_NEAR(r->list.segments[0].begin.starboard_m, 0.0, 0.03);
  EXPECT_LT(r->list.segments[0].end.starboard_m, -0.6);
  EXPECT_GT(r->list.segments[3].begin.starboard_m, 0.0);
  EXPECT_NEAR(r->list.segments[3].end.starboard_m, 0.0, 0.03);
  // Pieces of one wall do not touch: a gap of one beam spacing between them.
  EXPECT_GT(gap_m(r->list.segments[0].end, r->list.segments[1].begin), 0.01);
  // Coxswain merges across its seam (astern) and walks clockwise: 3 touching pieces.
  EXPECT_EQ(run({}, *scan)->list.count, 3U);
}

TEST(LidarClusterer, ObstacleAcrossTheSeamIsOneGroup) {
  SceneBuilder scene;
  scene.walls.push_back({BodyPoint{-5.0, -0.3}, BodyPoint{-5.0, 0.3}});  // astern, on the seam
  auto scan = scene.scan();
  LidarClusterParams p;
  p.wall_piece_max_length_m = 10.0;
  auto merged = run(p, *scan);
  EXPECT_TRUE(merged->stats.seam_merged);
  EXPECT_EQ(merged->stats.groups, 1U);
  ASSERT_EQ(merged->list.count, 1U);
  EXPECT_NEAR(length_m(merged->list.segments[0]), 0.6, 0.05);  // ends within a beam of the wall's
  EXPECT_NEAR(merged->list.segments[0].closest_range_m, 5.0, 1e-3);

  p.merge_across_seam = false;
  auto cut = run(p, *scan);
  EXPECT_FALSE(cut->stats.seam_merged);
  EXPECT_EQ(cut->stats.groups, 2U);
  EXPECT_EQ(cut->list.count, 2U);
}

TEST(LidarClusterer, SeamMergeNeedsAdjacency) {
  SceneBuilder scene;
  // Two separate buoys either side of the stern: the seam must not join them.
  scene.circles.push_back({BodyPoint{-5.0, -1.0}, 0.1});
  scene.circles.push_back({BodyPoint{-5.0, 1.0}, 0.1});
  auto scan = scene.scan();
  auto r = run({}, *scan);
  EXPECT_FALSE(r->stats.seam_merged);
  EXPECT_EQ(r->list.count, 2U);
}

TEST(LidarClusterer, ReturnsInsideTheHullBoxAreDropped) {
  SceneBuilder scene;
  scene.circles.push_back({BodyPoint{5.0, 0.0}, 0.1});
  // A mast-like post and a railing inside the default box (forward -2.2..0.1, +-0.65 m).
  scene.circles.push_back({BodyPoint{-1.0, 0.0}, 0.08});
  scene.walls.push_back({BodyPoint{-0.5, 0.5}, BodyPoint{-1.8, 0.5}});
  auto scan = scene.scan();
  auto r = run({}, *scan);
  ASSERT_EQ(r->list.count, 1U);
  EXPECT_GT(r->list.segments[0].begin.forward_m, 4.0);
  EXPECT_LT(r->stats.points_kept, r->stats.points_in);
  // Without the box the hull returns come back as obstacles.
  LidarClusterParams p;
  p.hull = HullBox{};
  EXPECT_GT(run(p, *scan)->list.count, 1U);
}

TEST(LidarClusterer, MinAndMaxRangeFilter) {
  SceneBuilder scene;
  scene.circles.push_back({BodyPoint{0.5, 0.5}, 0.02});   // ~0.69 m, inside min range below
  scene.circles.push_back({BodyPoint{30.0, -5.0}, 0.5});  // ~30 m, beyond 25 m
  scene.circles.push_back({BodyPoint{5.0, 0.0}, 0.1});
  auto scan = scene.scan();
  LidarClusterParams p;
  p.min_range_m = 1.0;
  p.min_group_points = 1;
  auto r = run(p, *scan);
  ASSERT_EQ(r->list.count, 1U);
  EXPECT_NEAR(r->list.segments[0].closest_range_m, 4.9, 0.03);
}

TEST(LidarClusterer, SparseFarPointsGroupThanksToTheProportionalGap) {
  SceneBuilder scene;
  scene.step_deg = 0.5;  // 0.175 m between returns at 20 m, more than the 0.1 m base gap
  scene.walls.push_back({BodyPoint{20.0, -2.0}, BodyPoint{20.0, 2.0}});
  auto scan = scene.scan();
  LidarClusterParams p;
  p.wall_piece_max_length_m = 10.0;
  auto r = run(p, *scan);
  ASSERT_EQ(r->list.count, 1U);
  EXPECT_EQ(r->list.segments[0].kind, ObstacleKind::kWall);
  EXPECT_NEAR(r->list.segments[0].closest_range_m, 20.0, 0.01);
  p.group_gap_per_m = 0.0;  // the fixed gap sees only single returns: all dropped as noise
  auto fixed = run(p, *scan);
  EXPECT_EQ(fixed->list.count, 0U);
  EXPECT_GT(fixed->stats.groups_dropped, 20U);
}

TEST(LidarClusterer, ClosestRangeIsTheSegmentsNotItsFirstPoint) {
  // The source team measured an obstacle at its first return; a wall square across the bow is
  // then reported 3.35 m away although it is 3.0 m ahead.
  SceneBuilder scene;
  scene.walls.push_back({BodyPoint{3.0, -1.5}, BodyPoint{3.0, 1.5}});
  auto scan = scene.scan();
  LidarClusterParams p;
  p.wall_piece_max_length_m = 10.0;
  auto r = run(p, *scan);
  ASSERT_EQ(r->list.count, 1U);
  const ObstacleSegment& s = r->list.segments[0];
  const double first_point_m = std::hypot(s.begin.forward_m, s.begin.starboard_m);
  EXPECT_NEAR(first_point_m, std::hypot(3.0, 1.5), 0.02);
  EXPECT_NEAR(s.closest_range_m, 3.0, 1e-4);
  // Reference mode: chord endpoints, but the distance is still the true one. The wall is cut at
  // their bow seam; the starboard half starts just starboard of the bow and ends at (3, 1.5),
  // so its first return is near but its last return is 3.35 m away.
  auto ref = LidarClusterParams::reference_tricat2022();
  ref.wall_piece_max_length_m = 10.0;
  auto rr = run(ref, *scan);
  ASSERT_EQ(rr->list.count, 2U);
  const ObstacleSegment& port = rr->list.segments[0];  // walk: bow -> port
  EXPECT_NEAR(std::hypot(port.end.forward_m, port.end.starboard_m), std::hypot(3.0, 1.5), 0.02);
  EXPECT_NEAR(port.closest_range_m, 3.0, 1e-3);
  // Walking reversed (their segments begin at the far end): still the true distance.
  ref.walk_clockwise = true;
  ref.walk_start_bearing_deg = 30.0;
  auto rev = run(ref, *scan);
  ASSERT_EQ(rev->list.count, 1U);
  EXPECT_NEAR(
      std::hypot(rev->list.segments[0].begin.forward_m, rev->list.segments[0].begin.starboard_m),
      std::hypot(3.0, 1.5), 0.02);
  EXPECT_NEAR(rev->list.segments[0].closest_range_m, 3.0, 1e-3);
}

TEST(LidarClusterer, NoiseGroupsAreDropped) {
  SceneBuilder scene;
  scene.circles.push_back({BodyPoint{5.0, 0.0}, 0.1});
  auto scan = scene.scan();
  // Isolated single returns (spray) spread around the boat.
  for (float b : {-120.0F, -60.0F, 60.0F, 120.0F}) {
    msg::LidarPoint p;
    p.bearing_deg = b + 0.1F;
    p.range_m = 3.0F;
    ASSERT_TRUE(scan->push(p));
  }
  std::sort(scan->points.begin(), scan->points.begin() + scan->point_count,
            [](const auto& a, const auto& b) { return a.bearing_deg < b.bearing_deg; });
  auto r = run({}, *scan);
  EXPECT_EQ(r->list.count, 1U);
  EXPECT_EQ(r->stats.groups_dropped, 4U);
  EXPECT_EQ(r->profile.closest_range_m[180 + 60], RangeProfile::kNoReturn);
}

TEST(LidarClusterer, DeterministicAndAllocationFree) {
  SceneBuilder scene;
  scene.walls.push_back({BodyPoint{4.0, -1.0}, BodyPoint{4.0, 1.0}});
  scene.walls.push_back({BodyPoint{4.0, 1.0}, BodyPoint{2.5, 1.0}});
  scene.walls.push_back({BodyPoint{-5.0, -0.3}, BodyPoint{-5.0, 0.3}});
  scene.circles.push_back({BodyPoint{-2.0, -6.0}, 0.3});
  auto scan = scene.scan();
  LidarClusterer clusterer{LidarClusterParams{}};
  auto a = std::make_unique<Result>();
  auto b = std::make_unique<Result>();
  g_allocations = 0;
  g_counting = true;
  clusterer.process(*scan, a->list, a->profile);
  clusterer.process(*scan, b->list, b->profile);
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  ASSERT_EQ(a->list.count, b->list.count);
  ASSERT_GT(a->list.count, 4U);
  for (std::uint32_t i = 0; i < a->list.count; ++i) {
    EXPECT_EQ(a->list.segments[i].begin.forward_m, b->list.segments[i].begin.forward_m);
    EXPECT_EQ(a->list.segments[i].end.starboard_m, b->list.segments[i].end.starboard_m);
    EXPECT_EQ(a->list.segments[i].closest_range_m, b->list.segments[i].closest_range_m);
  }
  EXPECT_EQ(a->profile.closest_range_m, b->profile.closest_range_m);
}

// Nothing is kept from scan to scan: whatever came before (the same geometry, returns missing,
// angles drifting, an unsorted or odd scan), a long-lived clusterer gives bit for bit what a
// fresh one gives for the same scan.
TEST(LidarClusterer, ScanHistoryDoesNotChangeTheResult) {
  SceneBuilder scene;
  scene.walls.push_back({BodyPoint{6.0, -3.0}, BodyPoint{6.0, 3.0}});
  scene.walls.push_back({BodyPoint{-4.0, -5.0}, BodyPoint{3.0, -5.0}});
  scene.circles.push_back({BodyPoint{2.5, 1.5}, 0.3});
  scene.circles.push_back({BodyPoint{-2.0, 3.0}, 0.25});
  const auto base = scene.scan();
  std::vector<std::unique_ptr<msg::LidarScan>> scans;
  for (int k = 0; k < 24; ++k) {
    auto s = std::make_unique<msg::LidarScan>();
    s->stamp_ns = base->stamp_ns + k;
    for (std::uint32_t i = 0; i < base->point_count; ++i) {
      msg::LidarPoint p = base->points[i];
      if (k % 4 == 1 && (i * 7 + static_cast<std::uint32_t>(k)) % 5 == 0) continue;  // dropouts
      if (k % 4 == 2)
        p.bearing_deg += 0.01F * static_cast<float>((i + static_cast<std::uint32_t>(k)) % 3);
      (void)s->push(p);
    }
    if (k % 4 == 3 && s->point_count > 20) {  // out of order, a NaN and an unwrapped bearing
      std::swap(s->points[3], s->points[9]);
      s->points[5].bearing_deg = std::nanf("");
      s->points[6].bearing_deg += 360.0F;
    }
    scans.push_back(std::move(s));
  }
  for (const LidarClusterParams& params :
       {LidarClusterParams{}, LidarClusterParams::reference_tricat2022()}) {
    LidarClusterer kept(params);
    auto a = std::make_unique<Result>();
    for (const auto& s : scans) {
      kept.process(*s, a->list, a->profile);
      const auto b = run(params, *s);
      ASSERT_EQ(a->list.count, b->list.count);
      for (std::uint32_t i = 0; i < a->list.count; ++i) {
        const ObstacleSegment& x = a->list.segments[i];
        const ObstacleSegment& y = b->list.segments[i];
        EXPECT_EQ(std::memcmp(&x.begin, &y.begin, sizeof(x.begin)), 0);
        EXPECT_EQ(std::memcmp(&x.end, &y.end, sizeof(x.end)), 0);
        EXPECT_EQ(x.closest_range_m, y.closest_range_m);
        EXPECT_EQ(x.point_count, y.point_count);
      }
      EXPECT_EQ(a->profile.closest_range_m, b->profile.closest_range_m);
      EXPECT_EQ(kept.last_stats().points_kept, b->stats.points_kept);
    }
  }
}

// The table-and-series trigonometry that turns every return into a point, against the library's.
TEST(LidarClusterer, BeamTrigonometryIsWithinAFloatsRounding) {
  const LidarClusterer clusterer{LidarClusterParams{}};
  double worst = 0.0;
  const auto check = [&](float bearing_deg) {
    float c = 0.0F;
    float s = 0.0F;
    clusterer.unit_of(bearing_deg, c, s);
    const double a = core::deg_to_rad(static_cast<double>(bearing_deg));
    worst = std::max(worst, std::abs(static_cast<double>(c) - std::cos(a)));
    worst = std::max(worst, std::abs(static_cast<double>(s) - std::sin(a)));
  };
  for (int i = 0; i <= 1440; ++i) {  // the table's own steps and just beside them
    const auto b = static_cast<float>(-180.0 + 0.25 * i);
    check(b);
    if (i > 0) check(std::nextafter(b, -200.0F));
    if (i < 1440) check(std::nextafter(b, 200.0F));
  }
  for (int i = 0; i < 200000; ++i) {  // and everywhere between
    check(static_cast<float>(-180.0 + 360.0 * (i + 0.37) / 200000.0));
  }
  EXPECT_LT(worst, 1.5e-7);
}

// Returns go through the four-at-a-time path or one by one depending on their neighbours (a
// dropped return among them); either way each becomes the same point, bit for bit.
TEST(LidarClusterer, APointDoesNotDependOnItsNeighbours) {
  SceneBuilder scene;
  scene.walls.push_back({BodyPoint{5.0, -2.0}, BodyPoint{5.0, 2.0}});
  scene.circles.push_back({BodyPoint{-2.0, 3.0}, 0.3});
  scene.circles.push_back({BodyPoint{1.0, -3.5}, 0.25});
  const auto base = scene.scan();
  for (std::uint32_t i = 0; i < base->point_count; ++i) {
    base->points[i].bearing_deg += 0.1234F;  // between the trigonometry table's entries
  }
  LidarClusterParams params;
  params.min_group_points = 1;  // every return counts
  const auto a = run(params, *base);
  for (std::uint32_t shift = 1; shift <= 3; ++shift) {
    // The same returns, moved along the lanes by dropped returns (range 0) in front and between
    // them: many now go one by one.
    auto moved = std::make_unique<msg::LidarScan>();
    for (std::uint32_t i = 0; i < shift; ++i) {
      ASSERT_TRUE(moved->push({-179.9F + 0.01F * static_cast<float>(i), 0.0F, 0, 0}));
    }
    for (std::uint32_t i = 0; i < base->point_count; ++i) {
      msg::LidarPoint p = base->points[i];
      if (i % (4 + shift) == 0) {
        ASSERT_TRUE(moved->push({p.bearing_deg, 0.0F, 0, 0}));
      }
      ASSERT_TRUE(moved->push(p));
    }
    const auto b = run(params, *moved);
    ASSERT_EQ(a->list.count, b->list.count);
    for (std::uint32_t i = 0; i < a->list.count; ++i) {
      const ObstacleSegment& x = a->list.segments[i];
      const ObstacleSegment& y = b->list.segments[i];
      EXPECT_EQ(std::memcmp(&x.begin, &y.begin, sizeof(x.begin)), 0) << "segment " << i;
      EXPECT_EQ(std::memcmp(&x.end, &y.end, sizeof(x.end)), 0) << "segment " << i;
    }
    EXPECT_EQ(a->profile.closest_range_m, b->profile.closest_range_m);
  }
}

TEST(LidarClusterer, FullScanOfReturnsStaysWithinCapacity) {
  // A closed ring of kMaxPoints returns (boat in a round pool): one group, no seam break.
  msg::LidarScan scan;
  const auto n = static_cast<int>(msg::LidarScan::kMaxPoints);
  for (int i = 1; i <= n; ++i) {
    msg::LidarPoint p;
    p.bearing_deg = static_cast<float>(-180.0 + 360.0 * i / n);
    p.range_m = 8.0F;
    ASSERT_TRUE(scan.push(p));
  }
  auto r = run({}, scan);
  EXPECT_EQ(r->stats.groups, 1U);
  EXPECT_GT(r->list.count, 50U);
  EXPECT_EQ(r->stats.segments_overflow, 0U);
  for (std::uint32_t i = 0; i < r->list.count; ++i) {
    EXPECT_NEAR(r->list.segments[i].closest_range_m, 8.0, 0.05);
  }
}

}  // namespace
}  // namespace coxswain::perception
