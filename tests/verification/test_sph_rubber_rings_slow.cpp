// Colliding rubber rings at 10 particles across each ring's wall (twice the resolution of
// test_sph_rubber_rings.cpp, whose header explains the checks and bounds). Gray et al. 2001 and
// PySPH's rings.py use 20 across (dx = 0.0005 m).
#include <gtest/gtest.h>

#include "spall/core/log.hpp"
#include "support/rings_run.hpp"

using namespace spall;

namespace {

test_support::RubberRings fine(bool artificial_stress) {
  test_support::RubberRings r;
  r.spacing = 0.001;
  r.artificial_stress = artificial_stress;
  return r;
}

}  // namespace

TEST(SphRubberRingsSlow, WithArtificialStressTheyBounceApartWhole) {
  log::set_quiet(true);
  const auto rings = fine(true);
  test_support::expect_bounce_apart_whole(rings, test_support::run_rubber_rings(rings));
}

TEST(SphRubberRingsSlow, WithoutArtificialStressTheyClumpAndFuse) {
  log::set_quiet(true);
  const auto rings = fine(false);
  test_support::expect_clump_and_fuse(rings, test_support::run_rubber_rings(rings));
}
