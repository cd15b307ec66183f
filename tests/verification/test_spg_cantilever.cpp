// SPG cantilever under its own weight, brought to rest by *DAMPING_GLOBAL (support/spg_cantilever.hpp),
// coarse: 20 x 2 x 4 elements. With four particle layers through the thickness, nodal integration
// integrates the section by the trapezoidal rule, which stiffens bending by 1 + 2 / n^2 = 1.125
// (the reason LS-DYNA's MSFAC weights surface particles); the tip deflection is compared with beam
// theory (shear term included) using that second moment, within 5 %. The fine beam against plain
// beam theory is in test_spg_cantilever_slow.cpp.
#include <gtest/gtest.h>

#include "spall/core/log.hpp"
#include "support/spg_cantilever.hpp"

using namespace spall;

TEST(SpgCantilever, CoarseTipDeflectionMatchesBeamTheoryWithItsSectionQuadrature) {
  log::set_quiet(true);
  const test_support::Cantilever c;
  const auto r = test_support::run_cantilever(c);
  const Real expected = r.bending / r.trapezoid_inertia_ratio + r.shear;
  const Real error = (r.tip_deflection - expected) / expected;
  std::printf("tip deflection %.4e m, beam theory %.4e m (bending %.4e with I x %.3f, shear %.4e): %+.2f %% "
              "(plain beam theory %+.2f %%), %lld steps, tip speed %.2e m/s\n",
              r.tip_deflection, expected, r.bending, r.trapezoid_inertia_ratio, r.shear, 100 * error,
              100 * (r.tip_deflection / (r.bending + r.shear) - 1), r.steps, r.tip_speed);
  EXPECT_LT(std::abs(error), 0.05);
  // Static: the damped beam has come to rest (the free swing would reach 2 omega_1 x deflection).
  EXPECT_LT(r.tip_speed, 0.01 * 2 * 2050 * r.tip_deflection);
}
