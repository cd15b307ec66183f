// spall::cube_root (core/cube_root.hpp) against the cube root in extended precision (cbrtl,
// 64-bit mantissa) rounded to double: within one unit in the last place over 2^-60 .. 2^60 and
// the range of the smoothing length's compressions; exact on perfect cubes; the library's answer
// outside the range it computes itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "spall/core/cube_root.hpp"

namespace {

// |a - b| in units of the last place of b.
double ulps(double a, double b) {
  return std::abs(a - b) / (std::nextafter(b, std::numeric_limits<double>::infinity()) - b);
}

double rounded_reference(double x) { return static_cast<double>(cbrtl(static_cast<long double>(x))); }

}  // namespace

TEST(cube_root, WithinOneUlpOfTheRoundedRoot) {
  std::mt19937_64 rng(20261126);
  std::uniform_real_distribution<double> exponent(-60, 60), compression(0.1, 10);
  double worst = 0;
  for (int i = 0; i < 200000; ++i) {
    const double x = std::exp2(exponent(rng));
    worst = std::max(worst, ulps(spall::cube_root(x), rounded_reference(x)));
    const double c = compression(rng);
    worst = std::max(worst, ulps(spall::cube_root(c), rounded_reference(c)));
  }
  EXPECT_LE(worst, 1.0);
}

TEST(cube_root, ExactOnPerfectCubes) {
  for (int k = 1; k <= 1000; ++k) {
    const double root = k * 0.125;  // root^3 is exact in double
    ASSERT_EQ(spall::cube_root(root * root * root), root) << root;
  }
  EXPECT_EQ(spall::cube_root(1.0), 1.0);
  EXPECT_EQ(spall::cube_root(0x1p-999), 0x1p-333);
}

TEST(cube_root, OutsideItsRangeTheLibraryAnswers) {
  for (double x : {0.0, -8.0, 1e-310, 0x1p1010, std::numeric_limits<double>::infinity()})
    EXPECT_EQ(spall::cube_root(x), std::cbrt(x)) << x;
  EXPECT_TRUE(std::isnan(spall::cube_root(std::numeric_limits<double>::quiet_NaN())));
}
