// SPDX-License-Identifier: Apache-2.0
#pragma once
// Obstacle segments for the avoidance tests, in the body frame.
#include "coxswain/perception/obstacles.hpp"

namespace coxswain::test {

/// A lidar segment from (f0, s0) to (f1, s1): forward and starboard metres.
inline perception::ObstacleSegment segment(double f0, double s0, double f1, double s1) {
  perception::ObstacleSegment s;
  s.begin = {f0, s0};
  s.end = {f1, s1};
  return s;
}

}  // namespace coxswain::test
