// Dam break in 3D (about half a minute on one core): the column L x L x 2L in a tank L deep
// between side walls, 16 particles across, about 33 000 particles with the walls; the surge front
// against the band between Koshizuka & Oka 1996 and Martin & Moyce 1952 (n^2 = 2, a = 2.25 in),
// tolerance 5 %, T = 0.381 excluded as the initial transient (see test_dam_break.cpp).
#include <gtest/gtest.h>

#include "spall/core/log.hpp"
#include "support/dam_break.hpp"

using namespace spall;

TEST(DamBreakSlow, SurgeFrontMatchesExperiments3D) {
  log::set_quiet(true);
  test_support::DamBreak d;
  d.dimension = 3;
  d.particles_across = 16;
  test_support::expect_surge_front_within_experiments(test_support::run_dam_break(d));
}
