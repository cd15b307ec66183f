// The SPH fluid's Tait / Murnaghan water, p = K0 [(rho / rho0)^gamma - 1] with K0 = rho0 c0^2 /
// gamma (Monaghan 1994; LS-DYNA *EOS_MURNAGHAN), against its closed form: zero at rho0, the
// acoustic limit dp/drho = c0^2, and c^2 = dp/drho at any density; the MAT_NULL pressure cutoff.
#include <gtest/gtest.h>

#include <cmath>

#include "spall/sph/fluid.hpp"

using spall::Real;

namespace {
spall::sph::FluidMaterial water() { return spall::sph::FluidMaterial::tait(1000, 20, 7, 0); }
}  // namespace

TEST(TaitEquationOfState, ZeroAtRestDensity) { EXPECT_EQ(water().pressure(1000), 0.0); }

TEST(TaitEquationOfState, ClosedFormAtOnePercentCompression) {
  // K0 = 1000 * 20^2 / 7 = 57142.857...; 1.01^7 - 1 = 0.0721353521...
  const Real expected = 1000.0 * 400.0 / 7.0 * (std::pow(1.01, 7) - 1);
  EXPECT_NEAR(water().pressure(1010), expected, 1e-9 * expected);
  EXPECT_NEAR(expected, 4122.02, 0.01);
}

TEST(TaitEquationOfState, AcousticLimitIsRho0C0Squared) {
  const auto m = water();
  const Real drho = 1e-4;
  // p ~ c0^2 (rho - rho0) for small compressions; the next term is relative (gamma - 1) / 2 drho/rho0.
  EXPECT_NEAR(m.pressure(1000 + drho) / drho, 400, 1e-6 * 400);
  EXPECT_NEAR(m.reference_sound_speed(), 20, 1e-12);
}

TEST(TaitEquationOfState, SoundSpeedSquaredIsDpDrho) {
  const auto m = water();
  for (Real rho : {980.0, 1000.0, 1030.0}) {
    const Real e = 1e-3;
    const Real dp_drho = (m.pressure(rho + e) - m.pressure(rho - e)) / (2 * e);
    const Real c = m.sound_speed_at(rho);
    EXPECT_NEAR(c * c, dp_drho, 1e-6 * dp_drho) << rho;
  }
}

TEST(TaitEquationOfState, PressureCutoffBoundsTension) {
  auto m = water();
  EXPECT_LT(m.pressure(990), -100.0);  // without a cutoff the liquid takes tension
  m.pressure_cutoff = -100;
  EXPECT_EQ(m.pressure(990), -100.0);
  EXPECT_GT(m.pressure(1010), 0.0);
}
