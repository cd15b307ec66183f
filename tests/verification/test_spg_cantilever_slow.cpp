// SPG cantilever under its own weight (support/spg_cantilever.hpp), fine: 40 x 2 x 8 elements (1107
// particles). Tip deflection within 5 % of beam theory with the shear term (issue 5); the
// remaining stiffening is mostly the trapezoidal quadrature of the section (1 + 2 / 8^2 = 1.03).
#include <gtest/gtest.h>

#include "spall/core/log.hpp"
#include "support/spg_cantilever.hpp"

using namespace spall;

TEST(SpgCantileverSlow, TipDeflectionWithinFivePercentOfBeamTheory) {
  log::set_quiet(true);
  test_support::Cantilever c;
  c.along = 40;
  c.through = 8;
  const auto r = test_support::run_cantilever(c);
  const Real expected = r.bending + r.shear;
  const Real error = (r.tip_deflection - expected) / expected;
  std::printf("tip deflection %.4e m, beam theory %.4e m (bending %.4e, shear %.4e): %+.2f %%, %lld steps\n",
              r.tip_deflection, expected, r.bending, r.shear, 100 * error, r.steps);
  EXPECT_LT(std::abs(error), 0.05);
}
