// SPDX-License-Identifier: Apache-2.0
#include "coxswain/guidance/pure_pursuit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "coxswain/core/angles.hpp"

namespace coxswain::guidance {
namespace {

using core::NavPoint;

TEST(PurePursuit, EmptyPathIsInvalid) {
  PurePursuit pp({});
  EXPECT_FALSE(pp.update({}, {}).valid);
  EXPECT_TRUE((PurePursuitParams{-1.0, 1.0}).validate().has_value());
}

TEST(PurePursuit, OnAStraightPathAheadIsStraight) {
  PurePursuit pp({2.5, 1.0});
  const std::vector<NavPoint> path{{0.0, 0.0}, {50.0, 0.0}};
  const auto c = pp.update(path, {{10.0, 0.0}, 0.0});
  ASSERT_TRUE(c.valid);
  EXPECT_NEAR(c.target.north_m, 12.5, 1e-9);
  EXPECT_NEAR(c.alpha_deg, 0.0, 1e-9);
  EXPECT_NEAR(c.curvature_per_m, 0.0, 1e-12);
  EXPECT_FALSE(c.at_end);
}

TEST(PurePursuit, OffsetFromAStraightPathUsesTheDocumentsCurvature) {
  const double ld = 2.5;
  PurePursuit pp({ld, 1.0});
  const std::vector<NavPoint> path{{0.0, 0.0}, {50.0, 0.0}};
  const auto c = pp.update(path, {{10.0, 1.0}, 0.0});  // 1 m east of the path, heading north
  const double along = std::sqrt(ld * ld - 1.0);
  EXPECT_NEAR(c.target.north_m, 10.0 + along, 1e-9);
  EXPECT_NEAR(c.target.east_m, 0.0, 1e-9);
  const double alpha = -std::atan2(1.0, along);  // turn to port, toward the path
  EXPECT_NEAR(c.alpha_deg, core::rad_to_deg(alpha), 1e-9);
  EXPECT_NEAR(c.curvature_per_m, 2.0 * std::sin(alpha) / ld, 1e-12);
  EXPECT_NEAR(c.heading_deg, core::rad_to_deg(alpha), 1e-9);
}

TEST(PurePursuit, OnACircleTheCurvatureIsOneOverRadius) {
  const double r = 10.0;
  std::vector<NavPoint> circle;
  for (int k = 0; k <= 180; ++k) {
    const double a = core::deg_to_rad(k);
    circle.push_back({r * std::sin(a), r - r * std::cos(a)});  // starts north-bound, curves east
  }
  PurePursuit pp({3.0, 1.0});
  const auto c = pp.update(circle, {{0.0, 0.0}, 0.0});
  EXPECT_NEAR(c.curvature_per_m, 1.0 / r, 0.01 / r);
  EXPECT_GT(c.alpha_deg, 0.0);  // to starboard
}

TEST(PurePursuit, KinematicBoatConvergesOntoAnLShapedPath) {
  PurePursuit pp({2.0, 0.8});
  const std::vector<NavPoint> path{{0.0, 0.0}, {20.0, 0.0}, {20.0, 20.0}};
  core::NavPose pose{{0.0, 1.5}, 20.0};
  const double v = 1.0;
  const double dt = 0.05;
  bool done = false;
  double max_err_first_leg = 0.0;
  for (int k = 0; k < 2000 && !done; ++k) {
    const auto c = pp.update(path, pose);
    done = c.at_end;
    pose.heading_deg =
        core::wrap_deg(pose.heading_deg + core::rad_to_deg(v * c.curvature_per_m * dt));
    pose.position.north_m += v * dt * std::cos(core::deg_to_rad(pose.heading_deg));
    pose.position.east_m += v * dt * std::sin(core::deg_to_rad(pose.heading_deg));
    if (pose.position.north_m > 8.0 && pose.position.north_m < 16.0) {
      max_err_first_leg = std::max(max_err_first_leg, std::abs(pose.position.east_m));
    }
  }
  EXPECT_TRUE(done);
  EXPECT_LT(max_err_first_leg, 0.1);
  EXPECT_LT(core::distance_m(pose.position, path.back()), 0.8 + 1e-9);
}

TEST(PurePursuit, PathEndTargetsTheLastPoint) {
  PurePursuit pp({3.0, 1.0});
  const std::vector<NavPoint> path{{0.0, 0.0}, {10.0, 0.0}};
  const auto c = pp.update(path, {{8.5, 0.5}, 0.0});
  EXPECT_DOUBLE_EQ(c.target.north_m, 10.0);
  EXPECT_DOUBLE_EQ(c.target.east_m, 0.0);
  EXPECT_FALSE(c.at_end);
  EXPECT_TRUE(pp.update(path, {{9.5, 0.2}, 0.0}).at_end);
}

TEST(PurePursuit, FarOffThePathHeadsBackToIt) {
  PurePursuit pp({2.0, 1.0});
  const std::vector<NavPoint> path{{0.0, 0.0}, {50.0, 0.0}};
  const auto c = pp.update(path, {{10.0, 8.0}, 0.0});
  EXPECT_NEAR(c.target.north_m, 10.0, 1e-9);
  EXPECT_NEAR(c.target.east_m, 0.0, 1e-9);
  EXPECT_NEAR(c.heading_deg, -90.0, 1e-9);
}

}  // namespace
}  // namespace coxswain::guidance
