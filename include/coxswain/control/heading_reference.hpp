// SPDX-License-Identifier: Apache-2.0
#pragma once
// Heading references. Every guidance and control engine takes TRUE headings in the navigation
// convention (0 = true north, clockwise positive, (-180, 180]); msg::ImuSample::heading_deg already
// arrives that way. These helpers exist for the places that hold other references: a raw magnetic
// heading (the 2022 code compared it with true GPS bearings and was off by the declination), and
// the 2026 plan's course frame (0 = the start direction).

namespace coxswain::control {

/// True heading from a magnetic one. declination_deg: east positive (true = magnetic + decl.);
/// e.g. about -8.5 in Korea (west).
[[nodiscard]] double true_from_magnetic_deg(double magnetic_deg, double declination_deg);

/// True heading of a course-frame angle whose 0 points at `course_zero_true_deg`.
[[nodiscard]] double true_from_course_deg(double course_deg, double course_zero_true_deg);

/// Course-frame angle of a true heading (inverse of true_from_course_deg).
[[nodiscard]] double course_from_true_deg(double true_deg, double course_zero_true_deg);

}  // namespace coxswain::control
