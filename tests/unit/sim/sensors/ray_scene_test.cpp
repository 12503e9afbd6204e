// SPDX-License-Identifier: Apache-2.0
#include "sim/sensors/ray_scene.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "sim/sensors/rng.hpp"

namespace coxswain::sim::sensors {
namespace {

TEST(RayScene, WallAtKnownDistance) {
  RayScene scene;
  scene.add_segment({{5.0, -10.0}, {5.0, 10.0}});  // wall 5 m north, running east-west
  scene.prepare({0.0, 0.0}, 0.5, 12.0);
  EXPECT_NEAR(scene.cast({0.0, 0.0}, 0.0), 5.0, 1e-9);
  // 60 deg off the wall's normal: 5 / cos(60) = 10 m.
  EXPECT_NEAR(scene.cast({0.0, 0.0}, 60.0), 10.0, 1e-9);
  EXPECT_NEAR(scene.cast({0.0, 0.0}, -60.0), 10.0, 1e-9);
  EXPECT_LT(scene.cast({0.0, 0.0}, 180.0), 0.0);  // nothing behind
  EXPECT_LT(scene.cast({0.0, 0.0}, 70.0), 0.0);   // 14.6 m: beyond max range
}

TEST(RayScene, BuoyFrontAndTangent) {
  RayScene scene;
  scene.add_circle({{10.0, 0.0}, 0.5});
  scene.prepare({0.0, 0.0}, 0.5, 30.0);
  EXPECT_NEAR(scene.cast({0.0, 0.0}, 0.0), 9.5, 1e-9);
  // Tangent ray: sin(a) = r / d; just inside it hits near the tangent point at sqrt(d^2 - r^2).
  const double tangent_deg = std::asin(0.5 / 10.0) * 180.0 / std::acos(-1.0);
  const double near_tangent = scene.cast({0.0, 0.0}, tangent_deg - 1e-4);
  EXPECT_NEAR(near_tangent, std::sqrt(100.0 - 0.25), 0.01);
  EXPECT_LT(scene.cast({0.0, 0.0}, tangent_deg + 1e-3), 0.0);
}

TEST(RayScene, BinnedCastEqualsBruteForceFromAnywhereInTheRegion) {
  RayScene scene;
  Rng rng(7);
  for (int i = 0; i < 40; ++i) {
    const core::NavPoint a{rng.uniform(-20, 20), rng.uniform(-20, 20)};
    scene.add_segment({a, {a.north_m + rng.uniform(-6, 6), a.east_m + rng.uniform(-6, 6)}});
    scene.add_circle({{rng.uniform(-20, 20), rng.uniform(-20, 20)}, rng.uniform(0.1, 0.6)});
  }
  const core::NavPoint center{1.0, -2.0};
  scene.prepare(center, 0.8, 12.0);
  int hits = 0;
  for (int i = 0; i < 20000; ++i) {
    const double r = 0.8 * std::sqrt(rng.uniform());
    const double a = rng.uniform(0.0, 6.283185307179586);
    const core::NavPoint o{center.north_m + r * std::cos(a), center.east_m + r * std::sin(a)};
    ASSERT_TRUE(scene.covers(o));
    const double bearing = rng.uniform(-180.0, 180.0);
    const double binned = scene.cast(o, bearing);
    const double brute = scene.cast_brute(o, bearing, 12.0);
    if (brute >= 0.0) ++hits;
    ASSERT_NEAR(binned, brute, 1e-9) << "ray " << i << " bearing " << bearing;
  }
  EXPECT_GT(hits, 1000);
}

}  // namespace
}  // namespace coxswain::sim::sensors
