// SPDX-License-Identifier: Apache-2.0
#include "coxswain/core/geodesy.hpp"

#include <gtest/gtest.h>

#include "coxswain/core/frames.hpp"

namespace coxswain::core {
namespace {

// A point near the KABOAT venue (Busan); exact values are not needed, only consistency.
constexpr GeoPoint kOrigin{35.0690, 128.8280, 0.0};

TEST(LocalFrame, OriginMapsToZero) {
  const LocalFrame frame(kOrigin);
  const NavPoint p = frame.to_nav(kOrigin);
  EXPECT_NEAR(p.north_m, 0.0, 1e-9);
  EXPECT_NEAR(p.east_m, 0.0, 1e-9);
}

TEST(LocalFrame, NorthIsXAndEastIsY) {
  const LocalFrame frame(kOrigin);
  // One arc-second of latitude is about 30.8 m.
  const NavPoint north = frame.to_nav({kOrigin.lat_deg + 1.0 / 3600.0, kOrigin.lon_deg, 0.0});
  EXPECT_NEAR(north.north_m, 30.83, 0.05);
  EXPECT_NEAR(north.east_m, 0.0, 0.01);
  const NavPoint east = frame.to_nav({kOrigin.lat_deg, kOrigin.lon_deg + 1.0 / 3600.0, 0.0});
  EXPECT_GT(east.east_m, 25.0);
  EXPECT_LT(east.east_m, 25.5);
  EXPECT_NEAR(east.north_m, 0.0, 0.01);
  EXPECT_NEAR(bearing_deg({0, 0}, east), 90.0, 0.01);
}

TEST(LocalFrame, RoundTripIsMillimetreExact) {
  const LocalFrame frame(kOrigin);
  for (double n = -300.0; n <= 300.0; n += 150.0) {
    for (double e = -300.0; e <= 300.0; e += 150.0) {
      const NavPoint back = frame.to_nav(frame.to_geo({n, e}));
      EXPECT_NEAR(back.north_m, n, 1e-6);
      EXPECT_NEAR(back.east_m, e, 1e-6);
    }
  }
}

TEST(LocalFrame, CopyKeepsOrigin) {
  const LocalFrame a(kOrigin);
  const LocalFrame b = a;
  const NavPoint pa = a.to_nav({35.07, 128.83, 0.0});
  const NavPoint pb = b.to_nav({35.07, 128.83, 0.0});
  EXPECT_DOUBLE_EQ(pa.north_m, pb.north_m);
  EXPECT_DOUBLE_EQ(pa.east_m, pb.east_m);
}

}  // namespace
}  // namespace coxswain::core
