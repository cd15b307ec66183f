// Taylor bar, OFHC copper, Johnson-Cook: Wilkins & Guinan 1973 test 1 (L0 23.47 mm, D0 7.62 mm,
// 210 m/s). Measured: final length over initial 0.630 and foot radius over initial 2.204
// (reference/validation.md §1(b)). Tolerances from issue 3: 5 % on the length, 10 % on the radius.
// Fine (D0/20, ~19 000 particles; label slow); test_sph_taylor_bar.cpp is the coarse variant.
#include <gtest/gtest.h>

#include "spall/core/log.hpp"
#include "support/taylor_bar.hpp"

using namespace spall;

TEST(SphTaylorBar, FinalShapeMatchesWilkinsGuinanTest1AtTwiceTheResolution) {
  log::set_quiet(true);
  test_support::TaylorBar bar;
  bar.particles_across = 20;
  const auto shape = test_support::run_taylor_bar(bar);
  EXPECT_NEAR(shape.length_ratio, 0.630, 0.05 * 0.630);
  EXPECT_NEAR(shape.radius_ratio, 2.204, 0.10 * 2.204);
}
