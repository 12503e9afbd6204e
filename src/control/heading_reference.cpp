// SPDX-License-Identifier: Apache-2.0
#include "coxswain/control/heading_reference.hpp"

#include "coxswain/core/angles.hpp"

namespace coxswain::control {

double true_from_magnetic_deg(double magnetic_deg, double declination_deg) {
  return core::wrap_deg(magnetic_deg + declination_deg);
}

double true_from_course_deg(double course_deg, double course_zero_true_deg) {
  return core::wrap_deg(course_deg + course_zero_true_deg);
}

double course_from_true_deg(double true_deg, double course_zero_true_deg) {
  return core::angle_diff_deg(true_deg, course_zero_true_deg);
}

}  // namespace coxswain::control
