// The colliding rubber rings (tests/support/rubber_rings.hpp) at 10 particles across the wall with
// the gradient correction (FORM 1) and the artificial stress, at the default TSSFAC 0.9: under
// LS-DYNA's step h / (c + |v|) the run stops as a runaway (at t = 0.114 ms; docs/VALIDATION.md),
// because the corrected operator's highest frequency reaches 2 / dt (docs/THEORY.md §3). Under
// Spall's correction-aware step it runs to the end with total linear momentum conserved to
// round-off and kinetic + internal + dissipated energy within 1 % of the initial at every step
// (the bounds of test_sph_rubber_rings.cpp; measured 0.22 %). The coarse variant in the default
// set is test_sph_stable_step.cpp's disordered plate.
#include <gtest/gtest.h>

#include "spall/core/error.hpp"
#include "spall/core/log.hpp"
#include "support/rings_run.hpp"

using namespace spall;

namespace {

test_support::RubberRings corrected_rings() {
  test_support::RubberRings r;
  r.spacing = 0.001;
  r.form = 1;
  return r;
}

}  // namespace

TEST(SphStableStepSlow, CorrectedRingsConserveEnergyAtTheDefaultFactor) {
  log::set_quiet(true);
  const auto run = test_support::run_rubber_rings(corrected_rings());
  test_support::expect_conservation(run);
}

TEST(SphStableStepSlow, CorrectedRingsRunAwayUnderTheCflStep) {
  log::set_quiet(true);
  model::Model m = test_support::rubber_rings_model(corrected_rings());
  m.sph_timestep = model::SphTimestep{1, {}};
  solver::Problem problem = solver::build_problem(m);
  EXPECT_THROW(solver::run(problem, {}), InstabilityError);
}
