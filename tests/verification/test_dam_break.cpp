// Dam break, coarse (plane strain, 16 particles across the column, about a second): the surge
// front against the experiments of Koshizuka & Oka 1996 and Martin & Moyce 1952 (n^2 = 2,
// a = 2.25 in), tolerance 5 % (issue 3). The two experiments differ by up to 7 % (at T = 2.72),
// so the front is compared with the band between them where both have data (T >= 0.83), with
// Koshizuka & Oka alone before. T = 0.381 is excluded: it is the initial transient, where the
// simulated toe still starts from a resolved corner at rest (the front lags by 7 % there).
// docs/VALIDATION.md gives the numbers and the finer runs.
#include <gtest/gtest.h>

#include "spall/core/log.hpp"
#include "support/dam_break.hpp"

using namespace spall;

// With every kernel SPHKERN offers (0 cubic spline, 1 quintic spline, 4 Wendland C2).
class DamBreak : public ::testing::TestWithParam<kernels::KernelKind> {};

TEST_P(DamBreak, SurgeFrontMatchesExperimentsPlaneStrain) {
  log::set_quiet(true);
  test_support::DamBreak d;
  d.dimension = 2;
  d.particles_across = 16;
  d.kernel = GetParam();
  test_support::expect_surge_front_within_experiments(test_support::run_dam_break(d));
}

INSTANTIATE_TEST_SUITE_P(Kernels, DamBreak,
                         ::testing::Values(kernels::KernelKind::cubic_spline, kernels::KernelKind::quintic_spline,
                                           kernels::KernelKind::wendland_c2));
