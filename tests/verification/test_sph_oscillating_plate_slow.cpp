// Oscillating cantilever plate at finer resolutions (tests/support/oscillating_plate.hpp; the
// coarse test is test_sph_oscillating_plate.cpp, which explains the coarse-resolution error).
// - Linear regime (V_f = 1e-4, no artificial stress) at 8, 10 and 12 particles across: the
//   Richardson extrapolation of the periods is within 2 % of the thin-plate period T = 0.2540 s.
//   2 %: thin-plate theory is 0.5 % short of plane-strain elasticity at L/H = 10 (converged
//   biquadratic finite elements give 0.2552 s), and the extrapolation from 4, 5, 6 and from 8,
//   10, 12 particles across differ by 1.5 % (docs/VALIDATION.md).
// - Gray et al.'s amplitude, V_f = 0.01, at 15 particles across. Without artificial stress the
//   tensile instability softens the plate: twice its first half period is more than 20 % above
//   the thin-plate period. With Monaghan's artificial stress (epsilon 0.3, n 4) the plate swings
//   steadily: two successive periods agree within 1 %, and their mean is within 8 % of the
//   thin-plate period: the 5 % of issue 3 plus 3 % for the artificial stress, which softens the
//   tensile side of the plate by an amount refinement does not remove (its mean period minus the
//   linear-regime period without it: +2.2 % at 15 across, +3.4 % at 20; docs/VALIDATION.md).
#include <gtest/gtest.h>

#include <cmath>

#include "spall/core/log.hpp"
#include "support/oscillating_plate.hpp"

using namespace spall;

namespace {

Real period(const test_support::OscillatingPlate& p) {
  const auto crossings = test_support::tip_zero_crossings(p);
  EXPECT_GE(crossings.size(), 2u) << p.layers << " particles across";
  const Real T = crossings.size() >= 2 ? crossings[1] : 0;
  std::printf(
      "plate, %d particles across, V_f %g, artificial stress %s: period %.5f s (%+.2f %%)\n",
      p.layers, p.velocity_factor, p.artificial_stress ? "on" : "off", T,
      100 * (T / test_support::thin_plate_period() - 1));
  return T;
}

}  // namespace

TEST(SphOscillatingPlateSlow, LinearRegimeExtrapolatesToThinPlateTheory) {
  log::set_quiet(true);
  const Real reference = test_support::thin_plate_period();
  const int layers[3] = {8, 10, 12};
  Real T[3], d[3];
  for (int i = 0; i < 3; ++i) {
    test_support::OscillatingPlate p;
    p.layers = layers[i];
    p.velocity_factor = 1e-4;
    p.end_time = 1.15 * reference;
    T[i] = period(p);
    d[i] = 1.0 / layers[i];
  }
  ASSERT_GT(T[0], T[1]);
  ASSERT_GT(T[1], T[2]);
  // Richardson through T(d) = T_inf + C d^p (see test_sph_oscillating_plate.cpp).
  const Real ratio = (T[0] - T[1]) / (T[1] - T[2]);
  const auto mismatch = [&](Real p) {
    return (std::pow(d[0], p) - std::pow(d[1], p)) / (std::pow(d[1], p) - std::pow(d[2], p)) -
           ratio;
  };
  Real low = 0.1, high = 6;
  for (int i = 0; i < 100; ++i) {
    const Real mid = 0.5 * (low + high);
    (mismatch(mid) < 0) == (mismatch(low) < 0) ? low = mid : high = mid;
  }
  const Real order = 0.5 * (low + high);
  const Real extrapolated = T[2] - (T[1] - T[2]) / (std::pow(d[1], order) - std::pow(d[2], order)) *
                                       std::pow(d[2], order);
  std::printf("observed order %.2f, extrapolated period %.5f s (%+.2f %%)\n", order, extrapolated,
              100 * (extrapolated / reference - 1));
  EXPECT_GT(order, 1.0);
  EXPECT_LT(order, 3.0);
  EXPECT_NEAR(extrapolated / reference, 1.0, 0.02);
}

// Issue 3's criterion at a single resolution: period within 5 % of the thin-plate period. The
// boundary error falls below it between 12 particles across (+5.1 %) and 16 (measured +3.36 %).
TEST(SphOscillatingPlateSlow, SixteenAcrossWithinFivePercentOfThinPlateTheory) {
  log::set_quiet(true);
  test_support::OscillatingPlate p;
  p.layers = 16;
  p.velocity_factor = 1e-4;
  p.end_time = 1.1 * test_support::thin_plate_period();
  EXPECT_NEAR(period(p) / test_support::thin_plate_period(), 1.0, 0.05);
}

TEST(SphOscillatingPlateSlow, ArtificialStressRemovesTheTensileInstability) {
  log::set_quiet(true);
  const Real reference = test_support::thin_plate_period();
  test_support::OscillatingPlate p;
  p.layers = 15;
  p.velocity_factor = 0.01;
  // Without: the first half period alone shows it.
  p.end_time = 0.9 * reference;
  const auto unstable = test_support::tip_zero_crossings(p);
  ASSERT_GE(unstable.size(), 1u);
  const Real unstable_period = 2 * unstable[0];
  // With: two full periods, from the first down-crossing to the third and from the first
  // up-crossing to the second.
  p.artificial_stress = true;
  p.end_time = 2.2 * reference;
  const auto c = test_support::tip_zero_crossings(p);
  ASSERT_GE(c.size(), 4u);
  const Real first = c[2] - c[0], second = c[3] - c[1];
  const Real mean = 0.5 * (first + second);
  std::printf(
      "plate, 15 across, V_f 0.01: without artificial stress twice the first half period "
      "%.5f s (%+.2f %%); with it periods %.5f and %.5f s, mean %+.2f %%\n",
      unstable_period, 100 * (unstable_period / reference - 1), first, second,
      100 * (mean / reference - 1));
  EXPECT_GT(unstable_period / reference - 1, 0.2);
  EXPECT_NEAR(first / second, 1.0, 0.01);
  EXPECT_NEAR(mean / reference, 1.0, 0.08);
}
