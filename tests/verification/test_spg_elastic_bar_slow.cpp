// Free-free elastic SPG bar, fine: 80 x 8 x 8 elements (6561 particles), against the closed-form
// first longitudinal mode (support/spg_bar.hpp): quarter period L / (2c) within 5 % (issue 5), and
// the energy balance over one period at TSSFAC 0.9 within 1 %.
#include <gtest/gtest.h>

#include "spall/core/log.hpp"
#include "support/spg_bar.hpp"

using namespace spall;

TEST(SpgElasticBarSlow, FineBarQuarterPeriodAndEnergy) {
  log::set_quiet(true);
  auto b = test_support::spg_bar(80);
  b.jitter = 0.15;
  const Real quarter = test_support::bar_quarter_period(b);
  const auto run = test_support::run_spg_bar(b, 4 * quarter, 0.9);
  const Real error = (test_support::first_minimum(run.time, run.kinetic) - quarter) / quarter;
  const auto& e = run.summary.energies;
  std::printf("quarter period error %+.3f %%, energy ratio after one period %.6f, %lld steps\n", 100 * error,
              e.ratio(), run.summary.steps);
  EXPECT_LT(std::abs(error), 0.05);
  EXPECT_NEAR(e.ratio(), 1.0, 0.01);
}
