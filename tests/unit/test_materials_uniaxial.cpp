// Material-point paths with closed-form answers (validation.md §6; Wilkins 1964; any plasticity
// text, e.g. Simo & Hughes 1998 §1-2): uniaxial stress with linear hardening, loading and
// unloading; uniaxial strain (the Hugoniot elastic limit and reverse yield); the Bauschinger
// effect of kinematic hardening. The pressure is the small-strain p = -K eps_v, so that every
// closed form holds exactly and the tolerances are round-off.
#include <gtest/gtest.h>

#include <cmath>

#include "spall/materials/elastic.hpp"
#include "spall/materials/material.hpp"

namespace spall::materials {
namespace {

// Steel-like constants (SI): E 200 GPa, nu 0.3, SIGY 250 MPa, ETAN 2 GPa.
constexpr Real young = 200e9, poisson = 0.3, yield0 = 250e6, etan = 2e9;
constexpr Real bulk = young / (3 * (1 - 2 * poisson));
constexpr Real shear = young / (2 * (1 + poisson));
constexpr Real hardening = young * etan / (young - etan);  // Ep of MAT_003 / MAT_024

Material plastic_kinematic(Real beta, Real tangent) {
  Material m;
  m.density = 7850;
  m.shear_modulus = shear;
  m.strength = PlasticKinematic{yield0, young * tangent / (young - tangent), beta, {}, 0};
  m.eos = LinearBulk{bulk};
  return m;
}

// The same bilinear curve as MAT_024's SIGY and ETAN make.
Material piecewise_linear() {
  Material m;
  m.density = 7850;
  m.shear_modulus = shear;
  PiecewiseLinear strength;
  strength.curve = HardeningCurve({{0, yield0}, {1, yield0 + hardening}});
  m.strength = strength;
  m.eos = LinearBulk{bulk};
  return m;
}

// Drives one point in uniaxial stress: each step imposes an axial strain increment and finds
// the lateral one that keeps sigma_yy = sigma_zz = S_yy + K eps_v = 0 (secant iteration).
class UniaxialStress {
 public:
  explicit UniaxialStress(Material material) : material_(std::move(material)) {}

  void step(Real axial) {
    Real d0 = -poisson * axial, d1 = -0.5 * axial;
    Real r0 = residual(axial, d0), r1 = residual(axial, d1);
    for (int i = 0; i < 60 && std::abs(r1) > 1e-6; ++i) {  // 1e-6 Pa of 1e8: round-off
      const Real d2 = d1 - r1 * (d1 - d0) / (r1 - r0);
      d0 = d1, r0 = r1;
      d1 = d2, r1 = residual(axial, d1);
    }
    ASSERT_LT(std::abs(r1), 1e-6);
    update(state_, back_stress_, axial, d1);
    strain_ += axial;
    volume_ += axial + 2 * d1;
  }
  Real stress() const { return state_.deviatoric_stress(0, 0) + bulk * volume_; }
  Real strain() const { return strain_; }
  const PointState& state() const { return state_; }

 private:
  void update(PointState& state, Mat3& back_stress, Real axial, Real lateral) const {
    const Mat3 d = Vec3(axial, lateral, lateral).asDiagonal();
    update_deviatoric_stress(material_, state, d, 1.0, material_.density, 0.0,
                             keeps_back_stress(material_) ? &back_stress : nullptr);
  }
  Real residual(Real axial, Real lateral) const {
    PointState trial = state_;
    Mat3 trial_back_stress = back_stress_;
    update(trial, trial_back_stress, axial, lateral);
    return trial.deviatoric_stress(1, 1) + bulk * (volume_ + axial + 2 * lateral);
  }

  Material material_;
  PointState state_;
  Mat3 back_stress_ = Mat3::Zero();  // kept beside the state, as a formulation keeps it
  Real strain_ = 0;
  Real volume_ = 0;
};

// sigma = E eps up to eps_Y = SIGY / E, then SIGY + E H / (E + H) (eps - eps_Y) with
// E H / (E + H) = ETAN; unloading with slope E; residual plastic strain eps_max - sigma_max / E.
void check_uniaxial_stress_load_unload(const Material& material) {
  UniaxialStress point(material);
  const Real eps_yield = yield0 / young;
  const Real step = eps_yield / 50;
  while (point.strain() < 10 * eps_yield - step / 2) {
    point.step(step);
    const Real eps = point.strain();
    const Real expected = eps <= eps_yield ? young * eps : yield0 + etan * (eps - eps_yield);
    ASSERT_NEAR(point.stress(), expected, 1e-9 * yield0) << "loading, eps = " << eps;
  }
  const Real eps_max = point.strain(), sigma_max = point.stress();
  const Real plastic = point.state().plastic_strain;
  EXPECT_NEAR(plastic, eps_max - sigma_max / young, 1e-12);
  // Unload to zero stress: elastic, slope E (the reverse yield at -sigma_max is not reached).
  const Real unload = sigma_max / young;
  for (int i = 0; i < 100; ++i) {
    point.step(-unload / 100);
    ASSERT_NEAR(point.stress(), sigma_max - young * (eps_max - point.strain()), 1e-9 * yield0);
  }
  EXPECT_NEAR(point.stress(), 0, 1e-9 * yield0);
  EXPECT_EQ(point.state().plastic_strain, plastic);
  EXPECT_NEAR(point.strain(), eps_max - sigma_max / young, 1e-15);  // the residual strain
}

TEST(materials_uniaxial, StressPathPlasticKinematicIsotropic) {
  check_uniaxial_stress_load_unload(plastic_kinematic(1.0, etan));
}

TEST(materials_uniaxial, StressPathPiecewiseLinear) {
  check_uniaxial_stress_load_unload(piecewise_linear());
}

// Uniaxial strain (a plane wave): elastic sigma_xx = (K + 4G/3) eps; yield at eps_Y = SIGY / (2G)
// with the Hugoniot elastic limit SIGY (1 - nu) / (1 - 2 nu); then (perfect plasticity)
// sigma_xx = K eps + 2/3 SIGY, slope K; unloading with slope K + 4G/3 until reverse yield after a
// strain change of 2 eps_Y, then sigma_xx = K eps - 2/3 SIGY.
TEST(materials_uniaxial, StrainPathHugoniotElasticLimitAndReverseYield) {
  const Material material = plastic_kinematic(1.0, 0.0);
  PointState state;
  Real eps = 0;
  const auto step = [&](Real increment) {
    const Mat3 d = Vec3(increment, 0, 0).asDiagonal();
    update_deviatoric_stress(material, state, d, 1.0, material.density, 0.0);
    eps += increment;
    return state.deviatoric_stress(0, 0) + bulk * eps;  // sigma_xx, p = -K eps
  };
  const Real eps_yield = yield0 / (2 * shear);
  const Real longitudinal = bulk + 4 * shear / 3;
  // Up to just below eps_Y: elastic.
  Real sigma = step(eps_yield * (1 - 1e-9));
  EXPECT_NEAR(sigma, longitudinal * eps, 1e-9 * yield0);
  EXPECT_EQ(state.plastic_strain, 0);
  EXPECT_NEAR(sigma, yield0 * (1 - poisson) / (1 - 2 * poisson), 1e-6 * yield0);  // HEL
  // Beyond: perfectly plastic, slope K.
  for (int i = 0; i < 100; ++i) {
    sigma = step(eps_yield / 20);
    ASSERT_NEAR(sigma, bulk * eps + 2 * yield0 / 3, 1e-9 * yield0);
  }
  EXPECT_GT(state.plastic_strain, 0);
  // Unload by just under 2 eps_Y: elastic, slope K + 4G/3.
  const Real eps_max = eps, sigma_max = sigma, plastic = state.plastic_strain;
  sigma = step(-2 * eps_yield * (1 - 1e-9));
  EXPECT_NEAR(sigma, sigma_max - longitudinal * (eps_max - eps), 1e-9 * yield0);
  EXPECT_EQ(state.plastic_strain, plastic);
  // Further: reverse yield, on the compression-side surface sigma_xx = K eps - 2/3 SIGY.
  for (int i = 0; i < 20; ++i) sigma = step(-eps_yield / 20);
  EXPECT_NEAR(sigma, bulk * eps - 2 * yield0 / 3, 1e-9 * yield0);
  EXPECT_GT(state.plastic_strain, plastic);
}

// Linear kinematic hardening (BETA = 0) keeps an elastic range of 2 SIGY: after loading to
// sigma_max in tension, reverse yield comes at sigma_max - 2 SIGY (Bauschinger effect; Prager
// 1956). Isotropic hardening (BETA = 1) grows the range to 2 sigma_max: no reverse yield until
// -sigma_max.
TEST(materials_uniaxial, KinematicHardeningReverseYieldsAtSigmaMaxMinusTwoSigmaY) {
  for (const Real beta : {0.0, 1.0}) {
    UniaxialStress point(plastic_kinematic(beta, etan));
    const Real eps_yield = yield0 / young;
    for (int i = 0; i < 200; ++i) point.step(eps_yield / 20);  // to 10 eps_Y
    const Real eps_max = point.strain(), sigma_max = point.stress();
    ASSERT_NEAR(sigma_max, yield0 + etan * (eps_max - eps_yield), 1e-9 * yield0);
    const Real plastic = point.state().plastic_strain;
    const Real elastic_range = beta == 0 ? 2 * yield0 : 2 * sigma_max;
    // Unload elastically to just inside the reverse yield stress.
    point.step(-(elastic_range / young) * (1 - 1e-9));
    EXPECT_NEAR(point.stress(), sigma_max - elastic_range, 1e-6 * yield0) << "beta " << beta;
    EXPECT_EQ(point.state().plastic_strain, plastic) << "beta " << beta;
    // A further strain de reverse-yields: sigma = sigma_max - range - ETAN de.
    const Real further = 2 * eps_yield;
    for (int i = 0; i < 40; ++i) point.step(-further / 40);
    EXPECT_NEAR(point.stress(), sigma_max - elastic_range - etan * further, 1e-6 * yield0)
        << "beta " << beta;
    EXPECT_GT(point.state().plastic_strain, plastic) << "beta " << beta;
  }
}

}  // namespace
}  // namespace spall::materials
