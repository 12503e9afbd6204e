// SPDX-License-Identifier: Apache-2.0
#include "coxswain/control/heading_reference.hpp"

#include <gtest/gtest.h>

#include "coxswain/core/angles.hpp"
#include "coxswain/core/frames.hpp"

namespace coxswain::control {
namespace {

// Korea's declination is about -8.5 deg (west). A boat pointing exactly at its waypoint (true
// bearing 45) reads 53.5 on the compass. Comparing that magnetic reading with the true GPS bearing
// (the defect) asks for an 8.5 deg turn to port that is not needed; converting first gives zero.
TEST(HeadingReference, DeclinationOffsetHeadingIsCorrected) {
  constexpr double kDeclinationDeg = -8.5;
  const core::NavPoint boat{0.0, 0.0};
  const core::NavPoint waypoint{50.0, 50.0};
  const double bearing = core::bearing_deg(boat, waypoint);
  ASSERT_NEAR(bearing, 45.0, 1e-9);
  const double compass_magnetic = 53.5;

  const double naive_error = core::angle_diff_deg(bearing, compass_magnetic);
  EXPECT_NEAR(naive_error, -8.5, 1e-9);

  const double heading_true = true_from_magnetic_deg(compass_magnetic, kDeclinationDeg);
  EXPECT_NEAR(core::angle_diff_deg(bearing, heading_true), 0.0, 1e-9);
}

TEST(HeadingReference, WrapsAcrossSouth) {
  EXPECT_NEAR(true_from_magnetic_deg(175.0, 10.0), -175.0, 1e-9);
  EXPECT_NEAR(true_from_magnetic_deg(-175.0, -10.0), 175.0, 1e-9);
}

TEST(HeadingReference, CourseFrameRoundTrip) {
  // 2026 plan: 0 deg = the start direction, here true 120.
  EXPECT_NEAR(true_from_course_deg(90.0, 120.0), -150.0, 1e-9);
  for (double c = -179.0; c <= 180.0; c += 7.0) {
    EXPECT_NEAR(course_from_true_deg(true_from_course_deg(c, 120.0), 120.0), c, 1e-9);
  }
}

}  // namespace
}  // namespace coxswain::control
