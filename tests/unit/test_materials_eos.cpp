// Equations of state against their formulas (LS-DYNA keyword manual: *EOS_LINEAR_POLYNOMIAL,
// *EOS_GRUNEISEN, *EOS_MURNAGHAN), values evaluated outside the library (Python, double
// precision); the sound speed against c^2 = (dp/drho)_s by central differences along an
// isentrope (de = p / rho^2 drho); MAT_NULL's cutoff and viscosity.
#include <gtest/gtest.h>

#include <cmath>

#include "spall/core/error.hpp"
#include "spall/materials/elastic.hpp"
#include "spall/materials/material.hpp"

namespace spall::materials {
namespace {

// Water as in the public bird-strike deck (C 1483 m/s, S1 1.75, GAMMA0 0.28), in SI.
const Gruneisen water{1483, 1.75, 0, 0, 0.28, 0};
// Copper-like constants (C 3940 m/s, S1 1.49, GAMMA0 2.02, A 0.47; Steinberg's table [memory]),
// with S2 = 0.1 and S3 = 0.2 made up so that every term of the formula is exercised.
const Gruneisen copper{3940, 1.49, 0.1, 0.2, 2.02, 0.47};
const LinearPolynomial polynomial{{1e5, 1.7e11, 3.1e11, 4.0e11, 0.5, 0.6, 0.7}};
// Tait water: K0 = rho0 c0^2 / GAMMA, GAMMA 7.
const Murnaghan tait{7, 1000.0 * 1483 * 1483 / 7};

TEST(materials_eos, GruneisenValues) {
  // mu = 0.1, E = 0: rho0 C^2 mu [1 + (1 - GAMMA0/2) mu] / [1 - (S1 - 1) mu]^2
  EXPECT_NEAR(evaluate_eos(water, 1000, 1100, 0).pressure, 279144234.2147553,
              1e-13 * 279144234.2147553);
  // mu = 0.2, e = 2e5 J/kg (E = rho0 e), all terms
  EXPECT_NEAR(evaluate_eos(copper, 8960, 8960 * 1.2, 2e5).pressure, 37925525710.760284,
              1e-13 * 37925525710.760284);
  // Tension, mu = -0.05: rho0 C^2 mu + (GAMMA0 + A mu) E
  EXPECT_NEAR(evaluate_eos(copper, 8960, 8960 * 0.95, 2e5).pressure, -3376844800.0,
              1e-13 * 3376844800.0);
  // A compression beyond the shock fit's range (1 - (S1 - 1) mu <= 0 at mu >= 4/3 for water).
  EXPECT_THROW(evaluate_eos(water, 1000, 2400, 0), InstabilityError);
}

TEST(materials_eos, LinearPolynomialDropsTheSquareTermsInTension) {
  // mu = 0.1: every term; mu = -0.1: C2 mu^2 and C6 mu^2 set to 0 (LS-DYNA manual).
  EXPECT_NEAR(evaluate_eos(polynomial, 2700, 2970, 1e5).pressure, 20653190000.0,
              1e-13 * 20653190000.0);
  EXPECT_NEAR(evaluate_eos(polynomial, 2700, 2430, 1e5).pressure, -17281100000.0,
              1e-13 * 17281100000.0);
}

TEST(materials_eos, MurnaghanValue) {
  // K0 ((rho / rho0)^GAMMA - 1) at rho / rho0 = 1.01
  EXPECT_NEAR(evaluate_eos(tait, 1000, 1010, 0).pressure, 22663783.77143915,
              1e-13 * 22663783.77143915);
}

// Without an EOS card, p = K (rho / rho0 - 1) exactly as the elastic SPH solid computes it.
TEST(materials_eos, LinearBulkIsTheElasticPressure) {
  const auto elastic = ElasticConstants::from_young_poisson(7850, 200e9, 0.3);
  Material material;
  material.density = 7850;
  material.shear_modulus = elastic.shear_modulus;
  material.eos = LinearBulk{elastic.bulk_modulus};
  for (const Real rho : {7700.0, 7850.0, 8000.0})
    EXPECT_EQ(eos_pressure(material, rho, 0), elastic_pressure(elastic, rho));
  EXPECT_NEAR(sound_speed(material, 7850, 0), elastic.longitudinal_wave_speed(7850), 1e-9);
}

// c^2 = (dp/drho)_s + 4G/(3 rho): the isentropic derivative by central differences with
// e(rho +- h) = e +- p/rho^2 h; relative error O(h^2) ~ 1e-8.
TEST(materials_eos, SoundSpeedIsTheIsentropicDerivative) {
  struct Case {
    EquationOfState eos;
    Real rho0, shear;
    Real mu, e;
  };
  const Case cases[] = {
      {water, 1000, 0, 0.1, 0},           {water, 1000, 0, -0.02, 3e3},
      {copper, 8960, 46e9, 0.2, 2e5},     {copper, 8960, 46e9, -0.05, 2e5},
      {polynomial, 2700, 26e9, 0.1, 1e5}, {polynomial, 2700, 26e9, -0.1, 1e5},
      {tait, 1000, 0, 0.01, 0},           {LinearBulk{1.7e11}, 2700, 26e9, 0.03, 0},
  };
  for (const auto& c : cases) {
    Material material;
    material.density = c.rho0;
    material.shear_modulus = c.shear;
    material.eos = c.eos;
    const Real rho = c.rho0 * (1 + c.mu);
    const Real p = eos_pressure(material, rho, c.e);
    const Real h = 1e-5 * rho;
    const Real de = p / (rho * rho) * h;
    const Real dp_drho =
        (eos_pressure(material, rho + h, c.e + de) - eos_pressure(material, rho - h, c.e - de)) /
        (2 * h);
    const Real expected = std::sqrt((rho * dp_drho + 4 * c.shear / 3) / rho);
    EXPECT_NEAR(sound_speed(material, rho, c.e), expected, 1e-7 * expected)
        << "EOS " << c.eos.index() << " at mu " << c.mu;
  }
}

// MAT_NULL: pressure from its EOS, cut at PC in tension (PC = 0: no tension); deviator is the
// viscous stress 2 MU dev(D) of the step.
TEST(materials_eos, NullMaterialCutoffAndViscosity) {
  Material material;
  material.density = 1000;
  material.strength = Null{1e-3};
  material.eos = water;
  material.tensile_limit = TensileLimit::pressure_cutoff;
  material.pressure_cutoff = -1e5;
  PointState state = initial_state(material);
  Mat3 d;
  d << 2, 1, 0, 1, -1, 0, 0, 0, 5;
  // Compressed: the EOS pressure; the deviator 2 MU dev(D).
  StressUpdate update = update_stress(material, state, d, 1e-6, 1100, 0);
  EXPECT_NEAR(update.pressure, 279144234.2147553, 1e-13 * 279144234.2147553);
  EXPECT_EQ(update.plastic_work, 0);
  const Mat3 viscous = 2e-3 * (d - d.trace() / 3 * Mat3::Identity());
  EXPECT_NEAR((state.deviatoric_stress - viscous).norm(), 0, 1e-18);
  // Stretched: rho0 C^2 mu = -2.2e7 Pa at mu = -0.01, cut to PC.
  update = update_stress(material, state, d, 1e-6, 990, 0);
  EXPECT_EQ(update.pressure, -1e5);
  material.pressure_cutoff = 0;
  EXPECT_EQ(update_stress(material, state, d, 1e-6, 990, 0).pressure, 0.0);
  EXPECT_FALSE(state.failed);  // a cutoff is not a failure
}

}  // namespace
}  // namespace spall::materials
