// SPDX-License-Identifier: Apache-2.0
#include "sim/sensors/ray_scene.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "sim/rng/rng.hpp"
#include "sim/world/course.hpp"
#include "sim/world/world.hpp"

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

// A lidar 8 m out on a slip's axis: rays aimed at the fingers' ends hit them (floating docks
// have pontoons half a metre across); zero-width fingers let the same rays through to the back.
TEST(RayScene, FingersOfADockFaceALidarLookingStraightDownTheSlip) {
  const auto range_at_finger = [](double finger_width_m) {
    world::World w;
    world::Dock d;
    d.name = "dock";
    d.entrance = {10.0, 0.0};
    d.width_m = 1.6;
    d.depth_m = 2.0;
    d.finger_width_m = finger_width_m;
    world::build_dock_geometry(d);
    w.docks.push_back(d);
    RayScene scene(w);
    scene.prepare({2.0, 0.0}, 0.5, 20.0);
    const double finger_middle_e = 0.8 + 0.5 * std::max(finger_width_m, 0.01);
    const double bearing_deg = std::atan2(finger_middle_e, 8.0) * 180.0 / std::acos(-1.0);
    return std::make_pair(scene.cast({2.0, 0.0}, bearing_deg),
                          scene.cast({2.0, 0.0}, -bearing_deg));
  };
  const auto [right_m, left_m] = range_at_finger(0.3);
  EXPECT_NEAR(right_m, 8.0 / std::cos(std::atan2(0.95, 8.0)), 1e-6);
  EXPECT_NEAR(left_m, right_m, 1e-9);
  const auto [thin_right_m, thin_left_m] = range_at_finger(0.0);
  EXPECT_LT(thin_right_m, 0.0);  // past the slip: nothing (the thin back wall spans the slip only)
  EXPECT_LT(thin_left_m, 0.0);
}

}  // namespace
}  // namespace coxswain::sim::sensors
