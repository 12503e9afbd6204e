// SPDX-License-Identifier: Apache-2.0
#include "coxswain/control/mapping_control.hpp"

#include <gtest/gtest.h>

namespace coxswain::control {
namespace {

TEST(MappingControl, DocumentFormula) {
  // x_map = (x - in_min) / (in_max - in_min) * (out_max - out_min) + out_min; x_ctl = alpha x_map.
  MappingControlParams p;
  p.in_min_deg = -60.0;
  p.in_max_deg = 60.0;
  p.alpha = 0.8;
  ASSERT_FALSE(p.validate().has_value());
  const MappingControl m(p);
  EXPECT_DOUBLE_EQ(m.command(0.0), 0.0);
  EXPECT_NEAR(m.command(30.0), 0.5 * 0.8, 1e-12);
  EXPECT_NEAR(m.command(-30.0), -0.5 * 0.8, 1e-12);
  EXPECT_NEAR(m.command(60.0), 0.8, 1e-12);
  EXPECT_NEAR(m.command(170.0), 0.8, 1e-12);  // input clamped to the range first
}

TEST(MappingControl, AlphaAboveOneIsClampedToTheOutputLimit) {
  MappingControlParams p;
  p.alpha = 3.0;
  const MappingControl m(p);
  EXPECT_DOUBLE_EQ(m.command(80.0), 1.0);
  EXPECT_DOUBLE_EQ(m.command(-80.0), -1.0);
  EXPECT_NEAR(m.command(15.0), 3.0 * 15.0 / 90.0, 1e-12);
}

TEST(MappingControl, Validate) {
  MappingControlParams p;
  p.in_max_deg = p.in_min_deg;
  EXPECT_TRUE(p.validate().has_value());
  p = {};
  p.alpha = 0.0;
  EXPECT_TRUE(p.validate().has_value());
}

}  // namespace
}  // namespace coxswain::control
