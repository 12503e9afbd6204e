// SPDX-License-Identifier: Apache-2.0
// LidarClusterer against the source team's recorded run on the water (peer/ in the shared test
// data; see peer_recording.hpp for the frame conventions). Skips when the recording is absent.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "coxswain/perception/lidar_clusterer.hpp"
#include "peer_recording.hpp"
#include "support/testdata.hpp"

namespace coxswain::perception {
namespace {

using core::BodyPoint;
using testing::peer::PeerScan;
using testing::peer::PeerSegment;

constexpr const char* kRecording = "peer/tricat221-0223-scans.jsonl";

double dist_m(BodyPoint a, BodyPoint b) {
  return std::hypot(a.forward_m - b.forward_m, a.starboard_m - b.starboard_m);
}
double point_to_segment_m(BodyPoint p, BodyPoint a, BodyPoint b) {
  const double dx = b.forward_m - a.forward_m;
  const double dy = b.starboard_m - a.starboard_m;
  const double len_sq = dx * dx + dy * dy;
  double t = 0.0;
  if (len_sq > 0.0) {
    t = std::clamp(
        ((p.forward_m - a.forward_m) * dx + (p.starboard_m - a.starboard_m) * dy) / len_sq, 0.0,
        1.0);
  }
  return dist_m(p, BodyPoint{a.forward_m + t * dx, a.starboard_m + t * dy});
}

struct Output {
  ObstacleList list;
  RangeProfile profile;
};

TEST(LidarPeerRecording, ReferenceModeReproducesTheirObstacleLists) {
  COXSWAIN_REQUIRE_TESTDATA(path, kRecording);
  const std::vector<PeerScan> scans = testing::peer::load_peer_recording(path);
  ASSERT_EQ(scans.size(), 174U);

  LidarClusterer clusterer(LidarClusterParams::reference_tricat2022());
  auto out = std::make_unique<Output>();
  int compared = 0;
  int count_equal = 0;
  int count_within_1 = 0;
  int max_count_diff = 0;
  int theirs_total = 0;
  int theirs_matched = 0;
  int theirs_near = 0;
  int ours_total = 0;
  for (const PeerScan& s : scans) {
    if (!s.has_segments) continue;
    ++compared;
    clusterer.process(*s.scan, out->list, out->profile);
    const int diff =
        std::abs(static_cast<int>(out->list.count) - static_cast<int>(s.segments.size()));
    count_equal += diff == 0 ? 1 : 0;
    count_within_1 += diff <= 1 ? 1 : 0;
    max_count_diff = std::max(max_count_diff, diff);
    ours_total += static_cast<int>(out->list.count);
    for (const PeerSegment& t : s.segments) {
      ++theirs_total;
      double best_m = 1e9;  // worse endpoint of the best-matching segment of ours
      for (std::uint32_t i = 0; i < out->list.count; ++i) {
        const ObstacleSegment& o = out->list.segments[i];
        best_m = std::min(best_m, std::max(dist_m(o.begin, t.begin), dist_m(o.end, t.end)));
      }
      theirs_matched += best_m < 1e-3 ? 1 : 0;
      theirs_near += best_m < 0.02 ? 1 : 0;
    }
  }
  std::printf(
      "reference mode: %d scans, count equal %d, within +-1 %d, max diff %d; "
      "their segments %d, matched within 1 mm %d, within 2 cm %d; ours %d\n",
      compared, count_equal, count_within_1, max_count_diff, theirs_total, theirs_matched,
      theirs_near, ours_total);
  // Measured (2026-11): 173 scans compared; segment count equal in 158, within +-1 in all 173
  // (max difference 1); of their 6484 segments 6370 (98.2 %) are matched endpoint for endpoint
  // within 1 mm and 6466 (99.7 %) within 2 cm. The differences, all deliberate:
  // - their node let the walk's last group escape the "more than 10 returns" filter, and removed
  //   its seeding duplicate of the first return from whichever group came first (even another
  //   one); reference mode keeps the rules, not these two bugs (a Python replay of their code
  //   with the bugs gives 6484 of 6484, without them 6465);
  // - their scan has 1360 beams over the closed interval [-pi, pi], so the first and the last
  //   beam both point at the bow (bearings +-2.5e-6 deg). Sorted by bearing (as LidarScan is),
  //   the last beam comes second in the walk instead of last: the group ending at the bow loses
  //   its final return and ends ~15 mm away (the ~95 segments between 1 mm and 2 cm).
  EXPECT_EQ(compared, 173);
  EXPECT_GE(count_equal, 150);
  EXPECT_GE(count_within_1, 170);
  EXPECT_LE(max_count_diff, 2);
  EXPECT_GE(theirs_matched * 1000, theirs_total * 975);
  EXPECT_GE(theirs_near * 1000, theirs_total * 995);
}

TEST(LidarPeerRecording, DefaultModeCoversTheirObstaclesWithHonestDistances) {
  COXSWAIN_REQUIRE_TESTDATA(path, kRecording);
  const std::vector<PeerScan> scans = testing::peer::load_peer_recording(path);
  ASSERT_FALSE(scans.empty());

  // Their boat is not ours: no hull box (their lidar saw nothing of its own hull in this run).
  LidarClusterParams params;
  params.hull = HullBox{};
  LidarClusterer clusterer(params);
  auto out = std::make_unique<Output>();
  int theirs_total = 0;
  int theirs_covered = 0;
  int first_point_overstates = 0;
  double worst_overstatement_m = 0.0;
  int ours_total = 0;
  for (const PeerScan& s : scans) {
    clusterer.process(*s.scan, out->list, out->profile);
    ours_total += static_cast<int>(out->list.count);
    double nearest_segment_m = 1e9;
    for (std::uint32_t i = 0; i < out->list.count; ++i) {
      const ObstacleSegment& o = out->list.segments[i];
      // The distance is the true one: never more than either end, equal to the exact value.
      const BodyPoint origin{};
      ASSERT_NEAR(o.closest_range_m, point_to_segment_m(origin, o.begin, o.end), 1e-4);
      ASSERT_LE(o.closest_range_m, std::min(dist_m(o.begin, origin), dist_m(o.end, origin)) + 1e-4);
      nearest_segment_m = std::min(nearest_segment_m, static_cast<double>(o.closest_range_m));
    }
    // The profile agrees with the segments to within the line-fit residual.
    float nearest_bin_m = RangeProfile::kNoReturn;
    for (std::uint32_t b = 0; b < out->profile.bin_count; ++b) {
      nearest_bin_m = std::min(nearest_bin_m, out->profile.closest_range_m[b]);
    }
    if (out->list.count > 0) {
      EXPECT_NEAR(nearest_bin_m, nearest_segment_m, 0.15);
    }

    for (const PeerSegment& t : s.segments) {
      ++theirs_total;
      const BodyPoint mid{(t.begin.forward_m + t.end.forward_m) / 2,
                          (t.begin.starboard_m + t.end.starboard_m) / 2};
      for (std::uint32_t i = 0; i < out->list.count; ++i) {
        if (point_to_segment_m(mid, out->list.segments[i].begin, out->list.segments[i].end) <
            0.15) {
          ++theirs_covered;
          break;
        }
      }
      // Their distance defect: an obstacle measured at its first return.
      const double first_m = dist_m(t.begin, BodyPoint{});
      const double true_m = point_to_segment_m(BodyPoint{}, t.begin, t.end);
      if (first_m - true_m > 0.1) ++first_point_overstates;
      worst_overstatement_m = std::max(worst_overstatement_m, first_m - true_m);
    }
  }
  std::printf(
      "default mode: ours %d segments; their %d segments, %d covered within 0.15 m; "
      "first-return distance overstated by > 0.1 m for %d of theirs (worst %.2f m)\n",
      ours_total, theirs_total, theirs_covered, first_point_overstates, worst_overstatement_m);
  // Measured (2026-11): 174 scans, ours 7259 segments, theirs 6484, all 6484 of theirs covered
  // (midpoint within 0.15 m of one of ours). Their first-return distance overstates the true
  // segment distance by more than 0.1 m for 2360 of their segments (worst 0.59 m): the defect
  // that closest_range_m removes. Deliberate differences of the default mode: proportional gap
  // (0.1 m + 3 % of range), groups of >= 4 returns, split distance 0.1 m + 1 % of range, split
  // returns shared by both halves, equal touching wall pieces, total-least-squares endpoints,
  // seam at the stern merged across, hull box, walk clockwise from astern.
  EXPECT_GE(theirs_covered * 100, theirs_total * 95);
}

}  // namespace
}  // namespace coxswain::perception
