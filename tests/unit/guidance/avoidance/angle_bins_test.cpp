// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/angle_bins.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "coxswain/core/angles.hpp"
#include "support/obstacles.hpp"

namespace coxswain::guidance {
namespace {

using test::segment;

AngleBins make(double min_deg = -90.0, double max_deg = 90.0, double w = 1.0) {
  AngleBins b;
  EXPECT_TRUE(b.configure({min_deg, max_deg, w}));
  return b;
}

std::size_t blocked_count(const AngleBins& b, double limit_m) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < b.size(); ++i)
    if (b.range_m(i) < limit_m) ++n;
  return n;
}

TEST(AngleBins, RejectsBadFans) {
  AngleBins b;
  EXPECT_FALSE(b.configure({10.0, -10.0, 1.0}));
  EXPECT_FALSE(b.configure({-90.0, 90.0, 0.7}));  // not a whole number of bins
  EXPECT_FALSE(b.configure({-180.0, 181.0, 1.0}));
  EXPECT_TRUE(b.configure({-180.0, 180.0, 0.5}));
  EXPECT_EQ(b.size(), 720U);
}

TEST(AngleBins, IndexAndCentre) {
  const AngleBins b = make();
  EXPECT_EQ(b.size(), 180U);
  EXPECT_EQ(b.index_of(0.0), 90U);
  EXPECT_EQ(b.index_of(-0.1), 89U);
  EXPECT_EQ(b.index_of(-90.0), 0U);
  EXPECT_EQ(b.index_of(90.0), b.size());  // half-open fan
  EXPECT_EQ(b.index_of(135.0), b.size());
  EXPECT_DOUBLE_EQ(b.center_deg(90), 0.5);
}

TEST(AngleBins, PointAheadWithoutHullCoversOnlyItsBins) {
  AngleBins b = make();
  b.add_segment(segment(5.0, -0.01, 5.0, 0.01), 0.0);
  EXPECT_NEAR(b.range_m(89), 5.0, 1e-6);
  EXPECT_NEAR(b.range_m(90), 5.0, 1e-6);
  EXPECT_EQ(blocked_count(b, 100.0), 2U);
}

TEST(AngleBins, MarginShrinksWithDistanceAsAsin) {
  const double hull = 0.8;
  for (const double d : {1.5, 3.0, 10.0}) {
    AngleBins b = make();
    b.add_segment(segment(d, 0.0, d, 0.0), hull);
    const double margin = core::rad_to_deg(std::asin(hull / d));
    for (std::size_t i = 0; i < b.size(); ++i) {
      // Bin i's nearest edge to the obstacle's bearing (0).
      const double lo = -90.0 + static_cast<double>(i);
      const double gap = lo >= 0.0 ? lo : (lo + 1.0 <= 0.0 ? -(lo + 1.0) : 0.0);
      if (gap < margin - 1e-6) {
        EXPECT_LT(b.range_m(i), 100.0) << "d=" << d << " bin " << i;
      } else if (gap > margin + 1e-6) {
        EXPECT_GE(b.range_m(i), AngleBins::kNoObstacle) << "d=" << d << " bin " << i;
      }
    }
  }
  AngleBins near = make();
  AngleBins far = make();
  near.add_segment(segment(1.0, 0.0, 1.0, 0.0), hull);
  far.add_segment(segment(10.0, 0.0, 10.0, 0.0), hull);
  EXPECT_GT(blocked_count(near, 100.0), 5 * blocked_count(far, 100.0));
}

TEST(AngleBins, WallSpanningTheWholeFanFillsEveryBin) {
  // Fan -60..60; a wall 4 m ahead from bearing -68 to +68: both ends outside the fan.
  AngleBins b = make(-60.0, 60.0, 1.0);
  b.add_segment(segment(4.0, -10.0, 4.0, 10.0), 0.0);
  for (std::size_t i = 0; i < b.size(); ++i) {
    const double c = core::deg_to_rad(b.center_deg(i));
    // True distance within the bin: at most the distance along its centre ray.
    EXPECT_LE(b.range_m(i), 4.0 / std::cos(c) + 1e-9) << i;
    EXPECT_GE(b.range_m(i), 4.0 - 1e-9) << i;
  }
  EXPECT_NEAR(b.range_m(b.index_of(0.0)), 4.0, 1e-9);  // the bow bin sees the true closest point
}

TEST(AngleBins, TrueClosestDistanceNotFirstPoint) {
  AngleBins b = make();
  // First point ~10 m away to port; the segment passes 3 m ahead of the bow.
  b.add_segment(segment(3.0, -9.5, 3.0, 9.5), 0.0);
  EXPECT_NEAR(b.range_m(b.index_of(0.2)), 3.0, 1e-9);
  EXPECT_NEAR(b.min_range_m(), 3.0, 1e-9);
}

TEST(AngleBins, SegmentBehindCrossingTheStern) {
  AngleBins b = make(-180.0, 180.0, 1.0);
  b.add_segment(segment(-3.0, 1.0, -3.0, -1.0), 0.0);  // across the stern, +-180 deg
  EXPECT_NEAR(b.range_m(b.index_of(179.7)), 3.0, 0.01);
  EXPECT_NEAR(b.range_m(b.index_of(-179.7)), 3.0, 0.01);
  EXPECT_GE(b.range_m(b.index_of(0.0)), AngleBins::kNoObstacle);
  EXPECT_GE(b.range_m(b.index_of(150.0)), AngleBins::kNoObstacle);
}

TEST(AngleBins, InsideTheHullBlocksTheWholeForwardHalfOnThatSide) {
  AngleBins b = make();
  b.add_segment(segment(0.0, 0.5, 0.0, 0.5), 0.8);  // abeam to starboard, within the hull margin
  EXPECT_LT(b.range_m(b.index_of(45.0)), 1.0);
  EXPECT_LT(b.range_m(b.index_of(5.0)), 1.0);
  EXPECT_GE(b.range_m(b.index_of(-45.0)), AngleBins::kNoObstacle);
}

TEST(AngleBins, FillSkipsOutOfRangeSegments) {
  AngleBins b = make();
  perception::ObstacleList list;
  ASSERT_TRUE(list.push(segment(20.0, 0.0, 20.0, 1.0)));
  ASSERT_TRUE(list.push(segment(5.0, 2.0, 5.0, 3.0)));
  b.fill(list, 0.5, 10.0);
  EXPECT_GE(b.range_m(b.index_of(0.0)), AngleBins::kNoObstacle);
  EXPECT_LT(b.range_m(b.index_of(25.0)), 10.0);
}

}  // namespace
}  // namespace coxswain::guidance
