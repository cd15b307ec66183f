// *MAT_JOHNSON_COOK (015) against closed forms (Johnson & Cook 1983, 1985; LS-DYNA keyword
// manual), with the OFHC copper constants of validation.md §1(b): A 90 MPa, B 292 MPa, N 0.31,
// C 0.025, M 1.09, TM 1356 K, TR 298 K, EPSO 1 /s, rho 8960 kg/m^3, CP 383 J/(kg K).
#include <gtest/gtest.h>

#include <cmath>

#include "spall/materials/elastic.hpp"
#include "spall/materials/material.hpp"

namespace spall::materials {
namespace {

constexpr Real density = 8960, shear = 46.3e9;  // G = E / (2 (1 + nu)), E 124 GPa, nu 0.34

JohnsonCook ofhc_copper() {
  JohnsonCook jc;
  jc.a = 90e6, jc.b = 292e6, jc.n = 0.31, jc.c = 0.025, jc.m = 1.09;
  jc.melt_temperature = 1356, jc.room_temperature = 298, jc.reference_rate = 1.0;
  jc.heat_capacity = 383;
  return jc;
}

Material material_of(const JohnsonCook& jc) {
  Material m;
  m.density = density;
  m.shear_modulus = shear;
  m.strength = jc;
  m.eos = LinearBulk{124e9 / (3 * (1 - 2 * 0.34))};
  m.tensile_limit = TensileLimit::principal_stress;
  m.pressure_cutoff = -1.2e9;
  m.initial_temperature = jc.room_temperature;
  return m;
}

// Simple shear gamma per step: D = gamma/2 (e1 e2 + e2 e1), effective strain rate gamma / sqrt(3).
Mat3 shear_rate(Real gamma) {
  Mat3 d = Mat3::Zero();
  d(0, 1) = d(1, 0) = gamma / 2;
  return d;
}

// sigma_y = (A + B eps^N)(1 + C ln rate*)(1 - T*^M), evaluated outside the library (Python,
// double precision) at three states.
TEST(materials_johnson_cook, FlowStressValues) {
  const JohnsonCook jc = ofhc_copper();
  EXPECT_DOUBLE_EQ(johnson_cook_flow_stress(jc, 0.0, 1.0, 298), 90e6);
  // eps 0.5, rate 1000 /s, T = TR
  EXPECT_NEAR(johnson_cook_flow_stress(jc, 0.5, 1000, 298), 381758055.32532346, 1e-6);
  // eps 0.2, rate at EPSO, 600 K
  EXPECT_NEAR(johnson_cook_flow_stress(jc, 0.2, 1.0, 600), 199139948.28925827, 1e-6);
  // eps 0.1, rate 2000 /s, 500 K
  EXPECT_NEAR(johnson_cook_flow_stress(jc, 0.1, 2000, 500), 231681144.73729566, 1e-6);
  // Below EPSO the rate term is floored at ln 1 = 0 (stated choice); at and above TM no strength.
  EXPECT_EQ(johnson_cook_flow_stress(jc, 0.2, 0.01, 600),
            johnson_cook_flow_stress(jc, 0.2, 1.0, 600));
  EXPECT_EQ(johnson_cook_flow_stress(jc, 0.2, 1.0, 1400), 0.0);
}

// eps_f = [D1 + D2 exp(D3 sigma*)][1 + D4 ln rate*][1 + D5 T*] with the OFHC copper damage
// constants D1..D5 = 0.54, 4.89, -3.03, 0.014, 1.12 (Johnson & Cook 1985) [memory], evaluated in
// Python.
TEST(materials_johnson_cook, FailureStrainValues) {
  JohnsonCook jc = ofhc_copper();
  jc.d1 = 0.54, jc.d2 = 4.89, jc.d3 = -3.03, jc.d4 = 0.014, jc.d5 = 1.12;
  // uniaxial tension sigma* = 1/3, rate at EPSO, T = TR
  EXPECT_NEAR(johnson_cook_failure_strain(jc, 1.0 / 3, 1.0, 298), 2.321030810104749, 1e-14);
  // compression sigma* = -1, 1000 /s, 600 K
  EXPECT_NEAR(johnson_cook_failure_strain(jc, -1.0, 1000, 600), 147.26440640370302, 1e-11);
  // EFMIN bounds it from below
  jc.min_failure_strain = 3.0;
  EXPECT_EQ(johnson_cook_failure_strain(jc, 1.0 / 3, 1.0, 298), 3.0);
}

// With B = C = 0 and M = 1 the flow stress is A (1 - T*), and adiabatic heating
// rho CP dT = sigma_y d(eps_p) integrates to T* = 1 - exp(-k eps_p), k = A / (rho CP (TM - TR)).
// The library heats with the temperature of the start of each step (explicit in T), which gives
// 1 - T* = (1 - k h)^(eps_p / h) for steps h = d(eps_p): an error eps_p k^2 h / 2 = 6e-7 in T*
// (1.3e-5 of T* = 0.048) at eps_p = 2, h = 1e-3.
TEST(materials_johnson_cook, AdiabaticHeatingFollowsTheClosedForm) {
  JohnsonCook jc = ofhc_copper();
  jc.b = 0, jc.c = 0, jc.m = 1;
  const Material material = material_of(jc);
  PointState state = initial_state(material);
  EXPECT_EQ(state.temperature, 298);
  Real work = 0;
  for (int i = 0; i < 2000; ++i)
    work += update_deviatoric_stress(material, state, shear_rate(std::sqrt(3.0) * 1e-3), 1.0,
                                     density, 0.0);
  const Real k = 90e6 / (density * 383 * (1356 - 298));
  const Real t_star = 1 - std::exp(-k * state.plastic_strain);
  EXPECT_NEAR(state.plastic_strain, 2.0, 0.01);
  EXPECT_NEAR((state.temperature - 298) / (1356 - 298), t_star, 2e-5 * t_star);
  // The last step's stress used the temperature before its own heating, k d(eps_p) = 2.5e-5 lower.
  EXPECT_NEAR(von_mises(state.deviatoric_stress), 90e6 * (1 - t_star), 4e-5 * 90e6);
  // All the plastic work became heat.
  EXPECT_NEAR(state.temperature - 298, work / (density * 383), 1e-9);
}

// D = sum d(eps_p) / eps_f; at D = 1 the point fails: no deviatoric stress and no tension.
// B = C = 0 and no heating keep sigma_eq = A, so a pressure p = -A/3 holds the triaxiality at
// sigma* = 1/3 and eps_f = 2.321030810104749 (FailureStrainValues).
TEST(materials_johnson_cook, DamageReachesFailureAtTheFailureStrain) {
  JohnsonCook jc = ofhc_copper();
  jc.b = 0, jc.c = 0;
  jc.heat_capacity = 1e30;  // no heating: sigma_eq stays A
  jc.d1 = 0.54, jc.d2 = 4.89, jc.d3 = -3.03, jc.d4 = 0.014, jc.d5 = 1.12;
  const Material material = material_of(jc);
  const Real failure_strain = 2.321030810104749;
  PointState state = initial_state(material);
  int steps = 0;
  while (!state.failed && steps < 10000) {
    update_deviatoric_stress(material, state, shear_rate(std::sqrt(3.0) * 1e-3), 1.0, density,
                             -30e6);
    ++steps;
    if (!state.failed) {
      ASSERT_NEAR(state.damage, state.plastic_strain / failure_strain, 1e-12);
      ASSERT_LT(state.plastic_strain, failure_strain);
    }
  }
  ASSERT_TRUE(state.failed);
  EXPECT_GE(state.plastic_strain, failure_strain);
  EXPECT_LT(state.plastic_strain, failure_strain + 1.1e-3);  // within the step that crossed it
  EXPECT_EQ(state.deviatoric_stress, Mat3::Zero());
  // Failed: tension is cut to 0, compression stays; further straining builds no stress.
  EXPECT_EQ(apply_tensile_limit(material, state, -5e8), 0.0);
  EXPECT_EQ(apply_tensile_limit(material, state, 5e8), 5e8);
  update_deviatoric_stress(material, state, shear_rate(1e-2), 1.0, density, 0.0);
  EXPECT_EQ(state.deviatoric_stress, Mat3::Zero());
}

// SPALL 1: p >= PC. SPALL 2: spall when the largest principal stress reaches -PC. SPALL 3: spall
// when p <= PC. A spalled point keeps no deviator and no tension (LS-DYNA keyword manual,
// *MAT_JOHNSON_COOK SPALL; as in its *MAT_ELASTIC_PLASTIC_HYDRO spall models).
TEST(materials_johnson_cook, SpallModels) {
  Material material = material_of(ofhc_copper());
  const Real pc = material.pressure_cutoff;  // -1.2 GPa
  // Uniaxial deviator: sigma_1 = 0.6 GPa - p. With p = -0.7 GPa: sigma_1 = 1.3 GPa > -PC but p >
  // PC.
  PointState loaded;
  loaded.deviatoric_stress = Vec3(2, -1, -1).asDiagonal();
  loaded.deviatoric_stress *= 0.3e9;

  material.tensile_limit = TensileLimit::pressure_cutoff;
  PointState state = loaded;
  EXPECT_EQ(apply_tensile_limit(material, state, -2e9), pc);
  EXPECT_EQ(apply_tensile_limit(material, state, -0.7e9), -0.7e9);
  EXPECT_FALSE(state.failed);

  material.tensile_limit = TensileLimit::principal_stress;
  state = loaded;
  EXPECT_EQ(apply_tensile_limit(material, state, -0.5e9), -0.5e9);  // sigma_1 = 1.1 GPa
  EXPECT_FALSE(state.failed);
  EXPECT_EQ(apply_tensile_limit(material, state, -0.7e9), 0.0);  // sigma_1 = 1.3 GPa: spalls
  EXPECT_TRUE(state.failed);
  EXPECT_EQ(state.deviatoric_stress, Mat3::Zero());

  material.tensile_limit = TensileLimit::hydrostatic_tension;
  state = loaded;
  EXPECT_EQ(apply_tensile_limit(material, state, -0.7e9), -0.7e9);
  EXPECT_FALSE(state.failed);
  EXPECT_EQ(apply_tensile_limit(material, state, -1.3e9), 0.0);
  EXPECT_TRUE(state.failed);
}

}  // namespace
}  // namespace spall::materials
