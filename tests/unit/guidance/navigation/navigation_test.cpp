// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "coxswain/core/angles.hpp"
#include "coxswain/guidance/buoy_circling.hpp"
#include "coxswain/guidance/docking_approach.hpp"
#include "coxswain/guidance/gps_calibration.hpp"
#include "coxswain/guidance/line_follow.hpp"
#include "coxswain/guidance/position_filter.hpp"
#include "coxswain/guidance/waypoint_follower.hpp"

namespace coxswain::guidance {
namespace {

constexpr double kDt = 0.1;
const core::TimeNs kTickNs = core::sec_to_ns(kDt);

// Kinematic boat: heading turns toward the desired one at a limited rate; a current drifts it.
struct Boat {
  core::NavPose pose;
  double speed_mps = 1.0;
  double max_rate_dps = 30.0;
  core::NavPoint current_mps;
  void step(double desired_deg) {
    const double turn = std::clamp(core::angle_diff_deg(desired_deg, pose.heading_deg),
                                   -max_rate_dps * kDt, max_rate_dps * kDt);
    pose.heading_deg = core::wrap_deg(pose.heading_deg + turn);
    const double h = core::deg_to_rad(pose.heading_deg);
    pose.position.north_m += kDt * (speed_mps * std::cos(h) + current_mps.north_m);
    pose.position.east_m += kDt * (speed_mps * std::sin(h) + current_mps.east_m);
  }
};

TEST(LineFollow, GeometrySigns) {
  const LineFollower lf;
  const LineFollowOutput o = lf.geometry({0, 0}, {10, 0}, {4, 2});  // leg north, boat east of it
  EXPECT_NEAR(o.cross_track_m, 2.0, 1e-12);                         // starboard of a northbound leg
  EXPECT_NEAR(o.along_track_m, 4.0, 1e-12);
  EXPECT_NEAR(o.progress, 0.4, 1e-12);
  EXPECT_LT(o.desired_heading_deg, 0.0);  // steer back to port
  EXPECT_NEAR(o.desired_heading_deg, -core::rad_to_deg(std::atan2(2.0, 4.0)), 1e-9);
}

// Boat 10 m off a northbound leg. Steering at the bearing of the point (the 2022 code) only meets
// the leg at the point; line following is back on the leg within a few look-aheads.
TEST(LineFollow, OffsetBoatConvergesToTheLineWherePureBearingDoesNot) {
  const core::NavPoint from{0, 0};
  const core::NavPoint to{100, 0};
  auto run = [&](bool line) {
    Boat b;
    b.pose.position = {0, 10};
    LineFollower lf;
    for (int i = 0; i < 400 && b.pose.position.north_m < 40.0; ++i) {
      const double d = line ? lf.update(from, to, b.pose.position, kDt).desired_heading_deg
                            : core::bearing_deg(b.pose.position, to);
      b.step(d);
    }
    return std::abs(lf.geometry(from, to, b.pose.position).cross_track_m);
  };
  EXPECT_GT(run(false), 5.0);  // 10 * (1 - 40/100) = 6 m still off
  EXPECT_LT(run(true), 0.5);
}

// A side current: plain LOS settles off the line, ILOS integrates the offset away.
TEST(LineFollow, IntegralRemovesCurrentOffset) {
  auto run = [](double sigma) {
    LineFollowParams p;
    p.integral_gain = sigma;
    LineFollower lf(p);
    Boat b;
    b.current_mps = {0.0, 0.25};
    for (int i = 0; i < 1500; ++i)
      b.step(lf.update({0, 0}, {500, 0}, b.pose.position, kDt).desired_heading_deg);
    return lf.geometry({0, 0}, {500, 0}, b.pose.position).cross_track_m;
  };
  EXPECT_GT(std::abs(run(0.0)), 0.8);
  EXPECT_LT(std::abs(run(0.2)), 0.2);
}

TEST(WaypointFollower, ArrivesInOrderAndFinishes) {
  WaypointFollower f;
  const std::vector<core::NavPoint> route{{30, 0}, {30, 30}, {0, 0}};
  ASSERT_TRUE(f.set_route(route));
  Boat b;
  std::vector<std::size_t> arrived;
  core::TimeNs t = 0;
  for (int i = 0; i < 3000 && !f.finished(); ++i) {
    const WaypointGuidance g = f.update(b.pose.position, t += kTickNs);
    if (g.event == WaypointEvent::kArrived) arrived.push_back(g.event_index);
    if (!g.finished) b.step(g.desired_heading_deg);
  }
  EXPECT_EQ(arrived, (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_EQ(f.missed_count(), 0U);
  EXPECT_TRUE(f.update(b.pose.position, t + kTickNs).finished);
}

TEST(WaypointFollower, PassedAbeamWithinSlipRadiusCountsAsMissed) {
  WaypointFollower f;  // arrival 1.5 m, slip 4 m
  const std::vector<core::NavPoint> route{{20, 0}, {40, 0}};
  ASSERT_TRUE(f.set_route(route));
  core::TimeNs t = 0;
  (void)f.update({0, 0}, t += kTickNs);
  EXPECT_EQ(f.update({19, 3}, t += kTickNs).event, WaypointEvent::kNone);  // not abeam yet
  const WaypointGuidance g = f.update({20.2, 3}, t += kTickNs);            // abeam, 3 m off
  EXPECT_EQ(g.event, WaypointEvent::kMissed);
  EXPECT_EQ(g.index, 1U);
  EXPECT_EQ(f.missed_count(), 1U);
}

TEST(WaypointFollower, PassedAbeamFarOutsideSlipRadiusTurnsBack) {
  WaypointFollower f;
  const std::vector<core::NavPoint> route{{20, 0}, {40, 0}};
  ASSERT_TRUE(f.set_route(route));
  (void)f.update({0, 0}, kTickNs);
  const WaypointGuidance g = f.update({22, 8}, 2 * kTickNs);
  EXPECT_EQ(g.event, WaypointEvent::kNone);
  EXPECT_EQ(g.index, 0U);
  EXPECT_NEAR(g.desired_heading_deg, core::bearing_deg({22, 8}, {20, 0}), 1e-9);
}

TEST(WaypointFollower, RejectsBadRoutes) {
  WaypointFollower f;
  EXPECT_FALSE(f.set_route({}));
  std::vector<core::NavPoint> big(WaypointFollower::kMaxWaypoints + 1);
  EXPECT_FALSE(f.set_route(big));
  EXPECT_TRUE(f.update({0, 0}, 0).finished);
}

TEST(GpsCalibration, OffsetFromFixesAtTheStartPoint) {
  GpsCalibration cal({}, {0, 0});
  for (int i = 0; i < 30; ++i) {
    const double jitter = 0.2 * std::sin(i * 1.3);
    cal.add(
        {3.0 + jitter, 4.0 - jitter});  // the KABOAT 2022 report's example: (3, 4) at the origin
  }
  const CalibrationResult r = cal.result();
  ASSERT_EQ(r.status, CalibrationStatus::kOk) << to_string(r.status);
  EXPECT_NEAR(r.offset.north_m, 3.0, 0.05);
  EXPECT_NEAR(r.offset.east_m, 4.0, 0.05);
  const core::NavPoint fixed = r.offset.apply({13.0, 24.0});
  EXPECT_NEAR(fixed.north_m, 10.0, 0.05);
  EXPECT_NEAR(fixed.east_m, 20.0, 0.05);
}

TEST(GpsCalibration, RefusesTooFewFixesWideSpreadAndHugeOffset) {
  GpsCalibration few;
  for (int i = 0; i < 5; ++i) few.add({1, 1});
  EXPECT_EQ(few.result().status, CalibrationStatus::kTooFewFixes);

  GpsCalibration moving;
  for (int i = 0; i < 30; ++i) moving.add({0.2 * i, 0});  // boat drifting 6 m
  EXPECT_EQ(moving.result().status, CalibrationStatus::kSpreadTooLarge);

  GpsCalibration far;
  for (int i = 0; i < 30; ++i) far.add({60, 0});
  EXPECT_EQ(far.result().status, CalibrationStatus::kOffsetTooLarge);
  EXPECT_FALSE(GpsCalibrationParams{}.validate().has_value());
}

// Deterministic pseudo-noise (a fixed-seed LCG mapped to roughly N(0, sigma)), no <random> state.
struct Noise {
  std::uint64_t s = 12345;
  double next(double sigma) {
    double sum = 0.0;
    for (int i = 0; i < 12; ++i) {
      s = s * 6364136223846793005ULL + 1442695040888963407ULL;
      sum += static_cast<double>(s >> 11) / static_cast<double>(1ULL << 53);
    }
    return (sum - 6.0) * sigma;
  }
};

TEST(PositionFilter, SmoothsFixNoiseWhileMovingWithoutLag) {
  // 1 m/s north-east, 5 Hz fixes with 0.4 m noise per axis, exact velocity: the estimate's error
  // must be well under the raw fixes' (about 0.42 of it at gain 0.3) and unbiased along track.
  PositionFilter filter({0.3});
  PositionFilter raw({1.0});
  Noise noise;
  const core::NavPoint vel{0.7, 0.7};
  double se_f = 0.0;
  double se_r = 0.0;
  double along_f = 0.0;
  int n = 0;
  for (int k = 0; k < 500; ++k) {
    const double t = 0.2 * k;
    const core::NavPoint truth{vel.north_m * t, vel.east_m * t};
    const core::NavPoint fix{truth.north_m + noise.next(0.4), truth.east_m + noise.next(0.4)};
    const core::TimeNs stamp = core::sec_to_ns(t);
    filter.add_fix(fix, stamp, vel);
    raw.add_fix(fix, stamp, vel);
    if (k < 50) continue;
    // Half-way to the next fix: the filter dead-reckons, the raw fix is held.
    const core::TimeNs mid = stamp + core::sec_to_ns(0.1);
    const core::NavPoint tm{truth.north_m + vel.north_m * 0.1, truth.east_m + vel.east_m * 0.1};
    const core::NavPoint ef = filter.position_at(mid);
    const core::NavPoint er = raw.position_at(mid);
    se_f += std::pow(ef.north_m - tm.north_m, 2) + std::pow(ef.east_m - tm.east_m, 2);
    se_r += std::pow(er.north_m - tm.north_m, 2) + std::pow(er.east_m - tm.east_m, 2);
    along_f += (ef.north_m - tm.north_m + ef.east_m - tm.east_m) / std::sqrt(2.0);
    ++n;
  }
  const double rms_f = std::sqrt(se_f / n);
  const double rms_r = std::sqrt(se_r / n);
  EXPECT_LT(rms_f, 0.55 * rms_r) << rms_f << " vs raw " << rms_r;
  EXPECT_LT(std::abs(along_f / n), 0.05);
}

TEST(PositionFilter, RawGainHoldsTheFixAndAnOutageRestarts) {
  PositionFilter raw({1.0});
  raw.add_fix({1.0, 2.0}, 0, core::NavPoint{1.0, 0.0});
  const core::NavPoint held = raw.position_at(core::sec_to_ns(0.2));
  EXPECT_DOUBLE_EQ(held.north_m, 1.0);
  EXPECT_DOUBLE_EQ(held.east_m, 2.0);

  PositionFilter f({0.3, 1.0, 0.5});
  f.add_fix({0.0, 0.0}, 0, core::NavPoint{0.0, 0.0});
  f.add_fix({10.0, 0.0}, core::sec_to_ns(5.0), core::NavPoint{0.0, 0.0});  // after an outage
  EXPECT_DOUBLE_EQ(f.position_at(core::sec_to_ns(5.0)).north_m, 10.0);
  // Dead reckoning stops max_predict_s after the last fix.
  f.add_fix({10.0, 0.0}, core::sec_to_ns(5.2), core::NavPoint{2.0, 0.0});
  EXPECT_NEAR(f.position_at(core::sec_to_ns(9.0)).north_m, 10.0 + 2.0 * 0.5, 1e-9);
}

TEST(PositionFilter, TravelledIntegratesTheReceiverVelocity) {
  // A boat drifting at 0.2 m/s west while it waits: after 4 s it is 0.8 m off the start point.
  PositionFilter f;
  for (int k = 0; k <= 20; ++k) {
    f.add_fix({0.0, -0.2 * 0.2 * k}, core::sec_to_ns(0.2 * k), core::NavPoint{0.0, -0.2});
  }
  EXPECT_NEAR(f.travelled_m().east_m, -0.8, 1e-9);
  EXPECT_NEAR(f.travelled_m().north_m, 0.0, 1e-12);
  f.reset();
  EXPECT_DOUBLE_EQ(f.travelled_m().east_m, 0.0);
}

TEST(DockingApproach, AimsAheadOfTheProjectionOnTheRay) {
  DockingApproach d;  // look-ahead 1.5 m, stop 0.3 m
  ASSERT_TRUE(d.set_ray({0, 0}, {10, 0}));
  const DockingCommand c = d.pursue({{4, 1}, 0.0}, 2.0);
  EXPECT_NEAR(c.along_ray_m, 4.0, 1e-12);
  EXPECT_NEAR(c.cross_ray_m, 1.0, 1e-12);
  EXPECT_NEAR(c.aim.north_m, 5.5, 1e-12);
  EXPECT_NEAR(c.aim.east_m, 0.0, 1e-12);
  EXPECT_NEAR(c.desired_heading_deg, core::bearing_deg({4, 1}, {5.5, 0}), 1e-12);
  EXPECT_FALSE(c.stop);
  EXPECT_FALSE(d.set_ray({0, 0}, {0.01, 0}));
}

TEST(DockingApproach, StopsUnderTheStopDistanceAndLatches) {
  DockingApproach d;
  ASSERT_TRUE(d.set_ray({0, 0}, {10, 0}));
  EXPECT_FALSE(d.pursue({{8, 0}, 0.0}, 0.31).stop);
  EXPECT_TRUE(d.pursue({{8.1, 0}, 0.0}, 0.29).stop);
  EXPECT_TRUE(d.pursue({{8.1, 0}, 0.0}, 0.8).stop);  // latched against lidar noise
  d.reset();
  EXPECT_FALSE(d.hold_marker(0.0, 5.0, std::nullopt).stop);
  EXPECT_NEAR(d.hold_marker(170.0, 15.0, 1.0).desired_heading_deg, -175.0, 1e-12);
}

TEST(DockingApproach, RangeAheadFromProfile) {
  perception::RangeProfile p;
  p.bin_width_deg = 1.0F;
  p.bin_count = 360;
  p.closest_range_m.fill(perception::RangeProfile::kNoReturn);
  EXPECT_FALSE(min_range_ahead_m(p, 10.0).has_value());
  p.closest_range_m[180 + 30] = 0.2F;  // 30 deg to starboard: not ahead
  p.closest_range_m[180 + 5] = 0.9F;
  p.closest_range_m[180 - 3] = 0.7F;
  const auto r = min_range_ahead_m(p, 10.0);
  ASSERT_TRUE(r.has_value());
  EXPECT_NEAR(*r, 0.7, 1e-6);
}

TEST(BuoyCircling, SteersTowardTheBuoyWhenItDriftsAft) {
  BuoyCircling c;  // hold at -90 (port)
  const BuoyCirclingOutput o = c.update(0.0, {-110.0, std::nullopt});
  EXPECT_NEAR(o.desired_heading_deg, -20.0, 1e-12);  // turn 20 deg to port
  const BuoyCirclingOutput far = c.update(0.0, {-90.0, 5.0});
  EXPECT_LT(far.desired_heading_deg, 0.0);  // too far: closer, toward port
  const BuoyCirclingOutput close = c.update(0.0, {-90.0, 1.0});
  EXPECT_GT(close.desired_heading_deg, 0.0);
}

// The 2026 plan ends the circle when the heading has passed 0 twice. A compass that wobbles
// +-3 deg near north crosses 0 many times; the accumulated wrap-safe turn does not care.
TEST(BuoyCircling, CountsOneTurnWithNoisyHeadingCrossingZero) {
  BuoyCircling c;
  int naive_crossings = 0;
  double prev = 0.0;
  int done_at = -1;
  const int steps = 720;  // -0.5 deg per step: one full counter-clockwise turn
  for (int i = 0; i <= steps + 40; ++i) {
    const double noise = 3.0 * std::sin(i * 2.1);
    const double h = core::wrap_deg(-0.5 * i + noise);
    if (i > 0 && std::signbit(h) != std::signbit(prev) && std::abs(h) < 90.0) ++naive_crossings;
    prev = h;
    const BuoyCirclingOutput o = c.update(h, {-90.0, std::nullopt});  // the buoy abeam
    if (o.done && done_at < 0) done_at = i;
  }
  EXPECT_GT(naive_crossings, 4);  // "passed 0 twice" fires almost at once
  ASSERT_GE(done_at, 0);
  EXPECT_NEAR(done_at, steps, 12);  // within the +-3 deg noise of a true 360
}

TEST(BuoyCircling, IgnoresCompassGlitches) {
  BuoyCircling c;
  const BuoyObservation abeam{-90.0, std::nullopt};
  c.update(10.0, abeam);
  c.update(-170.0, abeam);  // a 180 deg spike
  const BuoyCirclingOutput o = c.update(10.0, abeam);
  EXPECT_NEAR(o.turned_deg, 0.0, 1e-12);
}

// A boat that turns a full circle without the buoy in sight (searching for it, or circling the
// wrong place) has not gone round it: only the turn made while it is observed counts. The
// documents' way (every turn counts) stays available.
TEST(BuoyCircling, ATurnMadeBlindDoesNotCountTowardTheCircle) {
  BuoyCirclingParams only_seen;
  only_seen.count_only_seen = true;
  BuoyCircling c(only_seen);
  BuoyCircling documents;  // the default: every turn counts
  BuoyCirclingOutput blind;
  BuoyCirclingOutput counted;
  for (int i = 0; i <= 400; ++i) {
    const double h = core::wrap_deg(-1.0 * i);  // 400 deg counter-clockwise
    blind = c.update(h, {});
    counted = documents.update(h, {});
  }
  EXPECT_FALSE(blind.done);
  EXPECT_NEAR(blind.progress_deg, 0.0, 1e-12);
  EXPECT_TRUE(counted.done);
  EXPECT_NEAR(counted.progress_deg, 400.0, 1e-9);
  // Half a turn more with the buoy abeam: that half counts.
  for (int i = 401; i <= 580; ++i) blind = c.update(core::wrap_deg(-1.0 * i), {-90.0, 3.0});
  EXPECT_NEAR(blind.progress_deg, 180.0, 1e-9);
  EXPECT_FALSE(blind.done);
}

// Closed loop: a boat at 0.8 m/s holding a buoy on its port beam goes round it once.
TEST(BuoyCircling, ClosedLoopCirclesTheBuoy) {
  BuoyCircling c;
  Boat b;
  b.speed_mps = 0.8;
  b.max_rate_dps = 40.0;
  b.pose.position = {0, 3};  // buoy at the origin, 3 m to port of a northbound boat
  double min_d = 1e9;
  double max_d = 0.0;
  bool done = false;
  for (int i = 0; i < 1200 && !done; ++i) {
    const double brg =
        core::angle_diff_deg(core::bearing_deg(b.pose.position, {0, 0}), b.pose.heading_deg);
    const double rng = core::distance_m(b.pose.position, {0, 0});
    min_d = std::min(min_d, rng);
    max_d = std::max(max_d, rng);
    const BuoyCirclingOutput o = c.update(b.pose.heading_deg, {brg, rng});
    done = o.done;
    b.step(o.desired_heading_deg);
  }
  EXPECT_TRUE(done);
  EXPECT_GT(min_d, 1.5);
  EXPECT_LT(max_d, 5.0);
}

}  // namespace
}  // namespace coxswain::guidance

namespace coxswain::guidance {
namespace {

TEST(DockingApproach, SlipOfMarkerByRankThenByNearestBearing) {
  // Three markers seen, all shifted 12 deg to starboard by a position error: rank still names
  // the slip (nearest bearing would have picked the neighbour).
  const std::array<double, 3> slips{-20.0, 0.0, 20.0};
  const std::array<double, 3> seen{8.0, 32.0, -12.0};
  EXPECT_EQ(slip_of_marker(seen, 0, slips, 15.0), std::optional<std::size_t>(1));
  EXPECT_EQ(slip_of_marker(seen, 1, slips, 15.0), std::optional<std::size_t>(2));
  const std::array<double, 1> one{17.0};
  EXPECT_EQ(slip_of_marker(one, 0, slips, 5.0), std::optional<std::size_t>(2));
  EXPECT_FALSE(slip_of_marker(one, 0, slips, 2.0).has_value());
  EXPECT_FALSE(slip_of_marker(one, 1, slips, 15.0).has_value());
}

TEST(DockingApproach, FindSlipSeesTwoTipsWithADeeperInsideNotACorner) {
  perception::RangeProfile p;
  p.bin_width_deg = 1.0F;
  p.bin_count = 360;
  p.closest_range_m.fill(perception::RangeProfile::kNoReturn);
  // A wall 8 m ahead across the front; a 1.6 m mouth at 6 m (tips at +-7.6 deg), inside 8 m.
  for (int b = -60; b <= 60; ++b) {
    p.closest_range_m[static_cast<std::size_t>(180 + b)] =
        static_cast<float>(8.0 / std::cos(core::deg_to_rad(b + 0.5)));
  }
  p.closest_range_m[180 - 8] = 6.05F;
  p.closest_range_m[180 + 7] = 6.05F;
  const auto s = find_slip(p, SlipFinderParams{}, 0.0);
  ASSERT_TRUE(s.has_value());
  EXPECT_NEAR(s->mouth_x_m, 6.0, 0.1);
  EXPECT_NEAR(s->mouth_y_m, 0.0, 0.1);
  EXPECT_NEAR(s->axis_body_deg, 0.0, 2.0);
  EXPECT_NEAR(s->width_m, 1.6, 0.2);
  EXPECT_NEAR(slip_pursuit_bearing_deg(*s, 1.5), 0.0, 2.0);
  // Behind the boat: outside the forward sector.
  EXPECT_FALSE(find_slip(p, SlipFinderParams{}, 180.0).has_value());
  // Without the tips it is a plain wall (a corner has no tips either): no slip.
  p.closest_range_m[180 - 8] = 8.1F;
  p.closest_range_m[180 + 7] = 8.1F;
  EXPECT_FALSE(find_slip(p, SlipFinderParams{}, 0.0).has_value());
}

}  // namespace
}  // namespace coxswain::guidance

namespace coxswain::guidance {
namespace {

// Closest return per 1-degree bin of straight walls (body frame: x forward, y starboard).
struct Wall2d {
  double x0, y0, x1, y1;
};
perception::RangeProfile cast(const std::vector<Wall2d>& walls) {
  perception::RangeProfile p;
  p.bin_width_deg = 1.0F;
  p.bin_count = 360;
  p.closest_range_m.fill(perception::RangeProfile::kNoReturn);
  for (std::size_t i = 0; i < 360; ++i) {
    // Two rays per bin, as a 0.5-degree lidar would give.
    for (const double off : {0.25, 0.75}) {
      const double b = core::deg_to_rad(-180.0 + static_cast<double>(i) + off);
      const double dx = std::cos(b);
      const double dy = std::sin(b);
      for (const Wall2d& w : walls) {
        const double ex = w.x1 - w.x0;
        const double ey = w.y1 - w.y0;
        const double den = dx * ey - dy * ex;
        if (std::abs(den) < 1e-12) continue;
        const double t = (w.x0 * ey - w.y0 * ex) / den;  // along the ray
        const double u = (w.x0 * dy - w.y0 * dx) / den;  // along the wall
        if (t <= 0.05 || u < 0.0 || u > 1.0 || t > 12.0) continue;
        p.closest_range_m[i] = std::min(p.closest_range_m[i], static_cast<float>(t));
      }
    }
  }
  return p;
}

// Three docks side by side, 1.6 m slips 2 m deep, 3.1 m apart, their back on a long wall, seen
// from `ahead_m` in front of the middle slip's mouth and `offset_m` to its starboard.
std::vector<Wall2d> three_docks(double ahead_m, double offset_m) {
  std::vector<Wall2d> walls;
  const double back = ahead_m + 2.0;
  walls.push_back({back, -12.0, back, 12.0});
  for (int k = -1; k <= 1; ++k) {
    const double c = 3.1 * k - offset_m;
    walls.push_back({ahead_m, c - 0.8, back, c - 0.8});
    walls.push_back({ahead_m, c + 0.8, back, c + 0.8});
  }
  return walls;
}

TEST(DockingApproach, FindSlipSeesFingersFromInFrontAndPicksTheMarkedOne) {
  // Fingers seen along their faces (no range jump at a tip) are still found; of the five gaps
  // (three slips and the two between the docks, all alike to the lidar) the camera's marker
  // bearing names the slip, the map's expected mouth names it too.
  const auto p = cast(three_docks(6.0, 0.4));
  SlipFinderParams params;
  params.max_axis_deg = 20.0;
  const auto any = find_slip(p, params, 0.0);
  ASSERT_TRUE(any.has_value());
  EXPECT_NEAR(any->width_m, 1.6, 0.25);
  EXPECT_NEAR(any->axis_body_deg, 0.0, 10.0);
  // The middle slip's marker, 2 m inside its mouth: at atan2(-0.4, 8).
  const double marker_deg = core::rad_to_deg(std::atan2(-0.4, 8.0));
  const auto s = find_slip_toward(p, params, 0.0, marker_deg, 2.0, 6.0);
  ASSERT_TRUE(s.has_value());
  EXPECT_NEAR(s->mouth_x_m, 6.0, 0.3);
  EXPECT_NEAR(s->mouth_y_m, -0.4, 0.2);
  EXPECT_NEAR(s->width_m, 1.6, 0.25);
  // The port slip's marker (3.1 m over) picks the port slip.
  const double left_deg = core::rad_to_deg(std::atan2(-3.1 - 0.4, 8.0));
  const auto l = find_slip_toward(p, params, 0.0, left_deg, 2.0, 6.0);
  ASSERT_TRUE(l.has_value());
  EXPECT_NEAR(l->mouth_y_m, -3.5, 0.2);
  // The gap between two docks has a slip's shape to the lidar: only the bearing tells them apart.
  const double between_deg = core::rad_to_deg(std::atan2(-1.55 - 0.4, 8.0));
  const auto g = find_slip_toward(p, params, 0.0, between_deg, 2.0, 2.0);
  ASSERT_TRUE(g.has_value());
  EXPECT_NEAR(g->mouth_y_m, -1.95, 0.2);
  EXPECT_FALSE(find_slip_toward(p, params, 0.0, between_deg + 7.0, 2.0, 2.0).has_value());
  const auto near = find_slip_near(p, params, 0.0, {6.0, -0.2}, 1.0);
  ASSERT_TRUE(near.has_value());
  EXPECT_NEAR(near->mouth_y_m, -0.4, 0.2);
  EXPECT_FALSE(find_slip_near(p, params, 0.0, {6.0, 0.8}, 0.3).has_value());
}

TEST(DockingApproach, AGapBetweenTwoBuoysWithOpenWaterBehindIsNoSlip) {
  perception::RangeProfile p;
  p.bin_width_deg = 1.0F;
  p.bin_count = 360;
  p.closest_range_m.fill(perception::RangeProfile::kNoReturn);
  // Two buoys 1.8 m apart, 5 m ahead, nothing behind them within range.
  for (int b = -14; b <= -8; ++b) p.closest_range_m[static_cast<std::size_t>(180 + b)] = 5.1F;
  for (int b = 8; b <= 14; ++b) p.closest_range_m[static_cast<std::size_t>(180 + b)] = 5.1F;
  p.closest_range_m[180 - 11] = 5.0F;
  p.closest_range_m[180 + 11] = 5.0F;
  EXPECT_FALSE(find_slip(p, SlipFinderParams{}, 0.0).has_value());
  // A wall 3 m behind them closes the gap: now it has the shape of a slip.
  for (int b = -7; b <= 7; ++b) {
    p.closest_range_m[static_cast<std::size_t>(180 + b)] =
        static_cast<float>(8.0 / std::cos(core::deg_to_rad(b + 0.5)));
  }
  EXPECT_TRUE(find_slip(p, SlipFinderParams{}, 0.0).has_value());
}

TEST(DockingApproach, FingersAlongsideOnlyWhenTheBowIsBetweenTwoFingers) {
  // In a 1.6 m slip 2 m deep (the boat's bow, where the lidar is, 1.5 m in and 0.2 m to
  // starboard of its axis): a finger along each side.
  const auto slip_from = [](double bow_in_m, double starboard_m) {
    const double mouth = -bow_in_m;
    return std::vector<Wall2d>{{mouth, -0.8 - starboard_m, mouth + 2.0, -0.8 - starboard_m},
                               {mouth, 0.8 - starboard_m, mouth + 2.0, 0.8 - starboard_m},
                               {mouth + 2.0, -12.0, mouth + 2.0, 12.0}};
  };
  const FingersAlongside in = fingers_alongside(cast(slip_from(1.5, 0.2)), 1.2, 0.6);
  ASSERT_TRUE(in.both());
  EXPECT_NEAR(in.port_m, 1.0, 0.05);
  EXPECT_NEAR(in.starboard_m, 0.6, 0.05);
  // Only the bow in the mouth (0.3 m): the fingers do not reach half the hull aft.
  EXPECT_FALSE(fingers_alongside(cast(slip_from(0.3, 0.0)), 1.2, 0.6).both());
  // Beside the slip, against a finger's outer side: a finger to port only.
  const FingersAlongside beside = fingers_alongside(cast(slip_from(1.5, 1.3)), 1.2, 0.6);
  EXPECT_FALSE(beside.both());
  EXPECT_GT(beside.port_m, 0.0);
  EXPECT_LT(beside.starboard_m, 0.0);
  // Nosed into a corner, its apex 0.5 m ahead: a wall within reach on each side, but at 45
  // degrees to the hull, not along it.
  const std::vector<Wall2d> corner{{0.5, 0.0, -3.0, -3.5}, {0.5, 0.0, -3.0, 3.5}};
  EXPECT_FALSE(fingers_alongside(cast(corner), 1.2, 0.6).both());
  // Fingers farther than the limit are not alongside.
  EXPECT_FALSE(fingers_alongside(cast(slip_from(1.5, 0.2)), 0.9, 0.6).both());
  // Stopped with the slip's back 0.2 m ahead: its returns lie in the band abeam of the lidar
  // too, nearer the centre line than the fingers; ahead of the bow (0.1 m) they are no finger.
  EXPECT_FALSE(fingers_alongside(cast(slip_from(1.8, 0.0)), 1.2, 0.6).both());
  const FingersAlongside at_back = fingers_alongside(cast(slip_from(1.8, 0.0)), 1.2, 0.6, 0.1);
  ASSERT_TRUE(at_back.both());
  EXPECT_NEAR(at_back.port_m, 0.8, 0.05);
  EXPECT_NEAR(at_back.starboard_m, 0.8, 0.05);
}

}  // namespace
}  // namespace coxswain::guidance
