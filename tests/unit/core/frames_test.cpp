// SPDX-License-Identifier: Apache-2.0
#include "coxswain/core/frames.hpp"

#include <gtest/gtest.h>

namespace coxswain::core {
namespace {

TEST(Frames, BearingIsClockwiseFromNorth) {
  const NavPoint o{0.0, 0.0};
  EXPECT_DOUBLE_EQ(bearing_deg(o, {10.0, 0.0}), 0.0);
  EXPECT_DOUBLE_EQ(bearing_deg(o, {0.0, 10.0}), 90.0);
  EXPECT_DOUBLE_EQ(bearing_deg(o, {-10.0, 0.0}), 180.0);
  EXPECT_DOUBLE_EQ(bearing_deg(o, {0.0, -10.0}), -90.0);
  EXPECT_DOUBLE_EQ(distance_m(o, {3.0, 4.0}), 5.0);
}

TEST(Frames, BodyToNavHeadingEast) {
  const NavPose pose{{100.0, 50.0}, 90.0};
  const NavPoint ahead = body_to_nav(pose, {2.0, 0.0});
  EXPECT_NEAR(ahead.north_m, 100.0, 1e-12);
  EXPECT_NEAR(ahead.east_m, 52.0, 1e-12);
  const NavPoint starboard = body_to_nav(pose, {0.0, 1.0});
  EXPECT_NEAR(starboard.north_m, 99.0, 1e-12);  // facing east, starboard is south
  EXPECT_NEAR(starboard.east_m, 50.0, 1e-12);
}

TEST(Frames, NavToBodyInvertsBodyToNav) {
  const NavPose pose{{-3.0, 7.0}, -137.0};
  for (double f = -5.0; f <= 5.0; f += 2.5) {
    for (double s = -5.0; s <= 5.0; s += 2.5) {
      const BodyPoint back = nav_to_body(pose, body_to_nav(pose, {f, s}));
      EXPECT_NEAR(back.forward_m, f, 1e-12);
      EXPECT_NEAR(back.starboard_m, s, 1e-12);
    }
  }
}

// The 2022 boat mounted its lidar facing the stern: a return straight ahead of the lidar is astern.
TEST(Frames, MountFacingAstern) {
  const MountTransform mount{180.0, 0.3, 0.0};
  const BodyPoint p = sensor_to_body(mount, {2.0, 0.0});
  EXPECT_NEAR(p.forward_m, -1.7, 1e-12);
  EXPECT_NEAR(p.starboard_m, 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(sensor_bearing_to_body_deg(mount, 10.0), -170.0);
}

TEST(Frames, MountYawedToStarboard) {
  const MountTransform mount{90.0, 0.0, 0.0};  // camera looking to starboard
  const BodyPoint p = sensor_to_body(mount, {1.0, 0.0});
  EXPECT_NEAR(p.forward_m, 0.0, 1e-12);
  EXPECT_NEAR(p.starboard_m, 1.0, 1e-12);
}

}  // namespace
}  // namespace coxswain::core
