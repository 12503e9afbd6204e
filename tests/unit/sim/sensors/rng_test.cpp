// SPDX-License-Identifier: Apache-2.0
#include "sim/rng/rng.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace coxswain::sim::sensors {
namespace {

TEST(Rng, KnownSequenceForASeed) {
  // splitmix64 reference values for seed 0 (Vigna's splitmix64.c).
  Rng r(0);
  EXPECT_EQ(r.next_u64(), 0xE220A8397B1DCDAFULL);
  EXPECT_EQ(r.next_u64(), 0x6E789E6AA1B965F4ULL);
}

TEST(Rng, UniformAndNormalMoments) {
  Rng r(42);
  constexpr int kN = 200000;
  double su = 0.0;
  double sn = 0.0;
  double sn2 = 0.0;
  for (int i = 0; i < kN; ++i) {
    const double u = r.uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    su += u;
    const double n = r.normal(2.0);
    sn += n;
    sn2 += n * n;
  }
  EXPECT_NEAR(su / kN, 0.5, 0.005);
  EXPECT_NEAR(sn / kN, 0.0, 0.02);
  EXPECT_NEAR(std::sqrt(sn2 / kN), 2.0, 0.02);
}

TEST(Rng, DerivedSeedsDiffer) {
  EXPECT_NE(derive_seed(1, 1), derive_seed(1, 2));
  EXPECT_NE(derive_seed(1, 1), derive_seed(2, 1));
  EXPECT_EQ(derive_seed(5, 3), derive_seed(5, 3));
}

}  // namespace
}  // namespace coxswain::sim::sensors
