// A cantilever of solid finite elements under its own weight, brought to rest by damping
// (support/spg_cantilever.hpp), against beam theory with the shear term (Timoshenko & Gere;
// Cowper's kappa): 20 x 2 x 4 elements (4 through the depth). Issue 32: ELFORM 2 within 5 %;
// ELFORM 1 with stiffness hourglass control (IHQ 4, QM 0.1) within 10 %, its hourglass energy
// below 10 % of the internal energy.
#include <gtest/gtest.h>

#include "spall/core/log.hpp"
#include "support/spg_cantilever.hpp"

using namespace spall;

namespace {

test_support::CantileverResult run(int elform, int ihq) {
  log::set_quiet(true);
  test_support::Cantilever c;
  c.fem = test_support::FiniteElements{elform, {}};
  if (ihq > 0) {
    model::Hourglass hourglass;
    hourglass.ihq = ihq;
    c.fem->hourglass = hourglass;
  }
  const auto r = test_support::run_cantilever(c);
  const Real theory = r.bending + r.shear;
  std::printf("ELFORM %d IHQ %d: tip deflection %.6e m, beam theory %.6e m (error %+.2f %%), tip speed %.2e m/s, "
              "hourglass / internal energy %.4f, %lld steps\n", elform, ihq, r.tip_deflection, theory,
              100 * (r.tip_deflection - theory) / theory, r.tip_speed, r.hourglass_energy / r.internal_energy, r.steps);
  return r;
}

}  // namespace

TEST(FemCantilever, SelectiveReducedHexahedraMatchBeamTheory) {
  const auto r = run(2, 0);
  EXPECT_NEAR(r.tip_deflection, r.bending + r.shear, 0.05 * (r.bending + r.shear));
}

TEST(FemCantilever, OnePointHexahedraWithStiffnessHourglassControlMatchBeamTheory) {
  const auto r = run(1, 4);
  EXPECT_NEAR(r.tip_deflection, r.bending + r.shear, 0.10 * (r.bending + r.shear));
  EXPECT_LT(std::abs(r.hourglass_energy), 0.10 * r.internal_energy);
}
